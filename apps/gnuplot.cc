// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "gnuplot.h"

#include <cstdio>

#include "activecal/report/gnuplot_figure.h"
#include "app_common.h"

namespace activecal {
namespace app {

std::string GnuplotData(const std::string& name,
                        const std::vector<std::vector<double>>& rows) {
  return GnuplotDataBlock(name, rows);
}

bool RunGnuplot(const std::string& script, const std::string& png_path,
                std::string* error) {
  // The figure joins the program's outputs (app_common.h): renamed over
  // png_path with the others at the end, removed if the program fails.
  std::string png;
  return RenderGnuplotPng(script, png_path, &png, error) &&
         AddOutput(png_path, png, error);
}

void PlotOrNote(const std::string& script, const std::string& png_path,
                const std::string& flag) {
  if (!GnuplotAvailable()) {
    std::printf("  --%s: gnuplot is not installed; no plot\n", flag.c_str());
    return;
  }
  std::string error;
  if (!RunGnuplot(script, png_path, &error)) Fail("--" + flag + ": " + error);
  std::printf("  --%s: wrote %s\n", flag.c_str(), png_path.c_str());
}

}  // namespace app
}  // namespace activecal
