// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The wall-clock seconds a workflow reports in its summary
// (active_calibration.cc, select_design.cc, select_workflow.cc); not
// installed.

#ifndef ACTIVECAL_CALIBRATION_SRC_SECONDS_SINCE_H_
#define ACTIVECAL_CALIBRATION_SRC_SECONDS_SINCE_H_

#include <chrono>

namespace activecal {
namespace internal {

// Seconds of the steady clock from `start` to now.
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SRC_SECONDS_SINCE_H_
