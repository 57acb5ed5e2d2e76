// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/report/gnuplot_figure.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "activecal/io/output_files.h"

namespace activecal {
namespace {

TEST(GnuplotFigureTest, DataBlockHoldsEveryRowAtFullPrecision) {
  EXPECT_EQ(GnuplotDataBlock("curve", {{1, 0.1}, {2, 1.0 / 3.0}}),
            "$curve << EOD\n1 0.10000000000000001\n"
            "2 0.33333333333333331\nEOD\n");
  EXPECT_EQ(GnuplotDataBlock("empty", {}), "$empty << EOD\nEOD\n");
}

TEST(GnuplotFigureTest, PathsWithQuotesOrNoFolderAreRefusedByName) {
  std::string png, error;
  EXPECT_FALSE(RenderGnuplotPng("plot x", "a'b.png", &png, &error));
  EXPECT_EQ(error, "the plot path must not contain quotes: a'b.png");
  EXPECT_FALSE(
      RenderGnuplotPng("plot x", "/no/such/folder/f.png", &png, &error));
  EXPECT_EQ(error, "cannot write /no/such/folder/f.png");
}

TEST(GnuplotFigureTest, RendersAPngAndLeavesNoFileBehind) {
  if (!GnuplotAvailable()) GTEST_SKIP() << "gnuplot is not installed";
  const std::string path = ::testing::TempDir() + "gnuplot_figure_test.png";
  std::string png, error;
  ASSERT_TRUE(RenderGnuplotPng(
      GnuplotDataBlock("d", {{0, 0}, {1, 1}}) + "plot $d with lines", path,
      &png, &error))
      << error;
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_NE(access(path.c_str(), F_OK), 0);  // the caller writes it
  EXPECT_NE(access(TemporaryPath(path).c_str(), F_OK), 0);
  EXPECT_NE(access((path + ".gnuplot.log").c_str(), F_OK), 0);
  // A script gnuplot refuses: its first line of error, no figure.
  EXPECT_FALSE(
      RenderGnuplotPng("plot no_such_function(x)", path, &png, &error));
  EXPECT_EQ(error.rfind("gnuplot failed", 0), 0u) << error;
  EXPECT_NE(access(TemporaryPath(path).c_str(), F_OK), 0);
}

}  // namespace
}  // namespace activecal
