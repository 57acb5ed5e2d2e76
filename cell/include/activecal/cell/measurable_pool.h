// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A pool that samples where measurement is possible: instead of drawing
// joint values and keeping the few a cell can measure (a UR10e in front of
// a laser tracker keeps ~3 % of its joint space), draw what the device can
// measure and solve for the joints.
//
// Each draw: a target point inside the robot's reach (a box around the
// tips of 4,000 random configurations), inside the device's range (and a
// camera's field of view: one camera, chosen at random, for mocap) and
// outside every obstacle; a direction for the target's normal inside its
// acceptance cone about the direction to the device (uniform on the
// cone's cap) and a random roll about it. The tip pose that puts the
// target there is solved by the inverse kinematics (inverse_kinematics.h,
// matched in position and orientation) from seeds_per_target random starts
// inside the joint margins, so that every branch of the arm's inverse
// kinematics is tried; the distinct solutions (whatever the solver's
// status: the checks decide) are checked by CellChecker::Check and the
// feasible ones kept, in draw order.
//
//   MeasurablePoolOptions options;
//   options.num_poses = 20000;
//   MeasurablePoolSummary summary;
//   if (!SampleMeasurablePool(checker, options, &summary)) ...
//   summary.joints;  // num_poses x num_joints, each feasible
//
// Deterministic for a seed whatever the thread count: draw d uses the
// random stream Random::StreamSeed(seed, d) and its results are kept in
// draw order.

#ifndef ACTIVECAL_CELL_MEASURABLE_POOL_H_
#define ACTIVECAL_CELL_MEASURABLE_POOL_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>

#include "activecal/cell/cell_checker.h"
#include "activecal/cell/rejection_counts.h"
#include "activecal/core/types.h"

namespace activecal {

struct MeasurablePoolOptions {
  int64_t num_poses = 10000;  // feasible poses wanted
  uint64_t seed = 1;
  // The cell's target placed at each draw (0-based).
  int target = 0;
  // Inverse kinematics starts per target pose.
  int seeds_per_target = 4;
  // Levenberg-Marquardt iterations per start, and the tolerances: the
  // target pose is itself random, so an approximate solution serves.
  int ik_iterations = 40;
  double ik_position_tolerance_m = 1e-6;
  double ik_rotation_tolerance_rad = 1e-5;
  // Stop after this many draws (0: kDefaultDrawsPerPose x num_poses).
  int64_t max_draws = 0;
  // Stop when none of the first give_up_draws draws gives a feasible pose
  // (0: never). A cell that fills the pool within the default cap gives
  // at least one pose per 10 draws: none in 1,000 draws has probability
  // below e^-100 then.
  int64_t give_up_draws = 1000;
  int num_threads = 0;
  ProgressCallback progress;  // feasible poses found

  bool IsValid(std::string* error) const;
};

// The default cap on draws per pose wanted: the UR10e and iiwa cells of
// docs/scaling.md need 0.85 and 0.92 draws per feasible pose.
inline constexpr int64_t kDefaultDrawsPerPose = 10;

// The draws options allow: max_draws, or kDefaultDrawsPerPose x num_poses.
int64_t MaxDraws(const MeasurablePoolOptions& options);

struct MeasurablePoolSummary {
  // CONVERGENCE: num_poses poses found; NO_CONVERGENCE: max_draws reached
  // first, or give_up_draws without a pose (gave_up; joints has fewer
  // rows); USER_FAILURE: bad options or a cell without a device and
  // targets.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  Eigen::MatrixXd joints;
  int64_t draws = 0;      // target poses drawn
  int64_t ik_solves = 0;  // inverse kinematics solves run
  // Distinct solutions checked, and why the others were rejected (index:
  // RejectionReason).
  int64_t solutions_checked = 0;
  std::array<int64_t, kNumRejectionReasons> rejected{};
  // The same counts, per obstacle and per pair that collided.
  RejectionCounts counts;
  int64_t ik_failures = 0;          // solves with no usable result
  int64_t draws_without_point = 0;  // no target point passed the cheap tests
  int64_t max_draws = 0;            // the cap applied
  bool gave_up = false;             // stopped by give_up_draws
  double seconds = 0.0;

  // Draws and solves per feasible pose.
  double DrawsPerPose() const;
  double SolvesPerPose() const;
  std::string BriefReport() const;
  // One line on a pool that fell short: message, then the solutions
  // checked and the count per rejection reason, the failed solves, the
  // draws without a target point and, when no pose was found and
  // collisions rejected some, the pair to blame
  // (RejectionCounts::CollisionDiagnosis).
  std::string FailureText(const CellChecker& checker) const;
};

bool SampleMeasurablePool(const CellChecker& checker,
                          const MeasurablePoolOptions& options,
                          MeasurablePoolSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CELL_MEASURABLE_POOL_H_
