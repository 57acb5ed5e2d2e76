// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// What the simulated-session helpers (make_point_measurements,
// make_plane_measurements) share: the robot read from a URDF and the truth
// they simulate with, errors printed to stderr.

#ifndef ACTIVECAL_TESTS_SIMULATED_SESSION_H_
#define ACTIVECAL_TESTS_SIMULATED_SESSION_H_

#include <Eigen/Core>
#include <cstdint>
#include <cstdio>
#include <string>

#include "activecal/core/robot_model.h"
#include "activecal/core/simulation.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {
namespace testing {

// The chain of `urdf` from its root to `tip` into *robot; false (the
// error printed) if it cannot be read.
inline bool LoadSessionRobot(const char* urdf, const char* tip,
                             RobotDescription* robot) {
  UrdfChainOptions chain;
  chain.tip_link = tip;
  std::string error;
  if (!LoadUrdfRobot(urdf, chain, robot, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return false;
  }
  return true;
}

// The truth of a session: the model's nominal with a ball 0.02, -0.01,
// 0.1 m off the tip and every free parameter moved by 0.5 mm / 0.5 mrad
// (PerturbParameters, `seed`); false (the error printed) on a failure.
inline bool SessionTruth(const RobotModel& model, uint64_t seed,
                         Eigen::VectorXd* truth) {
  Eigen::VectorXd values = model.nominal;
  values.segment(model.block_offset(model.marker_block(0)), 3) << 0.02, -0.01,
      0.1;
  std::string error;
  if (!PerturbParameters(model, values, 0.5e-3, 0.5e-3, seed, truth, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return false;
  }
  return true;
}

}  // namespace testing
}  // namespace activecal

#endif  // ACTIVECAL_TESTS_SIMULATED_SESSION_H_
