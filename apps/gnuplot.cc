// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "gnuplot.h"

#include <cstdio>

#include "activecal/report/gnuplot_figure.h"
#include "app_common.h"

namespace activecal {
namespace app {

void PlotOrNote(const std::string& script, const std::string& png_path,
                const std::string& flag) {
  OutputFile png;
  std::string note, error;
  if (!MakeGnuplotFigure(script, png_path, "--" + flag, &png, &note, &error)) {
    Fail(error);
  }
  // The figure joins the program's outputs (app_common.h): renamed over
  // png_path with the others at the end, removed if the program fails.
  if (!png.path.empty() && !AddOutput(png.path, png.text, &error)) {
    Fail("--" + flag + ": " + error);
  }
  std::printf("%s", note.c_str());
}

}  // namespace app
}  // namespace activecal
