// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The analytic point Jacobian (core/point_jacobian.h) against the Ceres
// auto-diff residual's Jacobian and central differences, on every
// convention: standard and modified DH, Hayati, URDF joints (revolute about
// tilted axes, prismatic), a frame base, gains, a tip transform and several
// markers; and the pool path that uses it.

#include "activecal/core/point_jacobian.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/residuals/jacobians.h"
#include "test_util.h"

namespace activecal {
namespace {

// Every parameter free (the check is about derivatives, not
// identifiability), values moved off the nominal so that no angle is a
// round number.
RobotModel AllFree(RobotModel m, Random* random) {
  for (int i = 0; i < m.num_parameters(); ++i) {
    m.SetFree(i, true);
    if (!m.Validate(nullptr)) m.SetFree(i, false);  // e.g. the base's gain
  }
  for (int i : m.FreeParameterIndices()) {
    m.nominal[i] += 0.05 * (random->Uniform() - 0.5);
  }
  return m;
}

RobotModel ModifiedDhRevolute() {
  RobotModel m = testing::MixedModel();
  m.links[2].joint_type = JointType::kRevolute;
  m.links[2].joint_min = -2.0;
  m.links[2].joint_max = 2.0;
  return m;
}

RobotModel UrdfWithFixedAndPrismaticStart() {
  RobotModel m = testing::UrdfStyleModel();
  m.links[0].joint_type = JointType::kPrismatic;
  m.links[0].joint_min = 0.0;
  m.links[0].joint_max = 0.5;
  return m;
}

void ExpectAnalyticEqualsAutoDiff(const RobotModel& model, int trials,
                                  uint64_t seed) {
  Random random(seed);
  const RobotModel m = AllFree(model, &random);
  std::string error;
  ASSERT_TRUE(m.Validate(&error)) << error;
  const int p = m.num_free();
  const std::vector<const double*> blocks = BlockPointers(m, m.nominal.data());
  PointJacobianWorkspace workspace(m);
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q = testing::RandomJoints(m, &random);
    for (int marker = 0; marker < m.num_markers(); ++marker) {
      Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor> analytic(3, p);
      MeasuredPointJacobian(m, blocks.data(), q.data(), marker, &workspace,
                            analytic.data());
      Measurement meas;
      meas.joints = q;
      meas.marker = marker;
      Eigen::MatrixXd autodiff;
      ASSERT_TRUE(
          MeasurementJacobian(m, m.nominal, meas, 1.0, &autodiff, &error))
          << error;
      const double scale = std::max(1.0, autodiff.cwiseAbs().maxCoeff());
      EXPECT_LE((analytic - autodiff).cwiseAbs().maxCoeff(), 1e-12 * scale)
          << m.name << " trial " << trial << " marker " << marker
          << "\nanalytic\n"
          << analytic << "\nautodiff\n"
          << autodiff;
      // Central differences of the point itself (an independent check of
      // the derivative both compute).
      const std::vector<int> free = m.FreeParameterIndices();
      for (int j = 0; j < p; ++j) {
        const double h = 1e-6;
        Eigen::VectorXd plus = m.nominal, minus = m.nominal;
        plus[free[j]] += h;
        minus[free[j]] -= h;
        const Eigen::Vector3d diff = (MeasuredPoint(m, plus, q, marker) -
                                      MeasuredPoint(m, minus, q, marker)) /
                                     (2 * h);
        EXPECT_LE((diff - analytic.col(j)).cwiseAbs().maxCoeff(), 1e-7)
            << m.name << " column " << j;
      }
    }
  }
}

TEST(PointJacobianTest, PumaStandardDh) {
  ExpectAnalyticEqualsAutoDiff(Puma560PaperModel(), 20, 1);
}

TEST(PointJacobianTest, MixedDhHayatiModifiedPrismaticGains) {
  ExpectAnalyticEqualsAutoDiff(testing::MixedModel(), 20, 2);
}

TEST(PointJacobianTest, ModifiedDhRevolute) {
  ExpectAnalyticEqualsAutoDiff(ModifiedDhRevolute(), 20, 3);
}

TEST(PointJacobianTest, UrdfJointsFrameBaseTipAndTwoMarkers) {
  ExpectAnalyticEqualsAutoDiff(testing::UrdfStyleModel(), 20, 4);
}

TEST(PointJacobianTest, UrdfPrismaticFirstJoint) {
  ExpectAnalyticEqualsAutoDiff(UrdfWithFixedAndPrismaticStart(), 20, 5);
}

using Row3 = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>;

// The point Jacobian of the model at parameters x and joints q through the
// workspace `reused` (returned), and through a fresh workspace (*fresh).
Row3 JacobianReusedAndFresh(const RobotModel& model, const Eigen::VectorXd& x,
                            const Eigen::VectorXd& q,
                            PointJacobianWorkspace* reused, Row3* fresh) {
  const std::vector<const double*> blocks = BlockPointers(model, x.data());
  Row3 a(3, model.num_free());
  fresh->resize(3, model.num_free());
  MeasuredPointJacobian(model, blocks.data(), q.data(), 0, reused, a.data());
  PointJacobianWorkspace workspace(model);
  MeasuredPointJacobian(model, blocks.data(), q.data(), 0, &workspace,
                        fresh->data());
  return a;
}

// A workspace keeps the per-block trigonometry of URDF links between calls:
// when the parameters change (one angle of one link, or every value), the
// Jacobian is the one a fresh workspace computes, bit for bit, and the
// auto-diff one.
TEST(PointJacobianTest, UrdfCacheFollowsTheParameters) {
  Random random(9);
  const RobotModel m = AllFree(testing::UrdfStyleModel(), &random);
  Eigen::VectorXd other = m.nominal;
  other[m.block_offset(2) + kUrdfRy] += 0.01;  // one angle of one link
  Eigen::VectorXd moved = m.nominal;
  for (int i : m.FreeParameterIndices()) moved[i] += 0.02;
  PointJacobianWorkspace reused(m);
  for (int call = 0; call < 9; ++call) {
    const Eigen::VectorXd& params =
        call % 3 == 0 ? m.nominal : (call % 3 == 1 ? other : moved);
    const Eigen::VectorXd q = testing::RandomJoints(m, &random);
    Row3 b;
    const Row3 a = JacobianReusedAndFresh(m, params, q, &reused, &b);
    EXPECT_EQ(a, b) << "call " << call;
    Measurement meas;
    meas.joints = q;
    Eigen::MatrixXd autodiff;
    std::string error;
    ASSERT_TRUE(MeasurementJacobian(m, params, meas, 1.0, &autodiff, &error));
    EXPECT_LE((a - autodiff).cwiseAbs().maxCoeff(),
              1e-12 * std::max(1.0, autodiff.cwiseAbs().maxCoeff()))
        << "call " << call;
  }
}

// The cache holds what depends on the link too (its nominal origin and
// axis): a workspace reused for a model that differs only there, or for a
// block of the same values but other signs of zero, gives the fresh
// workspace's bits.
TEST(PointJacobianTest, UrdfCacheFollowsTheLinkAndTheBits) {
  Random random(10);
  const RobotModel m = AllFree(testing::UrdfStyleModel(), &random);
  RobotModel m2 = m;
  for (Link& link : m2.links) {
    if (link.convention != LinkConvention::kUrdf) continue;
    link.origin_rotation *= RpyRotation(0.1, -0.2, 0.3);
    link.axis = Eigen::Vector3d(link.axis + Eigen::Vector3d(0.1, 0.2, 0.3))
                    .normalized();
  }
  ASSERT_TRUE(m2.Validate(nullptr));
  const int p = m.num_free();
  PointJacobianWorkspace reused(m);
  auto expect_fresh = [&](const RobotModel& model, const Eigen::VectorXd& x,
                          const char* what) {
    const Eigen::VectorXd q = testing::RandomJoints(model, &random);
    Row3 b;
    const Row3 a = JacobianReusedAndFresh(model, x, q, &reused, &b);
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), sizeof(double) * 3 * p))
        << what;
  };
  expect_fresh(m, m.nominal, "model");
  expect_fresh(m2, m2.nominal, "the same blocks, another origin and axis");
  // Zero angles of either sign.
  Eigen::VectorXd plus = m.nominal, minus = m.nominal;
  for (int b = 0; b < m.num_blocks(); ++b) {
    if (m.is_marker_block(b) || m.link(b).convention != LinkConvention::kUrdf) {
      continue;
    }
    for (int k : {kUrdfRx, kUrdfRy, kUrdfRz}) {
      plus[m.block_offset(b) + k] = 0.0;
      minus[m.block_offset(b) + k] = -0.0;
    }
  }
  expect_fresh(m, plus, "+0");
  expect_fresh(m, minus, "-0");
}

// Only free columns, in free-parameter order, with some parameters held.
TEST(PointJacobianTest, FreeColumnsOnly) {
  RobotModel m = testing::UrdfStyleModel();
  for (int i = 0; i < m.num_parameters(); i += 3) m.SetFree(i, false);
  Random random(6);
  const Eigen::VectorXd q = testing::RandomJoints(m, &random);
  PointJacobianWorkspace workspace(m);
  const std::vector<const double*> blocks = BlockPointers(m, m.nominal.data());
  Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor> analytic(
      3, m.num_free());
  MeasuredPointJacobian(m, blocks.data(), q.data(), 0, &workspace,
                        analytic.data());
  Measurement meas;
  meas.joints = q;
  Eigen::MatrixXd autodiff;
  std::string error;
  ASSERT_TRUE(MeasurementJacobian(m, m.nominal, meas, 1.0, &autodiff, &error));
  EXPECT_LE((analytic - autodiff).cwiseAbs().maxCoeff(), 1e-12);
}

// The pool path: the analytic and the auto-diff pool Jacobians agree, and
// the analytic one does not depend on the thread count.
TEST(PointJacobianTest, PoolJacobiansAnalyticEqualsAutoDiff) {
  const RobotModel m = testing::MixedModel();
  Random random(7);
  const Eigen::MatrixXd joints = testing::RandomJointRows(m, 500, &random);
  PoolJacobianOptions options;
  options.num_threads = 1;
  RowMatrixXd analytic, analytic2, autodiff;
  std::string error;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &analytic, &error));
  options.num_threads = 2;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &analytic2, &error));
  options.analytic = false;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &autodiff, &error));
  EXPECT_EQ(analytic, analytic2);
  EXPECT_LE((analytic - autodiff).cwiseAbs().maxCoeff(), 1e-12);
}

// The kernel's batches: poses given column-major (a pool's layout) or one
// after another, in one call or split, give the per-pose bits; a pose's
// Jacobian does not depend on its neighbours. On every convention (DH,
// Hayati, modified DH, prismatic joints, gains; URDF joints, frame base,
// tip, two markers).
TEST(PointJacobianTest, KernelBatchesGiveThePerPoseBits) {
  for (const RobotModel& model :
       {testing::MixedModel(), testing::UrdfStyleModel()}) {
    Random random(11);
    const RobotModel m = AllFree(model, &random);
    const int p = m.num_free();
    const int n = m.num_joints();
    constexpr int kPoses = 37;
    Eigen::MatrixXd joints(kPoses, n);  // column-major, as PoolJacobians
    for (int i = 0; i < kPoses; ++i) {
      joints.row(i) = testing::RandomJoints(m, &random).transpose();
    }
    const Eigen::MatrixXd by_pose = joints.transpose();  // pose after pose
    const std::vector<const double*> blocks =
        BlockPointers(m, m.nominal.data());
    for (int marker = 0; marker < m.num_markers(); ++marker) {
      const PointJacobianKernel kernel(m, blocks.data(), marker);
      ASSERT_EQ(kernel.num_columns(), p);
      std::vector<double> whole(3 * p * kPoses), split(3 * p * kPoses),
          rows(3 * p * kPoses), single(3 * p);
      kernel.Evaluate(kPoses, joints.data(), 1, kPoses, whole.data());
      kernel.Evaluate(5, joints.data(), 1, kPoses, split.data());
      kernel.Evaluate(kPoses - 5, joints.data() + 5, 1, kPoses,
                      split.data() + 3 * p * 5);
      kernel.Evaluate(kPoses, by_pose.data(), n, 1, rows.data());
      EXPECT_EQ(0, std::memcmp(whole.data(), split.data(),
                               sizeof(double) * whole.size()));
      EXPECT_EQ(0, std::memcmp(whole.data(), rows.data(),
                               sizeof(double) * whole.size()));
      PointJacobianWorkspace workspace(m);
      for (int i = 0; i < kPoses; ++i) {
        const Eigen::VectorXd q = joints.row(i).transpose();
        MeasuredPointJacobian(m, blocks.data(), q.data(), marker, &workspace,
                              single.data());
        EXPECT_EQ(0, std::memcmp(single.data(), whole.data() + 3 * p * i,
                                 sizeof(double) * 3 * p))
            << m.name << " marker " << marker << " pose " << i;
      }
    }
  }
}

// Free entries that do not move the measured point (another marker's
// block, the measured marker's angles) are zero columns, and the others
// are the auto-diff ones: a model with both markers' blocks all free.
TEST(PointJacobianTest, OtherMarkersAndMarkerAnglesAreZeroColumns) {
  Random random(12);
  const RobotModel m = AllFree(testing::UrdfStyleModel(), &random);
  ASSERT_GE(m.num_markers(), 2);
  const std::vector<const double*> blocks = BlockPointers(m, m.nominal.data());
  const std::vector<int> free = m.FreeParameterIndices();
  const Eigen::VectorXd q = testing::RandomJoints(m, &random);
  for (int marker = 0; marker < 2; ++marker) {
    const PointJacobianKernel kernel(m, blocks.data(), marker);
    Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor> J(3,
                                                                m.num_free());
    kernel.Evaluate(1, q.data(), 1, 1, J.data());
    int zero = 0;
    for (int j = 0; j < m.num_free(); ++j) {
      int within = 0;
      const int block = m.BlockOf(free[j], &within);
      if (!m.is_marker_block(block)) continue;
      if (block != m.marker_block(marker) || within >= 3) {
        EXPECT_EQ(J.col(j).cwiseAbs().maxCoeff(), 0.0) << "column " << j;
        ++zero;
      } else {
        EXPECT_GT(J.col(j).norm(), 0.5) << "column " << j;  // a rotation's
      }
    }
    EXPECT_GE(zero, 3);
  }
}

// The pool's marker option: PoolJacobians for marker 1 is the auto-diff
// pool Jacobian of marker 1 (and not marker 0's); a marker out of range is
// an error naming it.
TEST(PointJacobianTest, PoolJacobiansOfTheSecondMarker) {
  const RobotModel m = testing::UrdfStyleModel();
  ASSERT_GE(m.num_markers(), 2);
  Random random(13);
  const Eigen::MatrixXd joints = testing::RandomJointRows(m, 40, &random);
  PoolJacobianOptions options;
  options.num_threads = 1;
  options.marker = 1;
  RowMatrixXd analytic, autodiff, first;
  std::string error;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &analytic, &error));
  options.analytic = false;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &autodiff, &error));
  options.marker = 0;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &first, &error));
  EXPECT_LE((analytic - autodiff).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT((analytic - first).cwiseAbs().maxCoeff(), 1e-6);
  options.marker = m.num_markers();
  EXPECT_FALSE(PoolJacobians(m, m.nominal, joints, options, &analytic, &error));
  EXPECT_NE(error.find("marker must be in [0, 1], got 2"), std::string::npos)
      << error;
}

// The pool's range check (done without building messages for valid poses)
// still rejects what CheckJointValues rejects, naming the pose: a value past
// a joint's range, NaN, and infinity; a value at a range end passes.
TEST(PointJacobianTest, PoolJacobiansRangeCheck) {
  const RobotModel m = Puma560PaperModel();
  ASSERT_TRUE(std::isfinite(m.links[1].joint_max));
  Eigen::MatrixXd joints = Eigen::MatrixXd::Zero(3, m.num_joints());
  joints(0, 1) = m.links[1].joint_max;
  joints(2, 4) = m.links[4].joint_min;
  RowMatrixXd out;
  std::string error;
  EXPECT_TRUE(
      PoolJacobians(m, m.nominal, joints, PoolJacobianOptions(), &out, &error))
      << error;
  for (const double bad :
       {m.links[1].joint_max + 1e-3, std::numeric_limits<double>::quiet_NaN(),
        -std::numeric_limits<double>::infinity()}) {
    Eigen::MatrixXd j = joints;
    j(1, 1) = bad;
    error.clear();
    EXPECT_FALSE(
        PoolJacobians(m, m.nominal, j, PoolJacobianOptions(), &out, &error));
    EXPECT_NE(error.find("pool pose 1: joint 2"), std::string::npos) << error;
  }
  // Measured readings: a tolerance beyond the range (what the Python
  // module's jacobian passes, as forward accepts such readings).
  Eigen::MatrixXd beyond = joints;
  beyond(1, 1) = m.links[1].joint_max + 1e-3;
  PoolJacobianOptions options;
  options.joint_tolerance_rad = 2e-3;
  EXPECT_TRUE(PoolJacobians(m, m.nominal, beyond, options, &out, &error))
      << error;
  beyond(1, 1) = m.links[1].joint_max + 3e-3;
  EXPECT_FALSE(PoolJacobians(m, m.nominal, beyond, options, &out, &error));
  EXPECT_NE(error.find("by more than"), std::string::npos) << error;
}

}  // namespace
}  // namespace activecal
