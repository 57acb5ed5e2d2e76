// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/selection/random_designs.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/core/validation.h"
#include "activecal/selection/criteria.h"
#include "selection_internal.h"

namespace activecal {

bool RandomDesignOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  internal::PositiveCounts(
      {{"num_poses", num_poses}, {"num_designs", num_designs}}, &msg);
  return FinishValidation(msg, error);
}

bool SelectRandomDesigns(const CandidatePool& pool,
                         const DesignConstraints& constraints,
                         const RandomDesignOptions& options,
                         SelectionSummary* summary,
                         std::vector<double>* log_dets) {
  internal::SelectionStart start;
  if (!internal::PrepareSelection(pool, constraints, options, "random", summary,
                                  &start)) {
    return false;
  }
  std::vector<int64_t> candidates;
  for (int64_t i = 0; i < pool.size(); ++i) {
    if (start.eligible[i]) candidates.push_back(i);
  }
  const int free_count =
      options.num_poses - static_cast<int>(constraints.fixed.size());
  std::vector<double> values(options.num_designs);
  ParallelFor(options.num_designs, options.num_threads,
              [&](int64_t begin, int64_t end, int) {
                for (int64_t k = begin; k < end; ++k) {
                  Random random(Random::StreamSeed(options.seed, k));
                  std::vector<int64_t> design = constraints.fixed;
                  for (int64_t j : random.SampleWithoutReplacement(
                           candidates.size(), free_count)) {
                    design.push_back(candidates[j]);
                  }
                  values[k] = LogDetFromScratch(pool, design);
                }
              });
  int best = 0;
  for (int k = 1; k < options.num_designs; ++k) {
    if (values[k] > values[best]) best = k;
  }
  // Redraw the best design from its stream.
  Random random(Random::StreamSeed(options.seed, best));
  summary->design = constraints.fixed;
  for (int64_t j :
       random.SampleWithoutReplacement(candidates.size(), free_count)) {
    summary->design.push_back(candidates[j]);
  }
  summary->log_det = LogDetFromScratch(pool, summary->design);
  summary->history.push_back(
      {SelectionStep::kInitial, -1, -1, summary->log_det});
  summary->restarts = options.num_designs;
  summary->best_restart = best;
  if (log_dets) *log_dets = values;
  summary->seconds = std::chrono::duration<double>(
                         std::chrono::steady_clock::now() - start.time)
                         .count();
  if (!std::isfinite(summary->log_det)) {
    summary->message = "all " + std::to_string(options.num_designs) +
                       " random designs are singular";
    return false;
  }
  std::ostringstream msg;
  msg << "best of " << options.num_designs << " random designs is number "
      << best;
  summary->message = msg.str();
  summary->termination_type = TerminationType::kConvergence;
  return true;
}

}  // namespace activecal
