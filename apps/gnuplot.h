// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Drawing a figure with gnuplot from a program (not part of the library):
// the script, with its data inline, is piped to gnuplot. Programs skip the
// figure with a note when gnuplot is not installed.

#ifndef ACTIVECAL_APPS_GNUPLOT_H_
#define ACTIVECAL_APPS_GNUPLOT_H_

#include <string>
#include <vector>

#include "activecal/report/gnuplot_figure.h"

namespace activecal {
namespace app {

// True when a gnuplot executable is on the PATH.
using ::activecal::GnuplotAvailable;

// Inline data block for a script: "$name << EOD\n<rows>\nEOD\n", each row
// its values separated by spaces.
std::string GnuplotData(const std::string& name,
                        const std::vector<std::vector<double>>& rows);

// Runs `script` through gnuplot (PNG terminal and output set before it)
// and adds the figure to the program's outputs (AddOutput, app_common.h:
// written to `png_path` with the others when the program ends well, not at
// all when it fails). False with *error (gnuplot's first line) on failure.
bool RunGnuplot(const std::string& script, const std::string& png_path,
                std::string* error);

// Draws `script` to --<flag>=png_path and prints "  --<flag>: wrote
// <path>", or "  --<flag>: gnuplot is not installed; no plot"; dies with
// "--<flag>: <gnuplot's error>".
void PlotOrNote(const std::string& script, const std::string& png_path,
                const std::string& flag);

}  // namespace app
}  // namespace activecal

#endif  // ACTIVECAL_APPS_GNUPLOT_H_
