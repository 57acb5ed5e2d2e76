// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The candidate pool of Sun & Hollerbach, Section V-B: every joint range
// sampled at evenly spaced levels, both ends included, and every combination
// of levels taken as a pose.
//
// A pose's index reads its level digits as a mixed-radix number, joint 1
// most significant: with 5 levels per joint, levels (0,3,0,4,1,2) are
// 3*5^4 + 4*5^2 + 1*5 + 2 = 1982. Indices are 0-based.

#ifndef ACTIVECAL_CORE_LATTICE_H_
#define ACTIVECAL_CORE_LATTICE_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

class JointLattice {
 public:
  JointLattice() = default;

  // A lattice over the model's joint ranges with levels[j] values on joint j
  // (every level count >= 2; a prismatic joint's range finite; a revolute
  // joint without a finite range takes one turn as joint_sampling.h's
  // PoolJointRange: a continuous joint -pi + 2 pi k / levels). Returns
  // false with a message on bad input.
  static bool Create(const RobotModel& model, const std::vector<int>& levels,
                     JointLattice* lattice, std::string* error);
  // The same number of levels on every joint.
  static bool Create(const RobotModel& model, int levels, JointLattice* lattice,
                     std::string* error);

  int num_joints() const { return static_cast<int>(levels_.size()); }
  int64_t size() const { return size_; }
  const std::vector<int>& levels() const { return levels_; }

  std::vector<int> Levels(int64_t index) const;
  int64_t Index(const std::vector<int>& levels) const;
  double Angle(int joint, int level) const;
  Eigen::VectorXd JointValues(int64_t index) const;
  // All poses, one row each (size() x num_joints()).
  Eigen::MatrixXd AllJointValues() const;

  // True for a revolute joint whose range spans a full turn so that levels
  // with both ends included would repeat an angle (limits of +-360 deg):
  // its levels then cover one turn from the lower limit, upper end left out
  // (min + 2 pi k / levels), every one a different pose. Also true for a
  // continuous joint (from -pi).
  bool one_turn(int joint) const { return one_turn_[joint] != 0; }
  // What a user is told about each one-turn joint of a lattice over `model`,
  // one line each (no prefix), e.g. "joint 4 (j3) has no limits: its 2
  // levels cover one turn from -180 deg (a continuous joint)".
  std::vector<std::string> OneTurnNotes(const RobotModel& model) const;

 private:
  std::vector<int> levels_;
  std::vector<double> min_, max_;
  std::vector<char> one_turn_;
  int64_t size_ = 0;
};

}  // namespace activecal

#endif  // ACTIVECAL_CORE_LATTICE_H_
