// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The greedy design: add the pose that raises log det most until the
// design has num_poses (from the fixed poses; a vanishing ridge while the
// design is singular). Ties go to the lowest index, so the result is the
// same for any thread count.

#ifndef ACTIVECAL_SELECTION_GREEDY_H_
#define ACTIVECAL_SELECTION_GREEDY_H_

#include <cstdint>
#include <string>

#include "activecal/core/candidate_pool.h"
#include "activecal/selection/design.h"

namespace activecal {

struct GreedyOptions {
  int num_poses = 30;
  int num_threads = 0;

  bool IsValid(std::string* error) const;
};

// Returns summary->IsSolutionUsable().
bool GreedyDesign(const CandidatePool& pool,
                  const DesignConstraints& constraints,
                  const GreedyOptions& options, SelectionSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_GREEDY_H_
