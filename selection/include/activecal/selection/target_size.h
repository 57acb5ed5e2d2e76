// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The size from a target: the fewest poses whose design predicts a task RMS
// position error (task_criterion.h) at or below a target.
//
//   TargetSizeOptions options;
//   options.sigma_m = 1e-4;          // measurement noise
//   options.target_rms_m = 5e-5;     // what the task needs
//   TargetSizeSummary summary;
//   FindSizeForTarget(pool, W, prior_rows, constraints, options,
//       [&](int n, SelectionSummary* s) { ...design n poses...; }, &summary);
//
// With prior rows (poses already measured) the prior alone is tried first,
// as size 0: when it meets the target no new pose is needed.
//
// The search first checks the target against every eligible pose together
// (the best any design can do: information only adds up). If that misses
// it, no size can meet it, and the summary says what the best reachable
// value is. Otherwise the design function is called at sizes n0, 2 n0,
// 4 n0, ... until one meets the target, then by bisection between the
// last size that missed and the first that met; the result is the smallest
// size found meeting it, with size - 1 evaluated and missing (unless it is
// the smallest size tried). The designs are re-optimised at each size, so
// the search assumes that the best design's criterion falls with its size,
// as it does for exact optima.

#ifndef ACTIVECAL_SELECTION_TARGET_SIZE_H_
#define ACTIVECAL_SELECTION_TARGET_SIZE_H_

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/types.h"
#include "activecal/selection/design.h"

namespace activecal {

struct TargetSizeOptions {
  double sigma_m = 1e-4;      // measurement noise (m), > 0
  double target_rms_m = 0.0;  // > 0
  // The first size tried; <= 0: the fewest poses whose rows could make M
  // positive definite, ceil((p - rank of the prior) / t), at least 1.
  int min_poses = 0;

  bool IsValid(std::string* error) const;
};

struct TargetSizeSummary {
  // CONVERGENCE: a size meets the target; FAILURE: none can (message says
  // the best reachable value) or a design failed; USER_FAILURE: bad options.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  int num_poses = 0;
  double predicted_task_rms_m = std::numeric_limits<double>::infinity();
  // Every eligible pose together: the best reachable value.
  double best_reachable_rms_m = std::numeric_limits<double>::infinity();
  // The sizes evaluated, increasing, and their designs' predicted task RMS
  // (+infinity for a singular design).
  std::vector<int> sizes;
  std::vector<double> rms_by_size_m;
  // The design found.
  SelectionSummary design;

  bool reached() const {
    return termination_type == TerminationType::kConvergence;
  }
};

// Designs num_poses poses (the new poses, fixed ones included); false on
// failure with the reason in summary->message.
using DesignOfSize = std::function<bool(int num_poses, SelectionSummary*)>;

bool FindSizeForTarget(const CandidatePool& pool, const Eigen::MatrixXd& W,
                       const RowMatrixXd& prior_rows,
                       const DesignConstraints& constraints,
                       const TargetSizeOptions& options,
                       const DesignOfSize& design_of_size,
                       TargetSizeSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_TARGET_SIZE_H_
