// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The failure of a workflow whose summary carries a termination type and a
// message (monte_carlo_study.cc, paper_example.cc, simulate_workflow.cc,
// evaluate.cc, compensate.cc); not installed.
//
//   if (!ok) return internal::Fail("--levels=5: ...", summary);

#ifndef ACTIVECAL_CALIBRATION_SRC_WORKFLOW_FAIL_H_
#define ACTIVECAL_CALIBRATION_SRC_WORKFLOW_FAIL_H_

#include <string>

#include "activecal/core/types.h"

namespace activecal {
namespace internal {

// Sets summary->termination_type to `type` and summary->message; false.
template <typename Summary>
bool Fail(const std::string& message, Summary* summary,
          TerminationType type = TerminationType::kFailure) {
  summary->termination_type = type;
  summary->message = message;
  return false;
}

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SRC_WORKFLOW_FAIL_H_
