// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The tables the programs print for a person: columns as wide as their
// widest cell (header included, so long parameter names such as
// "shoulder_lift_joint.offset" never push a row out of line), text columns
// left-aligned, number columns right-aligned, two spaces between columns,
// every line indented alike and ending with '\n'. Numbers are formatted by
// the caller (FormatNumber below, one printf conversion), so that a table
// shows exactly the digits it did before it was aligned.
//
//   TextTable table({{"parameter"}, {"unit"}, {"estimate", kRight}});
//   table.AddRow({"B.x", "m", FormatNumber("%.6f", -0.006009)});
//   std::cout << table.ToString(/*indent=*/2);
//
// Widths count bytes: cells are ASCII (parameter names, units, numbers).

#ifndef ACTIVECAL_CORE_TEXT_TABLE_H_
#define ACTIVECAL_CORE_TEXT_TABLE_H_

#include <string>
#include <vector>

namespace activecal {

enum class ColumnAlign { kLeft, kRight };

struct TextColumn {
  std::string header;
  ColumnAlign align = ColumnAlign::kLeft;
};

class TextTable {
 public:
  explicit TextTable(std::vector<TextColumn> columns);

  // One row, a cell per column (CHECKed: a programmer error otherwise).
  void AddRow(std::vector<std::string> cells);

  int num_rows() const { return static_cast<int>(rows_.size()); }
  // The width of column `c`: its widest cell or header (bytes).
  int Width(int c) const;

  // The header line and the rows, each line starting with `indent` spaces;
  // trailing spaces of a line are removed (a last text column pads
  // nothing).
  std::string ToString(int indent = 0) const;

 private:
  std::vector<TextColumn> columns_;
  std::vector<std::vector<std::string>> rows_;
};

// `value` through one printf conversion (e.g. "%.6f", "%12.4g", "%.3e"):
// the one number formatter of the printed tables.
std::string FormatNumber(const char* format, double value);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_TEXT_TABLE_H_
