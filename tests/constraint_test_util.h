// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Helpers shared by the tests of fixed points and planes (measurements
// without a tracker).

#ifndef ACTIVECAL_TESTS_CONSTRAINT_TEST_UTIL_H_
#define ACTIVECAL_TESTS_CONSTRAINT_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "activecal/core/free_set.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

// A shipped URDF's chain to `tip` with a ball (a stylus tip, a socket ball)
// off the flange, at (0.02, -0.01, 0.1) m in the marker frame.
inline RobotModel LoadShippedWithBall(const std::string& file,
                                      const std::string& tip) {
  UrdfChainOptions chain;
  chain.tip_link = tip;
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(LoadUrdfRobot(std::string(ACTIVECAL_DATA_DIR) + "/" + file, chain,
                            &robot, &error))
      << error;
  RobotModel m = robot.model;
  m.nominal.segment(m.block_offset(m.marker_block(0)), 3) << 0.02, -0.01, 0.1;
  return m;
}

// The names of the parameters a reduction held, as a set (the library's
// HeldNames, in their order).
inline std::set<std::string> HeldNameSet(
    const std::vector<HeldParameter>& held) {
  const std::vector<std::string> names = HeldNames(held);
  return std::set<std::string>(names.begin(), names.end());
}

}  // namespace activecal

#endif  // ACTIVECAL_TESTS_CONSTRAINT_TEST_UTIL_H_
