// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Exact designs for the task criterion phi = tr(W M^-1) (task_criterion.h):
//
//  * TaskExchange: Fedorov exchange. At every iteration the best swap over
//    all (design pose, candidate) pairs by the swap formula of
//    task_criterion.h. Candidates are scanned in order of their own add
//    change, and a candidate whose add change alone cannot beat the best
//    swap found is skipped (removing a pose never lowers phi, so
//    change(swap x, y) >= change(add x)): the result is the best swap, not
//    a heuristic one. Restart 0 starts from the heaviest poses of the
//    approximate task design (task_approximate.h) when given, restart r > 0
//    from a draw proportional to its weights, or from random poses. Each
//    iteration scans the design poses whose removal costs least against
//    the candidates whose addition gains most first (KL exchange), and all
//    pairs only when that finds no improving swap. A large pool is worked
//    in a reduced pool first (see the options), then polished whole.
//  * TaskGreedy: adds the pose that lowers phi most until num_poses
//    (a vanishing ridge while M is singular). Its designs are nested, so
//    the criterion it reports per size never rises.
//
// Both take the prior rows (poses already measured, whitened; may have no
// rows) and the design constraints. Restarts are independent, draw from
// their own seeded streams and run in parallel; ties go to the lowest
// index, so results do not depend on the thread count. Every step lowers
// phi, so no restart ends above its start.

#ifndef ACTIVECAL_SELECTION_TASK_EXCHANGE_H_
#define ACTIVECAL_SELECTION_TASK_EXCHANGE_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/types.h"
#include "activecal/selection/design.h"

namespace activecal {

struct TaskApproximateSummary;

struct TaskExchangeOptions {
  int num_poses = 30;  // new poses, fixed poses included (not the prior)
  int restarts = 4;
  // Swaps per restart; when reached the summary says NO_CONVERGENCE.
  int max_swaps = 10000;
  // A swap must lower phi by more than min_improvement * phi.
  double min_improvement = 1e-9;
  // With an approximate design and a pool larger than
  // max(reduced_pool_size, reduced_pool_per_pose * num_poses), the restarts
  // swap within that many poses (those of largest b_i under the approximate
  // design, its support and the fixed poses); the best is then polished by
  // swaps over the whole pool, so it is a local optimum of the full problem
  // either way. reduced_pool_size <= 0: always the whole pool.
  int64_t reduced_pool_size = 3000;
  int64_t reduced_pool_per_pose = 40;
  uint64_t seed = 1;
  int num_threads = 0;        // <= 0: all; results do not depend on it
  ProgressCallback progress;  // as restarts finish

  bool IsValid(std::string* error) const;
};

// summary->task_criterion receives phi of the design, recomputed from
// scratch; summary->log_det its log det (without the prior). `approximate`
// may be null. Returns summary->IsSolutionUsable().
bool TaskExchange(const CandidatePool& pool, const Eigen::MatrixXd& W,
                  const RowMatrixXd& prior_rows,
                  const DesignConstraints& constraints,
                  const TaskExchangeOptions& options,
                  const TaskApproximateSummary* approximate,
                  SelectionSummary* summary);

// Greedy additions up to num_poses. criterion_by_size (may be null)
// receives phi after each size from the fixed poses on: entry k is the
// design of its first (fixed + k + 1) poses (+infinity while singular).
bool TaskGreedy(const CandidatePool& pool, const Eigen::MatrixXd& W,
                const RowMatrixXd& prior_rows,
                const DesignConstraints& constraints, int num_poses,
                int num_threads, SelectionSummary* summary,
                std::vector<double>* criterion_by_size = nullptr);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_TASK_EXCHANGE_H_
