// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Fedorov's exchange, an exact-design algorithm beyond the paper's
// exchange-add-exchange, on the same information-matrix updates (DETMAX
// and the greedy design, the other two: detmax.h, greedy.h):
//
//  * FedorovExchange: at every iteration the best swap over all
//    (design pose, candidate) pairs, by the block exchange formula
//      det ratio = det(I + D_x) det(I - D_y + D_xy^T (I + D_x)^-1 D_xy),
//    in the fast form of Nguyen & Miller (1992): every candidate's block
//    D_j = X_j V X_j^T is kept current by rank-2t updates after each swap,
//    and swaps that cannot win are pruned by the bounds
//      ratio <= exp(tr D_x - tr D_y),
//      ratio <= det(I + D_x) prod_i (1 - mu_i(D_y) / (1 + lambda_max(D_x)))
//    (the second proved in fedorov.cc); the D_xy of the pairs that remain
//    are computed by one matrix product per batch of candidates.
//    With an approximate design, restart 0 starts from its N heaviest
//    poses and restart r > 0 from N of its poses drawn without replacement
//    with probability proportional to weight (randomized rounding);
//    without one, every restart starts from a random design.
//
// Restarts are independent and run in parallel threads; each draws from its
// own seeded stream and ties go to the lowest index, so the result is the
// same for any thread count. Only steps that raise log det are accepted,
// so it never ends below its start.

#ifndef ACTIVECAL_SELECTION_FEDOROV_H_
#define ACTIVECAL_SELECTION_FEDOROV_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "activecal/core/candidate_pool.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/design.h"

namespace activecal {

struct FedorovOptions {
  int num_poses = 30;
  int restarts = 16;
  // Swaps and excursions per restart (and per polish); when it is reached
  // the summary says NO_CONVERGENCE. 0: no swaps (only the start).
  int max_swaps = 100000;
  // A swap or excursion must raise log det by more than
  // min_improvement * max(1, |log det|) (relative: rounding in a log det
  // of any size cannot pass for progress).
  double min_improvement = 1e-9;
  // Swaps between from-scratch refreshes of every candidate's block.
  int refresh_interval = 20;
  // When no single swap helps, DETMAX excursions of 2..max_excursion poses
  // are tried, and swapping resumes after one succeeds (< 2: none).
  int max_excursion = 2;
  // With an approximate design, restarts swap first within a reduced pool
  // of max(reduced_pool_size, reduced_pool_per_pose * num_poses) poses
  // (those of largest variance under the approximate design, plus its
  // support and the fixed poses) when the pool is larger than that; the
  // best result is then polished by swaps over the whole pool.
  // reduced_pool_size <= 0: always the whole pool.
  int64_t reduced_pool_size = 3000;
  int64_t reduced_pool_per_pose = 40;
  // The polish swaps over the whole pool when it has at most this many
  // poses. A larger pool is polished in rounds over this many poses of
  // largest variance under the current design (re-ranked after each
  // round), until a round makes no swap or max_polish_rounds rounds have
  // run (then NO_CONVERGENCE): not a proof of local optimality over every
  // pose, which the efficiency certificate makes up for.
  int64_t polish_pool_size = 20000;
  int max_polish_rounds = 8;
  // Scan the weakest design poses against the strongest candidates first
  // (KL exchange) and all pairs only when that finds no improving swap.
  bool kl_exchange = true;
  uint64_t seed = 1;
  int num_threads = 0;  // <= 0: all
  // Called as restarts finish (done, total = restarts).
  ProgressCallback progress;

  bool IsValid(std::string* error) const;
};

// `approximate` (may be null): the restarts start from its roundings.
// A single-precision pool needs one (else FAILURE): the restarts then
// always run on the reduced pool (in double; the whole eligible pool when
// reduced_pool_size <= 0) and the polish always in rounds (over the whole
// eligible pool when polish_pool_size <= 0), so only sub-pools are ever
// held in double. summary->log_det is recomputed in double from the pool's
// exact blocks (CandidatePool::ExactBlock: the exact source if any, else
// the stored blocks), whatever pool the swaps ran on (the history's log
// dets are those of the pool each step ran on: for a single-precision pool,
// the widened blocks).
// Returns summary->IsSolutionUsable().
bool FedorovExchange(const CandidatePool& pool,
                     const DesignConstraints& constraints,
                     const FedorovOptions& options,
                     const ApproximateDesignSummary* approximate,
                     SelectionSummary* summary);

namespace internal {
// The pair scan's second bound on the log det ratio of swapping in a
// candidate x for a design pose y, from D_x = X_x V X_x^T and
// D_y = X_y V X_y^T (t x t, V = M^-1): log det(I + D_x) +
// sum_i log(1 - mu_i(D_y) / (1 + lambda_max(D_x))), -inf when a factor is
// <= 0. Exposed for its test.
double SwapLogRatioBound(const Eigen::MatrixXd& Dx, const Eigen::MatrixXd& Dy);
}  // namespace internal

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_FEDOROV_H_
