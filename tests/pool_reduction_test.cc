// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// ReduceForPool (calibration/pool_reduction.h): a parameter set reduced on
// the markers each pose of a pool sees. A UR10e (data/ur10e.urdf) with a
// second marker: seen at part of the pool its offsets stay free, seen at
// none they are held with a reason that says so; no masks is marker 0
// everywhere; a wrong mask count is refused.

#include "activecal/calibration/pool_reduction.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "activecal/core/joint_sampling.h"
#include "activecal/io/robot_loader.h"

namespace activecal {
namespace {

RobotModel Ur10eWithTwoMarkers() {
  RobotLoadOptions options;
  options.chain.tip_link = "tool0";
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(LoadRobot(std::string(ACTIVECAL_DATA_DIR) + "/ur10e.urdf",
                        options, &robot, &error))
      << error;
  RobotModel model = robot.model;
  Marker side = model.markers[0];
  side.name = "side";
  model.markers.push_back(side);
  const int n = static_cast<int>(model.nominal.size());
  model.nominal.conservativeResize(n + kMarkerBlockSize);
  model.nominal.tail(kMarkerBlockSize) << 0.05, 0, 0.03, 0, 0, 0;
  return model;
}

Eigen::MatrixXd Pool(const RobotModel& model, int n) {
  Eigen::MatrixXd joints;
  std::string error;
  EXPECT_TRUE(
      SampleJointValues(model, JointSampling::kSobol, n, 7, &joints, &error))
      << error;
  return joints;
}

bool IsFree(const RobotModel& model, const FreeSet& free,
            const std::string& name) {
  const int i = model.ParameterIndex(name);
  EXPECT_GE(i, 0) << name;
  return i >= 0 && free.Contains(i);
}

TEST(ReduceForPoolTest, AMarkerSeenOnPartOfThePoolKeepsItsOffsets) {
  const RobotModel model = Ur10eWithTwoMarkers();
  const Eigen::MatrixXd joints = Pool(model, 300);
  std::vector<uint32_t> masks(joints.rows(), 1u);
  for (size_t i = 0; i < masks.size(); i += 3) masks[i] = 2u;  // side only
  PoolReduction r;
  ASSERT_TRUE(ReduceForPool(model, ParameterSet::kFull, joints, &masks,
                            PoolReductionOptions(), &r))
      << r.message;
  for (const char* p :
       {"side.x", "side.y", "side.z", "tool.x", "tool.y", "tool.z"}) {
    EXPECT_TRUE(IsFree(model, r.free, p)) << p;
  }
  // Marker 0 alone (no masks): the second marker has no rows.
  PoolReduction first;
  ASSERT_TRUE(ReduceForPool(model, ParameterSet::kFull, joints, nullptr,
                            PoolReductionOptions(), &first));
  EXPECT_FALSE(IsFree(model, first.free, "side.x"));
  EXPECT_EQ(r.free.size(), first.free.size() + 3);
}

TEST(ReduceForPoolTest, AMarkerSeenNowhereIsHeldWithThatReason) {
  const RobotModel model = Ur10eWithTwoMarkers();
  const Eigen::MatrixXd joints = Pool(model, 300);
  const std::vector<uint32_t> masks(joints.rows(), 1u);
  PoolReduction r;
  ASSERT_TRUE(ReduceForPool(model, ParameterSet::kFull, joints, &masks,
                            PoolReductionOptions(), &r));
  int held_side = 0;
  for (const HeldParameter& h : r.held) {
    if (h.name.rfind("side.", 0) != 0) {
      EXPECT_EQ(h.reason.find("is seen at none"), std::string::npos) << h.name;
      continue;
    }
    ++held_side;
    EXPECT_EQ(h.reason,
              "marker 'side' is seen at none of the 300 poses of the pool");
  }
  EXPECT_EQ(held_side, 3);  // x, y, z (the angles are not in a position set)
  // Every pose seeing marker 0 only is what no masks plans.
  PoolReduction none;
  ASSERT_TRUE(ReduceForPool(model, ParameterSet::kFull, joints, nullptr,
                            PoolReductionOptions(), &none));
  EXPECT_TRUE(r.free == none.free);
  EXPECT_EQ(HeldNames(r.held), HeldNames(none.held));
  EXPECT_TRUE(r.point == none.point);
}

TEST(ReduceForPoolTest, SampleAndMaskCount) {
  const RobotModel model = Ur10eWithTwoMarkers();
  const Eigen::MatrixXd joints = Pool(model, 300);
  // A pool no larger than the sample: both subsets are the whole pool.
  PoolReductionOptions even;
  even.evenly_spaced = true;
  PoolReduction a, b;
  ASSERT_TRUE(ReduceForPool(model, ParameterSet::kFull, joints, nullptr,
                            PoolReductionOptions(), &a));
  ASSERT_TRUE(
      ReduceForPool(model, ParameterSet::kFull, joints, nullptr, even, &b));
  EXPECT_TRUE(a.free == b.free);
  ASSERT_EQ(a.held.size(), b.held.size());
  for (size_t k = 0; k < a.held.size(); ++k) {
    EXPECT_EQ(a.held[k].reason, b.held[k].reason);
  }
  const std::vector<uint32_t> short_masks(joints.rows() - 1, 3u);
  PoolReduction c;
  EXPECT_FALSE(ReduceForPool(model, ParameterSet::kFull, joints, &short_masks,
                             PoolReductionOptions(), &c));
  EXPECT_EQ(c.message, "299 marker masks for 300 poses");
}

TEST(ReduceModelForPoolTest, TheModelReducedAndWhatWasHeldOneLineEach) {
  RobotModel model = Ur10eWithTwoMarkers();
  const Eigen::MatrixXd joints = Pool(model, 300);
  const std::vector<uint32_t> masks(joints.rows(), 1u);
  PoolReductionOptions even;
  even.evenly_spaced = true;
  PoolReduction expected;
  ASSERT_TRUE(ReduceForPool(model, ParameterSet::kFull, joints, &masks, even,
                            &expected));
  std::string report = "before\n", error;
  PoolReduction reduction;
  ASSERT_TRUE(ReduceModelForPool(ParameterSet::kFull, joints, &masks, &model,
                                 &report, &error, &reduction))
      << error;
  EXPECT_TRUE(error.empty());
  EXPECT_TRUE(reduction.free == expected.free);
  EXPECT_EQ(model.FreeParameterIndices(), expected.free.Indices());
  ASSERT_FALSE(expected.held.empty());
  const HeldParameter& first = expected.held[0];
  EXPECT_EQ(report.rfind("before\n  --parameter_set=full: " + first.name +
                             " held fixed: " + first.reason + "\n",
                         0),
            0u);
  EXPECT_EQ(report,
            "before\n" + HeldFixedLines(ParameterSet::kFull, expected.held));
  EXPECT_EQ(HeldFixedLines(ParameterSet::kOffsets, {{"a", "why", {}}}),
            "  --parameter_set=offsets: a held fixed: why\n");
  EXPECT_EQ(HeldFixedLines(ParameterSet::kFull, {}), "");
  // A failure: the message named by the option, the model untouched.
  const std::vector<uint32_t> short_masks(joints.rows() - 1, 1u);
  const RobotModel reduced = model;
  report.clear();
  EXPECT_FALSE(ReduceModelForPool(ParameterSet::kFull, joints, &short_masks,
                                  &model, &report, &error));
  EXPECT_EQ(error, "--parameter_set=full: 299 marker masks for 300 poses");
  EXPECT_EQ(report, "");
  EXPECT_EQ(model.FreeParameterIndices(), reduced.FreeParameterIndices());
}

}  // namespace
}  // namespace activecal
