// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Internal to the io library: the one form of every reader's error,
// "<source>:<line>: <field>: <what>" (the YAML readers add the column,
// "<source>:<line>:<column>: <field>: <what>"), so that a person and a
// script find the file, the line and the field the same way in each.

#ifndef ACTIVECAL_IO_SRC_LINE_ERROR_H_
#define ACTIVECAL_IO_SRC_LINE_ERROR_H_

#include <cctype>
#include <string>

namespace activecal {
namespace internal {

// `what` starts with its field: a name of letters, digits, '_', '.', '[',
// ']' (x_m, pose_index, commanded_r11..commanded_r33, distances[0].from)
// followed by ": ".
inline bool StartsWithField(const std::string& what) {
  size_t i = 0;
  while (i < what.size()) {
    const unsigned char c = static_cast<unsigned char>(what[i]);
    if (!(std::isalnum(c) || c == '_' || c == '.' || c == '[' || c == ']')) {
      break;
    }
    ++i;
  }
  return i > 0 && what.compare(i, 2, ": ") == 0;
}

// "<source>:<line>: <what>" when `what` names its field, otherwise
// "<source>:<line>: <field>: <what>" (`field`: what the line is, e.g.
// "header" or "row", when the error is about the line as a whole).
inline std::string LineError(const std::string& source, int line,
                             const std::string& field,
                             const std::string& what) {
  return source + ":" + std::to_string(line) + ": " +
         (StartsWithField(what) ? what : field + ": " + what);
}

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_IO_SRC_LINE_ERROR_H_
