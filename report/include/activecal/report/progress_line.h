// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A progress line's timing and text, for a program's stderr ("<program>:
// <label>: 12288/15625 (41000/s, 0.1 s left)"): nothing in the first
// after_ns (a short step prints nothing); then on a terminal the line
// rewritten at most 5 times a second, in a file or a pipe a new line every
// after_ns, and the last one. The caller writes the lines (on a terminal
// each over the one before) and makes the calls one at a time.
//
//   ProgressLineClock clock("activecal_select: pool", /*tty=*/false,
//                           ProgressAfterNs(std::getenv("..."), 2e9), now);
//   const std::string line = clock.Update(done, total, now_ns);
//   if (!line.empty()) std::cerr << line << std::endl;

#ifndef ACTIVECAL_REPORT_PROGRESS_LINE_H_
#define ACTIVECAL_REPORT_PROGRESS_LINE_H_

#include <cstdint>
#include <string>

namespace activecal {

class ProgressLineClock {
 public:
  // `prefix`: what each line starts with ("<program>: <label>"); the clock
  // runs from start_ns.
  ProgressLineClock(std::string prefix, bool tty, int64_t after_ns,
                    int64_t start_ns);

  // The line due for `done` of `total` at now_ns, empty when none is:
  // "<prefix>: <done>/<total> (<rate>/s, <s> s left)" (rate to 3 digits,
  // seconds to 0.1), "... (<s> s so far)" while no rate is known, and
  // "<prefix>: <total>/<total> (<s> s)" once done (in a file or a pipe
  // only once). At most 255 characters.
  std::string Update(int64_t done, int64_t total, int64_t now_ns);

  // A line was due: on a terminal the caller ends it with a newline.
  bool printed() const { return printed_; }

 private:
  std::string prefix_;
  bool tty_;
  int64_t after_ns_;
  int64_t start_ns_;
  int64_t last_ns_ = 0;
  bool printed_ = false;
  bool finished_ = false;
};

// The delay before a progress line, from `text` in seconds (an environment
// variable's value: a number >= 0 and <= 1e6, 0 printing every update);
// `fallback` when text is null, empty or not such a number.
int64_t ProgressAfterNs(const char* text, int64_t fallback);

}  // namespace activecal

#endif  // ACTIVECAL_REPORT_PROGRESS_LINE_H_
