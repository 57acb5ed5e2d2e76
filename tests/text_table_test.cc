// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The printed tables (core/text_table.h): columns as wide as their widest
// cell, text left and numbers right, no trailing spaces.

#include "activecal/core/text_table.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace activecal {
namespace {

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(TextTableTest, ALongNameWidensItsColumnAndKeepsTheOthersInLine) {
  TextTable table({{"parameter"}, {"unit"}, {"estimate", ColumnAlign::kRight}});
  table.AddRow({"B.x", "m", FormatNumber("%.6f", -0.006009)});
  table.AddRow(
      {"shoulder_lift_joint.offset", "rad", FormatNumber("%.6f", 0.0123456)});
  EXPECT_EQ(table.Width(0), 26);  // the widest name, not the header
  EXPECT_EQ(table.Width(1), 4);   // the header
  EXPECT_EQ(table.Width(2), 9);   // "-0.006009"
  const std::vector<std::string> lines = Lines(table.ToString(2));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "  parameter                   unit   estimate");
  EXPECT_EQ(lines[1], "  B.x                         m     -0.006009");
  EXPECT_EQ(lines[2], "  shoulder_lift_joint.offset  rad    0.012346");
  // Right-aligned numbers end in one column.
  for (const std::string& line : lines) EXPECT_EQ(line.size(), lines[0].size());
}

TEST(TextTableTest, NoTrailingSpacesAfterAShortLastTextCell) {
  TextTable table({{"kept", ColumnAlign::kRight}, {"mark"}});
  table.AddRow({"12", ""});
  table.AddRow({"13", "<- kept"});
  EXPECT_EQ(table.ToString(), "kept  mark\n  12\n  13  <- kept\n");
  EXPECT_EQ(table.num_rows(), 2);
}

TEST(TextTableTest, HeaderOnlyAndIndent) {
  TextTable table({{"a"}, {"bb", ColumnAlign::kRight}});
  EXPECT_EQ(table.ToString(4), "    a  bb\n");
}

TEST(TextTableTest, FormatNumberIsOnePrintfConversion) {
  EXPECT_EQ(FormatNumber("%.3f", 3.26864), "3.269");
  EXPECT_EQ(FormatNumber("%.2g", 0.6478), "0.65");
  EXPECT_EQ(FormatNumber("%12.6f", 1.0), "    1.000000");
}

TEST(TextTableDeathTest, ARowWithTheWrongCellCountIsAProgrammerError) {
  TextTable table({{"a"}, {"b"}});
  EXPECT_DEATH(table.AddRow({"only one"}), "one cell per column");
}

}  // namespace
}  // namespace activecal
