// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The report's figures as SVG text (no script, no external resource): a
// histogram of error magnitudes on logarithmic bins, a curve with error
// bars, a matrix as a heat map with its row and column names. Each figure
// is one <svg> element whose class names what it shows ("histogram",
// "curve", "heatmap"); its bars, points and cells carry data-value
// attributes with the numbers drawn, so that a test can read them back.

#ifndef ACTIVECAL_REPORT_SVG_FIGURES_H_
#define ACTIVECAL_REPORT_SVG_FIGURES_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace activecal {

// Logarithmic bins: num_bins + 1 edges from lo to hi (> lo > 0), equal
// steps in log10. lo and hi are the smallest and largest positive values
// of all `values` widened by 1 %; values <= 0 fall into the first bin.
std::vector<double> LogBinEdges(const std::vector<std::vector<double>>& values,
                                int num_bins);
// How many of `values` fall into each bin of `edges` (the last bin
// includes its upper edge; values below the first edge count in the first
// bin, above the last in the last).
std::vector<int> BinCounts(const std::vector<double>& values,
                           const std::vector<double>& edges);

struct HistogramSeries {
  std::string label;  // e.g. "before (registration only)"
  std::vector<double> values;
  std::string color;  // CSS colour
};

// Side-by-side bars of each series on the same log bins (num_bins), x axis
// labelled `unit` on a log scale, y the count. Each bar: <rect
// class="bar" data-series="k" data-bin="b" data-value="count">.
std::string SvgHistogram(const std::vector<HistogramSeries>& series,
                         int num_bins, const std::string& unit,
                         const std::string& title);

struct CurveSeries {
  std::string label;
  std::vector<double> x, y, error;  // error: +- bar (empty: none)
  std::string color;
};

// Lines with points (and error bars), linear axes; `marked_x` draws a
// vertical line at that x (NaN: none). Each point: <circle class="point"
// data-series="k" data-x=".." data-value="y">.
std::string SvgCurve(const std::vector<CurveSeries>& series,
                     const std::string& x_label, const std::string& y_label,
                     double marked_x, const std::string& title);

// A square matrix (e.g. correlations in [-1, 1]) as coloured cells, blue
// for -1 through white to red for +1, with `names` beside the rows and
// above the columns. Each cell: <rect class="cell" data-row="i"
// data-col="j" data-value="v">.
std::string SvgHeatmap(const Eigen::MatrixXd& matrix,
                       const std::vector<std::string>& names,
                       const std::string& title);

// Text safe inside HTML and SVG elements and attributes (& < > " ').
std::string HtmlEscape(const std::string& text);

// A table cell of a number: `shown` (e.g. millimetres) with 3 decimals, a
// value that rounds to zero without its sign and "-" for one that is not
// finite; the SI value `si` in full in data-value, named by data-key:
// <td class="num" data-key="key" data-value="si">shown</td>.
std::string HtmlNumberCell(const std::string& key, double si, double shown);

}  // namespace activecal

#endif  // ACTIVECAL_REPORT_SVG_FIGURES_H_
