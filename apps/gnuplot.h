// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Drawing a figure with gnuplot from a program (not part of the library):
// the script, with its data inline, is piped to gnuplot. Programs skip the
// figure with a note when gnuplot is not installed.

#ifndef ACTIVECAL_APPS_GNUPLOT_H_
#define ACTIVECAL_APPS_GNUPLOT_H_

#include <string>

#include "activecal/report/gnuplot_figure.h"

namespace activecal {
namespace app {

// Draws `script` to --<flag>=png_path (MakeGnuplotFigure), the figure added
// to the program's outputs (WriteTextOrDie, app_common.h: written with the
// others when the program ends well, not at all when it fails), and prints
// "  --<flag>: wrote <path>", or "  --<flag>: gnuplot is not installed; no
// plot"; dies with "--<flag>: <gnuplot's error>".
void PlotOrNote(const std::string& script, const std::string& png_path,
                const std::string& flag);

}  // namespace app
}  // namespace activecal

#endif  // ACTIVECAL_APPS_GNUPLOT_H_
