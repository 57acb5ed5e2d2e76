// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Greedy: add the best pose until the design has num_poses.

#include "activecal/selection/greedy.h"

#include <chrono>
#include <cmath>
#include <string>

#include "activecal/selection/criteria.h"
#include "selection_internal.h"

namespace activecal {

bool GreedyOptions::IsValid(std::string* error) const {
  if (num_poses > 0) return true;
  if (error) *error = "num_poses must be > 0, got " + std::to_string(num_poses);
  return false;
}

bool GreedyDesign(const CandidatePool& pool,
                  const DesignConstraints& constraints,
                  const GreedyOptions& options, SelectionSummary* summary) {
  internal::SelectionStart start;
  if (!internal::PrepareSelection(pool, constraints, options, "greedy", summary,
                                  &start)) {
    return false;
  }
  const double eps = internal::RegularisingRidge(pool);
  internal::DeterminantScorer design(pool, options.num_threads, eps);
  for (int64_t f : constraints.fixed) design.Add(f);
  internal::RestartResult result;
  while (design.size() < options.num_poses) {
    int64_t best;
    double value;
    if (!design.BestAddition(start.eligible, &best, &value)) break;
    design.Add(best);
    result.history.push_back({SelectionStep::kAdd, best, -1,
                              LogDetFromScratch(pool, design.poses())});
  }
  internal::FinishRestart(pool, design.poses(), &result);
  internal::FinishSummary(
      result, 1, start.time,
      "ridge " + std::to_string(eps) + " while the design was singular",
      summary);
  return summary->IsSolutionUsable();
}

}  // namespace activecal
