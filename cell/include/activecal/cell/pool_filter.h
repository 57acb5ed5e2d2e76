// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The preprocess of a candidate pool: the poses a real cell can run (the
// checks of cell_checker.h), counted per reason, before the pool's
// Jacobians, the identifiability check and the design.
//
//   PoolFilterOptions options;
//   options.num_threads = 2;
//   PoolFilterSummary summary;
//   FilterPool(checker, pool_joints, options, &summary);
//   std::cout << summary.BriefReport(checker);
//   // "cell: 6211 of 200000 poses feasible; rejected: joint margin 9114,
//   //  target facing away 171020, ..."
//   Eigen::MatrixXd feasible = summary.FeasibleJoints(pool_joints);
//
// Deterministic: every pose is checked on its own, so the verdicts and the
// feasible rows are the same for every thread count.

#ifndef ACTIVECAL_CELL_POOL_FILTER_H_
#define ACTIVECAL_CELL_POOL_FILTER_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/cell/cell_checker.h"
#include "activecal/cell/rejection_counts.h"
#include "activecal/core/types.h"

namespace activecal {

struct PoolFilterOptions {
  int num_threads = 0;  // <= 0: all hardware threads
  ProgressCallback progress;
};

struct PoolFilterSummary {
  // CONVERGENCE: the pool was checked (feasible may be empty);
  // USER_FAILURE: the joints do not fit the model.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  int64_t num_poses = 0;
  // The rows that pass, ascending, and the targets each sees (bit t).
  std::vector<int64_t> feasible;
  std::vector<uint32_t> targets_seen;
  // Every row's verdict.
  std::vector<PoseVerdict> verdicts;
  // Rows rejected per reason (index: RejectionReason), and the obstacle
  // ones per obstacle (index: the cell's obstacles).
  std::array<int64_t, kNumRejectionReasons> rejected{};
  std::vector<int64_t> rejected_by_obstacle;
  // The same counts, with the pairs that collided (rejection_counts.h).
  RejectionCounts counts;
  double seconds = 0.0;

  int64_t num_feasible() const { return static_cast<int64_t>(feasible.size()); }
  // "joint margin 12, self-collision 3, obstacle table 40, obstacle wall 2,
  // out of range 0, out of view 0, target facing away 120, line of sight
  // blocked 1" (out of view only for cameras).
  std::string CountsText(const CellChecker& checker) const;
  // "cell: 210 of 1000 poses feasible (0.05 s); rejected: <counts>\n".
  std::string BriefReport(const CellChecker& checker) const;
  // The feasible rows of `joints`.
  Eigen::MatrixXd FeasibleJoints(const Eigen::MatrixXd& joints) const;
};

// Checks every row of `joints` (num_poses x num_joints, SI).
bool FilterPool(const CellChecker& checker, const Eigen::MatrixXd& joints,
                const PoolFilterOptions& options, PoolFilterSummary* summary);

// The rejected rows, in pool order, as a poses CSV (docs/formats.md) with
// three more columns, which the poses CSV readers ignore:
//
//   pose_index,q1_rad,...,q6_deg,reason,obstacle,detail
//   17,...,obstacle,table,wrist_3_link
//
// reason: RejectionReasonToString of the first check failed; obstacle: its
// name for an obstacle row, else empty; detail: the joint (joint_margin),
// the two links "a|b" (self_collision), the link that came too close
// (obstacle), or the link or obstacle that blocked the first target's line
// of sight; empty for the target checks. pose_index is labels[row] (the row
// when labels is empty).
std::string RejectedCsvText(const CellChecker& checker,
                            const Eigen::MatrixXd& joints,
                            const std::vector<int64_t>& labels,
                            const PoolFilterSummary& summary);

}  // namespace activecal

#endif  // ACTIVECAL_CELL_POOL_FILTER_H_
