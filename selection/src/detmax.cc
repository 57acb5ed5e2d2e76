// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// DETMAX (Mitchell 1974): excursions that add k poses and remove k, or
// remove k and add k, kept when they raise log det.

#include "activecal/selection/detmax.h"

#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "activecal/core/random.h"
#include "activecal/core/validation.h"
#include "activecal/selection/criteria.h"
#include "selection_internal.h"

namespace activecal {

bool DetmaxOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (internal::PositivePosesAndRestarts(*this, &msg)) {
    if (max_excursion <= 0)
      msg << "max_excursion must be > 0";
    else if (max_iterations < 0)
      msg << "max_iterations must be >= 0";
  }
  return FinishValidation(msg, error);
}

namespace internal {

bool TryExcursion(const CandidatePool& pool, const std::vector<char>& eligible,
                  const std::vector<char>& is_fixed, int min_size,
                  int max_excursion, double min_improvement, int threads,
                  std::vector<int64_t>* poses, SelectionStep* step) {
  for (int k = min_size; k <= max_excursion; ++k) {
    for (int direction = 0; direction < 2; ++direction) {
      internal::DeterminantScorer scorer(pool, threads);
      for (int64_t i : *poses) scorer.Add(i);
      const double base = scorer.Value();
      bool ok = true;
      for (int phase = 0; phase < 2 && ok; ++phase) {
        const bool adding = (phase == 0) == (direction == 0);
        for (int j = 0; j < k && ok; ++j) {
          int64_t pose;
          double value;
          if (adding) {
            ok = scorer.BestAddition(eligible, &pose, &value);
            if (ok) scorer.Add(pose);
          } else {
            ok = scorer.BestRemoval(is_fixed, &pose, &value) &&
                 scorer.Remove(pose);
          }
        }
      }
      // Accepted on values recomputed from scratch: the incremental ones of
      // a nearly singular design can drift by more than the threshold, and
      // two excursions could then undo each other forever.
      if (ok && scorer.Value() > base + internal::ImprovementThreshold(
                                            base, min_improvement)) {
        const double before = LogDetFromScratch(pool, *poses);
        const double after = LogDetFromScratch(pool, scorer.poses());
        if (!(after > before + internal::ImprovementThreshold(
                                   before, min_improvement))) {
          continue;
        }
        *poses = scorer.poses();
        step->kind = direction == 0 ? SelectionStep::kExcursionUp
                                    : SelectionStep::kExcursionDown;
        step->excursion_size = k;
        return true;
      }
    }
  }
  return false;
}

}  // namespace internal

bool Detmax(const CandidatePool& pool, const DesignConstraints& constraints,
            const DetmaxOptions& options, SelectionSummary* summary) {
  internal::SelectionStart start;
  if (!internal::PrepareSelection(pool, constraints, options, "detmax", summary,
                                  &start)) {
    return false;
  }
  return internal::RunRestartsFromInitialDesigns(
      pool, constraints, options, start, options.num_poses,
      [&](const internal::WorkingSet& work, int threads, std::string*,
          internal::RestartResult* result) {
        std::vector<int64_t>& poses = result->design;
        {
          internal::DeterminantScorer start_scorer(pool, threads);
          for (int64_t i : poses) start_scorer.Add(i);
          result->history.push_back(
              {SelectionStep::kInitial, -1, -1, start_scorer.Value()});
        }
        for (int it = 0;; ++it) {
          if (it >= options.max_iterations) {
            result->hit_bound = true;
            break;
          }
          SelectionStep step;
          if (!internal::TryExcursion(
                  pool, work.eligible, work.is_fixed, 1, options.max_excursion,
                  options.min_improvement, threads, &poses, &step)) {
            break;
          }
          step.log_det = LogDetFromScratch(pool, poses);
          result->history.push_back(step);
        }
        return true;
      },
      summary);
}

}  // namespace activecal
