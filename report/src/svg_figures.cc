// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/report/svg_figures.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "activecal/core/text_table.h"
#include "activecal/io/xml_text.h"

namespace activecal {
namespace {

// A number as an attribute value: enough digits to read it back exactly.
std::string Num(double v) { return FormatNumber("%.17g", v); }
std::string Px(double v) { return FormatNumber("%.2f", v); }

// Tick label: 3 significant digits, no trailing zeros.
std::string Tick(double v) { return FormatNumber("%.3g", v); }

constexpr double kWidth = 640, kHeight = 300;
constexpr double kLeft = 60, kRight = 20, kTop = 30, kBottom = 50;

std::string Open(const std::string& css_class, double width, double height,
                 const std::string& title) {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"" + css_class +
         "\" width=\"" + Px(width) + "\" height=\"" + Px(height) +
         "\" viewBox=\"0 0 " + Px(width) + " " + Px(height) +
         "\" role=\"img\" font-family=\"sans-serif\" font-size=\"11\">\n"
         "<title>" +
         HtmlEscape(title) + "</title>\n<text x=\"" + Px(width / 2) +
         "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\">" +
         HtmlEscape(title) + "</text>\n";
}

std::string Text(double x, double y, const std::string& text,
                 const std::string& anchor, const std::string& extra = "") {
  return "<text x=\"" + Px(x) + "\" y=\"" + Px(y) + "\" text-anchor=\"" +
         anchor + "\"" + extra + ">" + HtmlEscape(text) + "</text>\n";
}

std::string Line(double x1, double y1, double x2, double y2,
                 const std::string& style) {
  return "<line x1=\"" + Px(x1) + "\" y1=\"" + Px(y1) + "\" x2=\"" + Px(x2) +
         "\" y2=\"" + Px(y2) + "\" " + style + "/>\n";
}

std::string Legend(const std::vector<std::pair<std::string, std::string>>& s,
                   double x, double y) {
  std::string out;
  for (size_t k = 0; k < s.size(); ++k) {
    const double yk = y + 14 * k;
    out += "<rect x=\"" + Px(x) + "\" y=\"" + Px(yk - 9) +
           "\" width=\"10\" height=\"10\" fill=\"" + s[k].second + "\"/>\n";
    out += Text(x + 14, yk, s[k].first, "start");
  }
  return out;
}

// Round numbers for a linear axis from lo to hi.
std::vector<double> LinearTicks(double lo, double hi) {
  const double span = hi - lo;
  if (!(span > 0)) return {lo};
  const double raw = span / 5;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * power;
    if (step >= raw) break;
  }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * span;
       t += step) {
    ticks.push_back(std::abs(t) < 1e-12 * span ? 0.0 : t);
  }
  return ticks;
}

}  // namespace

std::string HtmlEscape(const std::string& text) {
  return EscapeXmlText(text, XmlApostrophe::kNumeric);
}

std::string HtmlNumberCell(const std::string& key, double si, double shown) {
  std::string text = std::isfinite(shown) ? FormatNumber("%.3f", shown) : "-";
  if (text == "-0.000") text = "0.000";
  return "<td class=\"num\" data-key=\"" + HtmlEscape(key) +
         "\" data-value=\"" + FormatNumber("%.17g", si) + "\">" + text +
         "</td>";
}

std::vector<double> LogBinEdges(const std::vector<std::vector<double>>& values,
                                int num_bins) {
  CHECK_GT(num_bins, 0);
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (const std::vector<double>& v : values) {
    for (double x : v) {
      if (x > 0 && std::isfinite(x)) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
    }
  }
  if (!(hi > 0)) lo = hi = 1.0;  // nothing positive: one decade around 1
  lo /= 1.01;
  hi *= 1.01;
  if (hi / lo < 10) {  // at least a decade, centred
    const double widen = std::sqrt(10 / (hi / lo));
    lo /= widen;
    hi *= widen;
  }
  std::vector<double> edges(num_bins + 1);
  const double a = std::log10(lo), b = std::log10(hi);
  for (int k = 0; k <= num_bins; ++k) {
    edges[k] = std::pow(10.0, a + (b - a) * k / num_bins);
  }
  return edges;
}

std::vector<int> BinCounts(const std::vector<double>& values,
                           const std::vector<double>& edges) {
  CHECK_GE(edges.size(), 2u);
  const int bins = static_cast<int>(edges.size()) - 1;
  std::vector<int> counts(bins, 0);
  for (double x : values) {
    // The first edge above x, minus one: its bin.
    int b = static_cast<int>(std::upper_bound(edges.begin(), edges.end(), x) -
                             edges.begin()) -
            1;
    counts[std::clamp(b, 0, bins - 1)]++;
  }
  return counts;
}

std::string SvgHistogram(const std::vector<HistogramSeries>& series,
                         int num_bins, const std::string& unit,
                         const std::string& title) {
  std::vector<std::vector<double>> all;
  for (const HistogramSeries& s : series) all.push_back(s.values);
  const std::vector<double> edges = LogBinEdges(all, num_bins);
  std::vector<std::vector<int>> counts;
  int top = 1;
  for (const HistogramSeries& s : series) {
    counts.push_back(BinCounts(s.values, edges));
    top = std::max(
        top, *std::max_element(counts.back().begin(), counts.back().end()));
  }
  const double w = kWidth - kLeft - kRight, h = kHeight - kTop - kBottom;
  const double x0 = kLeft, y0 = kTop + h;
  const double la = std::log10(edges.front()), lb = std::log10(edges.back());
  auto x_of = [&](double v) {
    return x0 + w * (std::log10(v) - la) / (lb - la);
  };
  auto y_of = [&](double c) { return y0 - h * c / top; };
  std::string svg = Open("histogram", kWidth, kHeight, title);
  // Axes.
  svg += Line(x0, y0, x0 + w, y0, "stroke=\"black\"");
  svg += Line(x0, y0, x0, kTop, "stroke=\"black\"");
  for (double t : LinearTicks(0, top)) {
    if (t != std::floor(t)) continue;
    svg += Line(x0 - 4, y_of(t), x0, y_of(t), "stroke=\"black\"");
    svg += Text(x0 - 6, y_of(t) + 4, Tick(t), "end");
  }
  for (int d = static_cast<int>(std::ceil(la - 1e-9));
       d <= static_cast<int>(std::floor(lb + 1e-9)); ++d) {
    for (int m = 1; m <= 9; ++m) {
      const double v = m * std::pow(10.0, d);
      if (v < edges.front() || v > edges.back()) continue;
      svg +=
          Line(x_of(v), y0, x_of(v), y0 + (m == 1 ? 6 : 3), "stroke=\"black\"");
      if (m == 1 || m == 2 || m == 5) {
        svg += Text(x_of(v), y0 + 18, Tick(v), "middle");
      }
    }
  }
  svg += Text(x0 + w / 2, kHeight - 10, unit + " (log scale)", "middle");
  svg += Text(14, kTop + h / 2, "count", "middle",
              " transform=\"rotate(-90 14 " + Px(kTop + h / 2) + ")\"");
  const int n = std::max<int>(1, static_cast<int>(series.size()));
  for (size_t k = 0; k < series.size(); ++k) {
    for (int b = 0; b < num_bins; ++b) {
      const double left = x_of(edges[b]), right = x_of(edges[b + 1]);
      const double bw = (right - left) / n;
      const int c = counts[k][b];
      svg += "<rect class=\"bar\" data-series=\"" + std::to_string(k) +
             "\" data-bin=\"" + std::to_string(b) + "\" data-low=\"" +
             Num(edges[b]) + "\" data-high=\"" + Num(edges[b + 1]) +
             "\" data-value=\"" + std::to_string(c) + "\" x=\"" +
             Px(left + bw * k) + "\" y=\"" + Px(y_of(c)) + "\" width=\"" +
             Px(std::max(0.5, bw - 0.5)) + "\" height=\"" + Px(y0 - y_of(c)) +
             "\" fill=\"" + series[k].color + "\"/>\n";
    }
  }
  std::vector<std::pair<std::string, std::string>> legend;
  for (const HistogramSeries& s : series) {
    legend.push_back(
        {s.label + " (" + std::to_string(s.values.size()) + ")", s.color});
  }
  svg += Legend(legend, x0 + w - 220, kTop + 10);
  return svg + "</svg>\n";
}

std::string SvgCurve(const std::vector<CurveSeries>& series,
                     const std::string& x_label, const std::string& y_label,
                     double marked_x, const std::string& title) {
  double xl = std::numeric_limits<double>::infinity(), xh = -xl;
  double yl = xl, yh = -xl;
  for (const CurveSeries& s : series) {
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.y[i])) continue;
      const double e = s.error.empty() ? 0.0 : s.error[i];
      xl = std::min(xl, s.x[i]);
      xh = std::max(xh, s.x[i]);
      yl = std::min(yl, s.y[i] - e);
      yh = std::max(yh, s.y[i] + e);
    }
  }
  if (!std::isfinite(xl)) xl = 0, xh = 1, yl = 0, yh = 1;
  if (!(xh > xl)) xh = xl + 1;
  if (!(yh > yl)) yh = yl + 1;
  const double pad = 0.05 * (yh - yl);
  yl -= pad;
  yh += pad;
  const double w = kWidth - kLeft - kRight, h = kHeight - kTop - kBottom;
  const double x0 = kLeft, y0 = kTop + h;
  auto x_of = [&](double v) { return x0 + w * (v - xl) / (xh - xl); };
  auto y_of = [&](double v) { return y0 - h * (v - yl) / (yh - yl); };
  std::string svg = Open("curve", kWidth, kHeight, title);
  svg += Line(x0, y0, x0 + w, y0, "stroke=\"black\"");
  svg += Line(x0, y0, x0, kTop, "stroke=\"black\"");
  for (double t : LinearTicks(yl, yh)) {
    svg += Line(x0 - 4, y_of(t), x0, y_of(t), "stroke=\"black\"");
    svg += Text(x0 - 6, y_of(t) + 4, Tick(t), "end");
  }
  for (double t : LinearTicks(xl, xh)) {
    svg += Line(x_of(t), y0, x_of(t), y0 + 4, "stroke=\"black\"");
    svg += Text(x_of(t), y0 + 16, Tick(t), "middle");
  }
  svg += Text(x0 + w / 2, kHeight - 10, x_label, "middle");
  svg += Text(14, kTop + h / 2, y_label, "middle",
              " transform=\"rotate(-90 14 " + Px(kTop + h / 2) + ")\"");
  if (std::isfinite(marked_x)) {
    svg += Line(x_of(marked_x), y0, x_of(marked_x), kTop,
                "stroke=\"gray\" stroke-dasharray=\"4 3\" class=\"marked\"");
  }
  std::vector<std::pair<std::string, std::string>> legend;
  for (size_t k = 0; k < series.size(); ++k) {
    const CurveSeries& s = series[k];
    legend.push_back({s.label, s.color});
    std::string points;
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.y[i])) continue;
      points += Px(x_of(s.x[i])) + "," + Px(y_of(s.y[i])) + " ";
    }
    svg += "<polyline fill=\"none\" stroke=\"" + s.color + "\" points=\"" +
           points + "\"/>\n";
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.y[i])) continue;
      if (!s.error.empty() && s.error[i] > 0) {
        svg += Line(x_of(s.x[i]), y_of(s.y[i] - s.error[i]), x_of(s.x[i]),
                    y_of(s.y[i] + s.error[i]), "stroke=\"" + s.color + "\"");
      }
      svg += "<circle class=\"point\" data-series=\"" + std::to_string(k) +
             "\" data-x=\"" + Num(s.x[i]) + "\" data-value=\"" + Num(s.y[i]) +
             "\" cx=\"" + Px(x_of(s.x[i])) + "\" cy=\"" + Px(y_of(s.y[i])) +
             "\" r=\"3\" fill=\"" + s.color + "\"/>\n";
    }
  }
  svg += Legend(legend, x0 + w - 200, kTop + 10);
  return svg + "</svg>\n";
}

std::string SvgHeatmap(const Eigen::MatrixXd& matrix,
                       const std::vector<std::string>& names,
                       const std::string& title) {
  const int p = static_cast<int>(matrix.rows());
  CHECK_EQ(matrix.cols(), p);
  CHECK_EQ(static_cast<int>(names.size()), p);
  size_t longest = 1;
  for (const std::string& n : names) longest = std::max(longest, n.size());
  const double cell = p <= 20 ? 18 : p <= 40 ? 12 : 8;
  const double label = 6.5 * longest + 8;
  const double width = label + cell * p + 20;
  const double height = 30 + label + cell * p + 10;
  const double x0 = label, y0 = 30 + label;
  std::string svg = Open("heatmap", std::max(width, 300.0), height, title);
  for (int i = 0; i < p; ++i) {
    svg += Text(x0 - 4, y0 + cell * i + cell * 0.75, names[i], "end",
                " font-size=\"" + Px(std::min(11.0, cell - 1)) + "\"");
    const double xc = x0 + cell * i + cell * 0.75;
    svg += Text(xc, y0 - 4, names[i], "start",
                " font-size=\"" + Px(std::min(11.0, cell - 1)) +
                    "\" transform=\"rotate(-90 " + Px(xc) + " " + Px(y0 - 4) +
                    ")\"");
  }
  for (int i = 0; i < p; ++i) {
    for (int j = 0; j < p; ++j) {
      const double v = matrix(i, j);
      const double c = std::clamp(std::isfinite(v) ? v : 0.0, -1.0, 1.0);
      // White at 0, red at +1, blue at -1.
      const int fade = static_cast<int>(std::lround(255 * (1 - std::abs(c))));
      char colour[16];
      std::snprintf(colour, sizeof(colour), "#%02x%02x%02x", c > 0 ? 255 : fade,
                    fade, c < 0 ? 255 : fade);
      svg += "<rect class=\"cell\" data-row=\"" + std::to_string(i) +
             "\" data-col=\"" + std::to_string(j) + "\" data-value=\"" +
             Num(v) + "\" x=\"" + Px(x0 + cell * j) + "\" y=\"" +
             Px(y0 + cell * i) + "\" width=\"" + Px(cell) + "\" height=\"" +
             Px(cell) + "\" fill=\"" + colour +
             "\" stroke=\"#ddd\" stroke-width=\"0.5\"><title>" +
             HtmlEscape(names[i] + " / " + names[j] + ": " +
                        FormatNumber("%.3f", v)) +
             "</title></rect>\n";
    }
  }
  return svg + "</svg>\n";
}

}  // namespace activecal
