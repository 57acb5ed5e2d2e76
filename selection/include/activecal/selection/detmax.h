// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// DETMAX (Mitchell 1974), an exact-design algorithm on the updates of the
// information matrix: excursions that add k poses and remove k (or remove
// k and add k), k = 1..max_excursion, kept when they raise log det.
// Restarts are independent and run in parallel threads, each from its own
// seeded stream, ties to the lowest index: the same result for any thread
// count; it never ends below its start.

#ifndef ACTIVECAL_SELECTION_DETMAX_H_
#define ACTIVECAL_SELECTION_DETMAX_H_

#include <cstdint>
#include <string>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/types.h"
#include "activecal/selection/design.h"

namespace activecal {

struct DetmaxOptions {
  int num_poses = 30;
  int max_excursion = 4;
  // Excursions per restart; when reached, NO_CONVERGENCE.
  int max_iterations = 10000;
  // Relative, as FedorovOptions::min_improvement.
  double min_improvement = 1e-9;
  int restarts = 4;
  uint64_t seed = 1;
  int num_threads = 0;
  // Called as restarts finish (done, total = restarts).
  ProgressCallback progress;

  bool IsValid(std::string* error) const;
};

// Returns summary->IsSolutionUsable().
bool Detmax(const CandidatePool& pool, const DesignConstraints& constraints,
            const DetmaxOptions& options, SelectionSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_DETMAX_H_
