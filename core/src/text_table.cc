// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/text_table.h"

#include <glog/logging.h>

#include <algorithm>
#include <cstdio>
#include <utility>

namespace activecal {

TextTable::TextTable(std::vector<TextColumn> columns)
    : columns_(std::move(columns)) {
  CHECK(!columns_.empty()) << "a table needs a column";
}

void TextTable::AddRow(std::vector<std::string> cells) {
  CHECK_EQ(cells.size(), columns_.size()) << "one cell per column";
  rows_.push_back(std::move(cells));
}

int TextTable::Width(int c) const {
  CHECK(c >= 0 && c < static_cast<int>(columns_.size()));
  size_t width = columns_[c].header.size();
  for (const std::vector<std::string>& row : rows_) {
    width = std::max(width, row[c].size());
  }
  return static_cast<int>(width);
}

std::string TextTable::ToString(int indent) const {
  std::vector<int> widths(columns_.size());
  for (size_t c = 0; c < columns_.size(); ++c) widths[c] = Width(c);
  auto line = [&](const std::vector<std::string>& cells) {
    std::string text(std::max(indent, 0), ' ');
    for (size_t c = 0; c < cells.size(); ++c) {
      if (c > 0) text += "  ";
      const std::string pad(widths[c] - cells[c].size(), ' ');
      text += columns_[c].align == ColumnAlign::kRight ? pad + cells[c]
                                                       : cells[c] + pad;
    }
    text.erase(text.find_last_not_of(' ') + 1);
    return text + "\n";
  };
  std::vector<std::string> header;
  for (const TextColumn& column : columns_) header.push_back(column.header);
  std::string text = line(header);
  for (const std::vector<std::string>& row : rows_) text += line(row);
  return text;
}

std::string FormatNumber(const char* format, double value) {
  char cell[64];
  std::snprintf(cell, sizeof(cell), format, value);
  return cell;
}

}  // namespace activecal
