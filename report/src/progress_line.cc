// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/report/progress_line.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <utility>

namespace activecal {

ProgressLineClock::ProgressLineClock(std::string prefix, bool tty,
                                     int64_t after_ns, int64_t start_ns)
    : prefix_(std::move(prefix)),
      tty_(tty),
      after_ns_(after_ns),
      start_ns_(start_ns) {}

std::string ProgressLineClock::Update(int64_t done, int64_t total,
                                      int64_t now_ns) {
  // Nothing in the first after_ns: a short step prints no line.
  if (now_ns - start_ns_ < after_ns_) return "";
  // On a terminal the line is rewritten 5 times a second; in a file or a
  // pipe a new line every after_ns (the threshold), and the last one.
  const int64_t every =
      tty_ ? std::min<int64_t>(200000000, after_ns_) : after_ns_;
  if (done < total && printed_ && now_ns - last_ns_ < every) return "";
  if (done >= total && !tty_ && finished_) return "";
  last_ns_ = now_ns;
  finished_ = done >= total;
  printed_ = true;
  const double elapsed = (now_ns - start_ns_) * 1e-9;
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  char line[256];
  if (done < total && rate > 0) {
    std::snprintf(line, sizeof(line), "%s: %lld/%lld (%.3g/s, %.1f s left)",
                  prefix_.c_str(), static_cast<long long>(done),
                  static_cast<long long>(total), rate, (total - done) / rate);
  } else {
    std::snprintf(line, sizeof(line),
                  done < total ? "%s: %lld/%lld (%.1f s so far)"
                               : "%s: %lld/%lld (%.1f s)",
                  prefix_.c_str(), static_cast<long long>(done),
                  static_cast<long long>(total), elapsed);
  }
  return line;
}

int64_t ProgressAfterNs(const char* text, int64_t fallback) {
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  const double s = std::strtod(text, &end);
  if (*end != '\0' || !(s >= 0) || s > 1e6) return fallback;
  return static_cast<int64_t>(s * 1e9);
}

}  // namespace activecal
