// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// An order to run a design in: a short tour in joint space, every move
// between consecutive poses checked for collisions.
//
// The time of a move from q to q' is max_j |q'_j - q_j| / v_j: every joint
// at its velocity limit v_j (the URDF's <limit velocity>; default_velocity
// where none is given), accelerations ignored: an estimate of motion time,
// not a trajectory. The tour is an open path (no return to the start):
// nearest neighbour from every start, the shortest kept, then 2-opt
// (segment reversals) until no reversal shortens it; the input order is
// improved by 2-opt too, and the shorter of the two (in the time above, a
// blocked move counting as kBlockedMovePenaltyS more) is returned, so the
// tour never takes longer than the input order when that order is free.
//
// A move is checked along the straight line in joint space, at
// configurations no more than resolution_rad (revolute) or resolution_m
// (prismatic) apart in every joint, both ends included, by
// CellChecker::CheckCollisions (self-collision and obstacles, with the
// cell's clearances). A blocked move is avoided by the reordering when a
// free order is found, else reported in blocked_moves.

#ifndef ACTIVECAL_CELL_TOUR_H_
#define ACTIVECAL_CELL_TOUR_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/cell/cell_checker.h"
#include "activecal/core/types.h"

namespace activecal {

inline constexpr double kBlockedMovePenaltyS = 1e6;

struct TourOptions {
  // Per joint (rad/s or m/s); empty or <= 0 entries: default_velocity.
  std::vector<double> velocity_limits;
  double default_velocity = 1.0;         // rad/s (revolute), m/s (prismatic)
  double resolution_rad = M_PI / 180.0;  // 1 deg
  double resolution_m = 0.005;
  // False: order by time only, no move checked.
  bool check_moves = true;

  bool IsValid(std::string* error) const;
};

struct TourSummary {
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  // order[k]: the row of the poses run k-th (a permutation).
  std::vector<int> order;
  double time_before_s = 0.0;  // the input order's motion time
  double time_after_s = 0.0;   // the tour's
  // Positions k in the tour whose move k -> k + 1 is blocked (could not be
  // avoided), and the first configuration found blocked on each.
  std::vector<int> blocked_moves;
  std::vector<std::string> blocked_reasons;
  int blocked_before = 0;  // blocked moves of the input order
  int64_t moves_checked = 0;
  int64_t configurations_checked = 0;
  std::vector<double> velocities;  // the velocities used, per joint
  double seconds = 0.0;

  // One line. With `not_checked` (why the moves were not checked, e.g.
  // "no --cell"), it says so in place of the counts of moves checked:
  // "...; no --cell: moves not checked, ...".
  std::string BriefReport(const std::string& not_checked = "") const;
};

// The estimated time of the move a -> b (s).
double MoveTime(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                const std::vector<double>& velocities);

// Orders the rows of `poses` (num_poses x num_joints, SI). `checker` may be
// null (or without collision geometry) when options.check_moves is false.
bool OrderTour(const CellChecker* checker, const Eigen::MatrixXd& poses,
               const TourOptions& options, TourSummary* summary);

// Checks the straight move a -> b at options' resolution; false when a
// configuration on it collides (*verdict says how).
bool MoveIsFree(const CellChecker& checker, const Eigen::VectorXd& a,
                const Eigen::VectorXd& b, const TourOptions& options,
                CellChecker::Workspace* workspace, PoseVerdict* verdict,
                int64_t* configurations = nullptr);

}  // namespace activecal

#endif  // ACTIVECAL_CELL_TOUR_H_
