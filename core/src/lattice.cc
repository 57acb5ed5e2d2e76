// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/lattice.h"

#include <cmath>
#include <sstream>

#include "activecal/core/joint_sampling.h"

namespace activecal {

namespace {

// True when two of the `levels` values of revolute joint j, spread over its
// range with both ends included, are the same angle modulo 2 pi (e.g. -360,
// 0, 360 deg): the lattice would list one pose several times.
bool RepeatsAnAngle(const Link& l, int levels) {
  constexpr double kTolerance = 1e-9;  // rad
  auto value = [&](int k) {
    if (k == levels - 1) return l.joint_max;
    return l.joint_min + (l.joint_max - l.joint_min) * k / (levels - 1);
  };
  // Levels can only coincide when the range reaches a full turn.
  if (l.joint_max - l.joint_min < 2 * M_PI - kTolerance) return false;
  for (int a = 0; a < levels; ++a) {
    for (int b = a + 1; b < levels; ++b) {
      if (std::abs(std::remainder(value(b) - value(a), 2 * M_PI)) <=
          kTolerance) {
        return true;
      }
    }
  }
  return false;
}

}  // namespace

bool JointLattice::Create(const RobotModel& model,
                          const std::vector<int>& levels, JointLattice* lattice,
                          std::string* error) {
  std::ostringstream msg;
  if (static_cast<int>(levels.size()) != model.num_joints()) {
    msg << "lattice: expected " << model.num_joints()
        << " level counts (one per joint), got " << levels.size();
  }
  double size = 1.0;
  for (size_t j = 0; j < levels.size() && msg.tellp() == 0; ++j) {
    const Link& l = model.links[j];
    if (levels[j] < 2) {
      msg << "lattice: joint " << j + 1 << " needs at least 2 levels (both "
          << "ends of its range), got " << levels[j];
    } else if ((!std::isfinite(l.joint_min) || !std::isfinite(l.joint_max)) &&
               l.joint_type != JointType::kRevolute) {
      msg << "lattice: joint " << j + 1 << " (" << model.block_name(j + 1)
          << ") has no finite range";
    }
    size *= levels[j];
  }
  if (msg.tellp() == 0 && size > 1e9) {
    msg << "lattice: " << size << " poses is more than the 1e9 supported";
  }
  if (msg.tellp() != 0) {
    if (error) *error = msg.str();
    return false;
  }
  lattice->levels_ = levels;
  lattice->min_.clear();
  lattice->max_.clear();
  lattice->one_turn_.clear();
  for (size_t j = 0; j < model.links.size(); ++j) {
    const Link& l = model.links[j];
    if (!std::isfinite(l.joint_min) || !std::isfinite(l.joint_max)) {
      // A continuous joint (or one bounded on one side): one turn, as the
      // sampled pools (joint_sampling.h).
      double low = 0, width = 0;
      bool one_turn = false;
      PoolJointRange(model, static_cast<int>(j), &low, &width, &one_turn,
                     nullptr);
      lattice->min_.push_back(low);
      lattice->max_.push_back(low + width);
      lattice->one_turn_.push_back(1);
      continue;
    }
    lattice->min_.push_back(l.joint_min);
    lattice->max_.push_back(l.joint_max);
    lattice->one_turn_.push_back(l.joint_type == JointType::kRevolute &&
                                 RepeatsAnAngle(l, levels[j]));
  }
  lattice->size_ = static_cast<int64_t>(size);
  return true;
}

bool JointLattice::Create(const RobotModel& model, int levels,
                          JointLattice* lattice, std::string* error) {
  return Create(model, std::vector<int>(model.num_joints(), levels), lattice,
                error);
}

std::vector<int> JointLattice::Levels(int64_t index) const {
  std::vector<int> out(levels_.size());
  for (int j = num_joints() - 1; j >= 0; --j) {
    out[j] = static_cast<int>(index % levels_[j]);
    index /= levels_[j];
  }
  return out;
}

int64_t JointLattice::Index(const std::vector<int>& levels) const {
  int64_t index = 0;
  for (int j = 0; j < num_joints(); ++j) index = index * levels_[j] + levels[j];
  return index;
}

double JointLattice::Angle(int joint, int level) const {
  if (one_turn_[joint]) {
    return min_[joint] + 2 * M_PI * level / levels_[joint];
  }
  if (level == levels_[joint] - 1) return max_[joint];
  return min_[joint] +
         (max_[joint] - min_[joint]) * level / (levels_[joint] - 1);
}

Eigen::VectorXd JointLattice::JointValues(int64_t index) const {
  const std::vector<int> lv = Levels(index);
  Eigen::VectorXd q(num_joints());
  for (int j = 0; j < num_joints(); ++j) q[j] = Angle(j, lv[j]);
  return q;
}

Eigen::MatrixXd JointLattice::AllJointValues() const {
  Eigen::MatrixXd all(size_, num_joints());
  for (int64_t i = 0; i < size_; ++i) all.row(i) = JointValues(i).transpose();
  return all;
}

std::vector<std::string> JointLattice::OneTurnNotes(
    const RobotModel& model) const {
  std::vector<std::string> notes;
  for (int j = 0; j < num_joints(); ++j) {
    if (!one_turn(j)) continue;
    const Link& l = model.links[j];
    const bool continuous =
        !std::isfinite(l.joint_min) || !std::isfinite(l.joint_max);
    std::ostringstream s;
    s.precision(6);
    s << "joint " << j + 1 << " (" << model.block_name(j + 1) << ") "
      << (continuous ? "has no limits" : "spans a full turn") << ": its "
      << levels_[j] << " levels cover one turn from "
      << Angle(j, 0) * 180 / M_PI << " deg ("
      << (continuous ? "a continuous joint" : "both ends would repeat a pose")
      << ")";
    notes.push_back(s.str());
  }
  return notes;
}

}  // namespace activecal
