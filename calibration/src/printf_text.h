// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// printf into a std::string, for the report lines of the workflows
// (evaluate.cc, compensate.cc); not installed. A line longer than 511
// bytes is cut there.

#ifndef ACTIVECAL_CALIBRATION_SRC_PRINTF_TEXT_H_
#define ACTIVECAL_CALIBRATION_SRC_PRINTF_TEXT_H_

#include <cstdarg>
#include <cstdio>
#include <string>

namespace activecal {
namespace internal {

inline std::string Printf(const char* format, ...)
    __attribute__((format(printf, 1, 2)));
inline std::string Printf(const char* format, ...) {
  char text[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof(text), format, args);
  va_end(args);
  return text;
}

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SRC_PRINTF_TEXT_H_
