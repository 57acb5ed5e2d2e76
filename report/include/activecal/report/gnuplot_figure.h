// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// PNG figures drawn by gnuplot (the programs' --plot, --selection_plot and
// the paper's figures): a script in, the PNG's bytes out. The caller decides
// where they go (the programs add them to their set of outputs, written
// together at the end).

#ifndef ACTIVECAL_REPORT_GNUPLOT_FIGURE_H_
#define ACTIVECAL_REPORT_GNUPLOT_FIGURE_H_

#include <string>
#include <vector>

#include "activecal/io/output_files.h"

namespace activecal {

// Whether a gnuplot is on the PATH.
bool GnuplotAvailable();

// A gnuplot data block "$name << EOD ... EOD" of `rows` (17 digits), for the
// script to plot from.
std::string GnuplotDataBlock(const std::string& name,
                             const std::vector<std::vector<double>>& rows);

// Draws `script` (after "set terminal pngcairo size 1000,650" and "set
// output") into `*png`, the figure meant for `png_path`. gnuplot writes it
// to png_path's temporary name (io's TemporaryPath), removed again; nothing
// is written at png_path. A path with quotes is refused, an unwritable
// folder named. On failure, false with gnuplot's first line of error.
bool RenderGnuplotPng(const std::string& script, const std::string& png_path,
                      std::string* png, std::string* error);

// The figure of a program's option (`option`, e.g. "--plot"): with gnuplot
// installed, `script` drawn (RenderGnuplotPng) into *png = {png_path, the
// PNG's bytes} and *note "  <option>: wrote <png_path>\n"; without, *png
// left empty (no path) and *note "  <option>: gnuplot is not installed; no
// plot\n". False with *error "<option>: <why>" (gnuplot's error, or
// "cannot write '<png_path>': it is a directory", as an output set says).
bool MakeGnuplotFigure(const std::string& script, const std::string& png_path,
                       const std::string& option, OutputFile* png,
                       std::string* note, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_REPORT_GNUPLOT_FIGURE_H_
