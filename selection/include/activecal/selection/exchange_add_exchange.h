// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The exchange-add-exchange algorithm of Sun & Hollerbach, Section IV:
//
//  1. Initialise: n random poses from the pool (fixed poses included).
//  2. Exchange step: remove the pose whose removal lowers the criterion
//     least, add the pool pose that raises it most; keep the swap if the
//     criterion went up, else undo it and stop (or stop after
//     max_exchanges swaps).
//  3. Add step: add the best pose until num_poses are reached, the target
//     is reached, or no pose raises the criterion.
//  4. Exchange step again.
//  Restarts repeat 1-4 from new random poses; the best design is kept.
//
// With SelectionCriterion::kDeterminantUpdate (the paper's contribution)
// every candidate is scored by the block update formulas in O(t p^2); with
// kEigenvalueOi every candidate design is scored by the SVD of its stacked
// design matrix (the paper's OI), as the algorithms before it did. Both
// criteria order designs identically (OI is a monotone function of log det
// when all p singular values are non-zero), so they pick the same poses;
// the second exists to show it and to measure the cost.
//
// An initial design with fewer than p independent rows is singular. It is
// completed greedily, one pose at a time maximising log det(M + eps I) with
// eps = 1e-9 * the mean diagonal entry of one pool pose's X_i^T X_i, until
// M itself is positive
// definite; the summary's message says so.

#ifndef ACTIVECAL_SELECTION_EXCHANGE_ADD_EXCHANGE_H_
#define ACTIVECAL_SELECTION_EXCHANGE_ADD_EXCHANGE_H_

#include <cstdint>
#include <limits>
#include <string>

#include "activecal/core/candidate_pool.h"
#include "activecal/selection/design.h"

namespace activecal {

enum class SelectionCriterion {
  kDeterminantUpdate,  // log det by the update formulas
  kEigenvalueOi,       // OI by SVD of the stacked design matrix
};

struct ExchangeAddExchangeOptions {
  int num_poses = 30;      // the maximum design size n1 (fixed included)
  int initial_poses = 12;  // the random initial design size n
  // Per exchange step; when reached, the summary says NO_CONVERGENCE.
  int max_exchanges = 1000;
  // Stop adding once log det X^T X (natural log) reaches this.
  double target_log_det = std::numeric_limits<double>::infinity();
  // A step must raise log det by more than
  // min_improvement * max(1, |log det|) to count as an increase.
  double min_improvement = 1e-10;
  // Restarts run in parallel (see BestOfRestarts); the best by log det
  // wins, the lowest restart on ties.
  int restarts = 1;
  uint64_t seed = 1;
  int num_threads = 0;  // <= 0: all; results do not depend on it
  // Called as restarts finish (done, total = restarts).
  ProgressCallback progress;
  SelectionCriterion criterion = SelectionCriterion::kDeterminantUpdate;

  bool IsValid(std::string* error) const;
};

bool ExchangeAddExchange(const CandidatePool& pool,
                         const DesignConstraints& constraints,
                         const ExchangeAddExchangeOptions& options,
                         SelectionSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_EXCHANGE_ADD_EXCHANGE_H_
