// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/point_simulation.h"

#include <algorithm>

#include "activecal/core/kinematics.h"
#include "activecal/core/point_constraints.h"
#include "activecal/core/random.h"

namespace activecal {

bool SimulatePointMeasurements(const RobotModel& model,
                               const Eigen::VectorXd& true_parameters,
                               const PointSimulationOptions& options,
                               uint64_t seed, std::vector<Measurement>* rows,
                               std::vector<Eigen::Vector3d>* points,
                               std::string* error) {
  if (options.num_points < 1 || options.per_point < 2) {
    if (error) {
      *error = "num_points must be >= 1 and per_point >= 2, got " +
               std::to_string(options.num_points) + " and " +
               std::to_string(options.per_point);
    }
    return false;
  }
  if (!(options.placement_m >= 0) || !(options.spread_rad >= 0)) {
    if (error) *error = "placement_m and spread_rad must be >= 0";
    return false;
  }
  if (options.marker < 0 || options.marker >= model.num_markers()) {
    if (error) *error = "marker out of range";
    return false;
  }
  Random random(seed);
  rows->clear();
  points->clear();
  const int n = model.num_joints();
  Eigen::VectorXd q_ref(n);
  for (int k = 0; k < options.num_points; ++k) {
    for (int j = 0; j < n; ++j) {
      const Link& l = model.links[j];
      q_ref[j] =
          0.5 * (std::max(l.joint_min, -2.0) + std::min(l.joint_max, 2.0)) +
          0.6 * (random.Uniform() - 0.5);
    }
    const Eigen::Vector3d c =
        MeasuredPoint(model, true_parameters, q_ref, options.marker);
    points->push_back(c);
    int made = 0;
    for (int attempt = 0;
         made < options.per_point && attempt < 100 * options.per_point;
         ++attempt) {
      Eigen::VectorXd q = q_ref;
      for (int j = 0; j < n; ++j) {
        q[j] += options.spread_rad * (random.Uniform() - 0.5);
      }
      Eigen::Vector3d target = c;
      for (int a = 0; a < 3; ++a) {
        target[a] += options.placement_m * random.Gaussian();
      }
      if (!ReachPoint(model, true_parameters, options.marker, target, &q)) {
        continue;
      }
      if (!model.CheckJointValues(q, nullptr)) continue;
      Measurement m;
      m.type = MeasurementType::kPoint;
      m.point = options.prefix + std::to_string(k);
      m.joints = q;
      m.marker = options.marker;
      rows->push_back(m);
      ++made;
    }
    if (made < options.per_point) {
      if (error) {
        *error = "socket " + std::to_string(k) + ": reached from " +
                 std::to_string(made) + " configurations of " +
                 std::to_string(options.per_point) + " asked for";
      }
      return false;
    }
  }
  return true;
}

}  // namespace activecal
