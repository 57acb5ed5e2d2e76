// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Simulated fixed-point sessions (point_constraints.h): a robot whose
// marker is placed in sockets from several configurations each, for trying
// a calibration without a tracker and for testing it. Reproducible for a
// seed.

#ifndef ACTIVECAL_CORE_POINT_SIMULATION_H_
#define ACTIVECAL_CORE_POINT_SIMULATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

struct PointSimulationOptions {
  int num_points = 3;  // sockets, labelled "<prefix><k>", k = 0, 1, ...
  int per_point = 25;  // configurations reaching each socket
  std::string prefix = "hole_";
  // Repeatability of a placement: each placement lands off the socket by
  // a Gaussian of this standard deviation per axis (m).
  double placement_m = 0.0;
  // Each configuration starts as a socket's reference configuration
  // moved by a uniform draw of +-spread_rad / 2 on every joint, then is
  // pulled back onto the socket (ReachPoint).
  double spread_rad = 1.2;
  int marker = 0;
};

// `options.per_point` configurations at each of `options.num_points`
// sockets the robot at `true_parameters` (full vector) reaches: a socket is
// where a configuration near the middle of the joint ranges puts the
// marker. Every configuration lies inside the joint ranges. *points: the
// sockets' true coordinates (base frame). False with a message when a
// socket cannot be reached from enough configurations.
bool SimulatePointMeasurements(const RobotModel& model,
                               const Eigen::VectorXd& true_parameters,
                               const PointSimulationOptions& options,
                               uint64_t seed, std::vector<Measurement>* rows,
                               std::vector<Eigen::Vector3d>* points,
                               std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_POINT_SIMULATION_H_
