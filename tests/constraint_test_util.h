// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Helpers shared by the tests of fixed points and planes (measurements
// without a tracker).

#ifndef ACTIVECAL_TESTS_CONSTRAINT_TEST_UTIL_H_
#define ACTIVECAL_TESTS_CONSTRAINT_TEST_UTIL_H_

#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "activecal/core/free_set.h"
#include "activecal/core/robot_model.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/residuals/measurement_residual.h"

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

// The full parameter set reduced (ReduceParameterSet, weight 1) on the data
// at the model's nominal values: the held parameters, the free set in *free.
inline std::vector<HeldParameter> HeldOfFullSet(
    const RobotModel& model, const std::vector<Measurement>& data,
    FreeSet* free) {
  Eigen::VectorXd point = model.nominal;
  std::vector<HeldParameter> held;
  std::string error;
  EXPECT_TRUE(ReduceParameterSet(model, ParameterSet::kFull, data, 1.0, &point,
                                 free, &held, &error))
      << error;
  return held;
}

// The residual of the measurement m on (a copy of) the model.
inline std::unique_ptr<ceres::CostFunction> ResidualOf(const RobotModel& model,
                                                       const Measurement& m) {
  return std::unique_ptr<ceres::CostFunction>(MeasurementResidual::Create(
      std::make_shared<const RobotModel>(model), m));
}

// A residual's parameter blocks: the model's blocks in *x, then `extra`
// (the unknowns of a constraint: a point, a plane) in order.
inline std::vector<double*> BlocksWith(const RobotModel& model,
                                       Eigen::VectorXd* x,
                                       const std::vector<double*>& extra) {
  std::vector<double*> blocks;
  for (int b = 0; b < model.num_blocks(); ++b) {
    blocks.push_back(x->data() + model.block_offset(b));
  }
  blocks.insert(blocks.end(), extra.begin(), extra.end());
  return blocks;
}

// Room for the Jacobian of each parameter block of the cost (row-major,
// num_residuals rows), and the pointers to it in *ptrs.
inline std::vector<std::vector<double>> JacobianStorage(
    const ceres::CostFunction& cost, std::vector<double*>* ptrs) {
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  std::vector<std::vector<double>> jac(sizes.size());
  ptrs->clear();
  for (size_t b = 0; b < sizes.size(); ++b) {
    jac[b].resize(cost.num_residuals() * sizes[b]);
    ptrs->push_back(jac[b].data());
  }
  return jac;
}

// The names of the parameters a reduction held, as a set (the library's
// HeldNames, in their order).
inline std::set<std::string> HeldNameSet(
    const std::vector<HeldParameter>& held) {
  const std::vector<std::string> names = HeldNames(held);
  return std::set<std::string>(names.begin(), names.end());
}

// Checks what constraint rows hold beyond position rows at the same joints:
// `held` (the constraint rows' holds) holds every name of `position_held`
// and besides the base's 6 (which the positions do not hold; each for "has
// no effect on these measurements") exactly one parameter, a length (the
// scale the constraints cannot see). Returns that length's name ("" when
// the extra holds are not one).
inline std::string ExpectBaseAndOneLengthHeldBeyond(
    const RobotModel& model, const std::set<std::string>& position_held,
    const std::vector<HeldParameter>& held) {
  const std::set<std::string> names = HeldNameSet(held);
  for (const char* b : {"B.x", "B.y", "B.z", "B.rx", "B.ry", "B.rz"}) {
    EXPECT_EQ(position_held.count(b), 0u) << b;
    EXPECT_EQ(names.count(b), 1u) << b;
  }
  for (const HeldParameter& h : held) {
    if (h.name.rfind("B.", 0) == 0) {
      EXPECT_EQ(h.reason, "has no effect on these measurements") << h.name;
    }
  }
  for (const std::string& name : position_held) {
    EXPECT_EQ(names.count(name), 1u) << name;
  }
  std::vector<std::string> extra;
  for (const std::string& name : names) {
    if (!position_held.count(name) && name.rfind("B.", 0) != 0) {
      extra.push_back(name);
    }
  }
  EXPECT_EQ(extra.size(), 1u);
  if (extra.size() != 1) return "";
  EXPECT_EQ(model.Kind(model.ParameterIndex(extra[0])), ParameterKind::kLength)
      << extra[0];
  return extra[0];
}

}  // namespace activecal

#endif  // ACTIVECAL_TESTS_CONSTRAINT_TEST_UTIL_H_
