// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Numbers as text, shared by the file readers and writers of core (not
// installed).

#ifndef ACTIVECAL_CORE_SRC_NUMBER_TEXT_H_
#define ACTIVECAL_CORE_SRC_NUMBER_TEXT_H_

#include <charconv>
#include <cmath>
#include <string>

namespace activecal {
namespace internal {

inline constexpr double kDegree = M_PI / 180.0;

// Shortest decimal text that reads back to the same double.
inline std::string ShortestText(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

// `s` without leading and trailing blanks (space, tab, CR).
inline std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// Parses the whole of `text` as a finite double (a leading '+' allowed).
// On failure says why in *why: "expected a number, got 'abc'" or
// "must be finite, got 'inf'".
inline bool ParseFiniteNumber(const std::string& text, double* value,
                              std::string* why) {
  const char* begin = text.data();
  const char* end = begin + text.size();
  // from_chars does not take a leading '+'.
  if (begin != end && *begin == '+') ++begin;
  double parsed = 0.0;
  const auto result = std::from_chars(begin, end, parsed);
  if (result.ec == std::errc::result_out_of_range && result.ptr == end) {
    *why = "must be finite (beyond the range of a double), got '" + text + "'";
    return false;
  }
  if (result.ec != std::errc() || result.ptr != end || text.empty()) {
    *why = "expected a number, got '" + text + "'";
    return false;
  }
  if (!std::isfinite(parsed)) {
    *why = "must be finite, got '" + text + "'";
    return false;
  }
  *value = parsed;
  return true;
}

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_CORE_SRC_NUMBER_TEXT_H_
