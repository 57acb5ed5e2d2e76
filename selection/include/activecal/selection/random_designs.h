// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Best of K random designs (Sun & Hollerbach, Section V-C): the baseline
// the active algorithms are measured against.

#ifndef ACTIVECAL_SELECTION_RANDOM_DESIGNS_H_
#define ACTIVECAL_SELECTION_RANDOM_DESIGNS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/selection/design.h"

namespace activecal {

struct RandomDesignOptions {
  int num_poses = 30;  // poses per design, fixed poses included
  int num_designs = 5000;
  uint64_t seed = 1;
  // Threads (<= 0: all). Design k always draws from its own stream, so the
  // result does not depend on the count.
  int num_threads = 0;

  bool IsValid(std::string* error) const;
};

// Draws options.num_designs designs uniformly (fixed poses always in,
// excluded poses never) and keeps the best by log det. If log_dets is not
// null it receives every design's natural log det (-inf when singular), in
// draw order, for histograms.
bool SelectRandomDesigns(const CandidatePool& pool,
                         const DesignConstraints& constraints,
                         const RandomDesignOptions& options,
                         SelectionSummary* summary,
                         std::vector<double>* log_dets = nullptr);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_RANDOM_DESIGNS_H_
