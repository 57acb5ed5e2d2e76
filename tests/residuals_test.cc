// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <string>

#include "activecal/calibration/pool_builder.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/residuals/measurement_residual.h"
#include "test_util.h"

namespace activecal {
namespace {

// The residual rows of measurement `m` at full parameters p (double
// evaluation of the cost function, no derivatives).
Eigen::VectorXd ResidualAt(const RobotModel& model, const Eigen::VectorXd& p,
                           const Measurement& m, double weight) {
  auto shared = std::make_shared<const RobotModel>(model);
  std::unique_ptr<ceres::CostFunction> cost(
      MeasurementResidual::Create(shared, m, weight));
  const std::vector<const double*> blocks = BlockPointers(model, p.data());
  Eigen::VectorXd r(m.dimension());
  EXPECT_TRUE(cost->Evaluate(blocks.data(), r.data(), nullptr));
  return r;
}

// Central differences of the residual with respect to each free parameter,
// step h scaled to the parameter.
Eigen::MatrixXd CentralDifferenceJacobian(const RobotModel& model,
                                          const Eigen::VectorXd& p,
                                          const Measurement& m, double weight) {
  const std::vector<int> free = model.FreeParameterIndices();
  Eigen::MatrixXd J(m.dimension(), free.size());
  for (size_t c = 0; c < free.size(); ++c) {
    const double h = 1e-6 * std::max(1.0, std::abs(p[free[c]]));
    Eigen::VectorXd plus = p, minus = p;
    plus[free[c]] += h;
    minus[free[c]] -= h;
    J.col(c) = (ResidualAt(model, plus, m, weight) -
                ResidualAt(model, minus, m, weight)) /
               (2 * h);
  }
  return J;
}

void CheckJacobiansAgainstCentralDifferences(const RobotModel& model,
                                             MeasurementType type,
                                             uint64_t seed, int marker = 0) {
  Random random(seed);
  const double weight = 0.3;
  for (int trial = 0; trial < 25; ++trial) {
    Eigen::VectorXd p = model.nominal;
    for (int i = 0; i < p.size(); ++i) p[i] += 0.1 * random.Gaussian();
    Measurement m;
    m.type = type;
    m.marker = marker;
    m.joints = testing::RandomJoints(model, &random);
    m.joints2 = testing::RandomJoints(model, &random);
    // Measured values near, not at, the prediction: the rotation log away
    // from zero exercises its general branch.
    m = PredictMeasurement(model, p, m);
    m.position += Eigen::Vector3d(0.01, -0.02, 0.03);
    {
      // Turn the measured orientation a little (composed, so that the
      // rotation vector stays within angle pi).
      const double angle = m.rotation.norm();
      const Eigen::Matrix3d R =
          angle > 0
              ? Eigen::AngleAxisd(angle, m.rotation / angle).toRotationMatrix()
              : Eigen::Matrix3d::Identity();
      const Eigen::AngleAxisd turned(
          R *
          Eigen::AngleAxisd(0.06, Eigen::Vector3d(0.5, 0.2, -0.4).normalized())
              .toRotationMatrix());
      m.rotation = turned.angle() * turned.axis();
    }
    m.distance += 0.01;
    Eigen::MatrixXd J;
    std::string error;
    ASSERT_TRUE(MeasurementJacobian(model, p, m, weight, &J, &error)) << error;
    const Eigen::MatrixXd N = CentralDifferenceJacobian(model, p, m, weight);
    ASSERT_EQ(J.rows(), m.dimension());
    ASSERT_EQ(J.cols(), model.num_free());
    for (int c = 0; c < J.cols(); ++c) {
      EXPECT_LT((J.col(c) - N.col(c)).norm(),
                1e-7 * std::max(1.0, N.col(c).norm()))
          << MeasurementTypeName(type) << " " << model.FreeParameterNames()[c]
          << " trial " << trial;
    }
  }
}

// The mixed model with its tool orientation free, which only 6D pose
// measurements see.
RobotModel MixedModelWithToolAngles() {
  RobotModel m = testing::MixedModel();
  m.markers[0].free = {true, true, true, true, true, true};
  m.nominal.tail(3) << 0.1, -0.2, 0.3;
  return m;
}

TEST(MeasurementResidualTest, PumaPositionJacobianMatchesCentralDifferences) {
  CheckJacobiansAgainstCentralDifferences(Puma560PaperModel(),
                                          MeasurementType::kPosition, 1);
}

TEST(MeasurementResidualTest, MixedModelJacobiansMatchCentralDifferences) {
  // Standard DH, Hayati, modified DH, a prismatic joint, gains, tool.
  for (MeasurementType type :
       {MeasurementType::kPosition, MeasurementType::kPose,
        MeasurementType::kDistance}) {
    CheckJacobiansAgainstCentralDifferences(MixedModelWithToolAngles(), type,
                                            2);
  }
}

TEST(MeasurementResidualTest,
     UrdfJointsFrameBaseMarkersMatchCentralDifferences) {
  for (MeasurementType type :
       {MeasurementType::kPosition, MeasurementType::kPose,
        MeasurementType::kDistance}) {
    for (int marker : {0, 1}) {
      CheckJacobiansAgainstCentralDifferences(testing::UrdfStyleModel(), type,
                                              11 + marker, marker);
    }
  }
}

// A pose measurement at random joints of the model (drawn from seed).
Measurement RandomPose(const RobotModel& model, uint64_t seed) {
  Random random(seed);
  Measurement m;
  m.type = MeasurementType::kPose;
  m.joints = testing::RandomJoints(model, &random);
  return m;
}

TEST(MeasurementResidualTest, PoseJacobianAtZeroRotationError) {
  // At a perfect measurement the rotation log is at its small-angle branch.
  const RobotModel model = MixedModelWithToolAngles();
  Measurement m = RandomPose(model, 7);
  m = PredictMeasurement(model, model.nominal, m);
  Eigen::MatrixXd J;
  std::string error;
  ASSERT_TRUE(MeasurementJacobian(model, model.nominal, m, 1.0, &J, &error));
  const Eigen::MatrixXd N =
      CentralDifferenceJacobian(model, model.nominal, m, 1.0);
  EXPECT_LT((J - N).norm(), 1e-6 * std::max(1.0, N.norm()));
  EXPECT_LT(ResidualAt(model, model.nominal, m, 1.0).norm(), 1e-12);
}

TEST(MeasurementResidualTest, PoseAndDistanceResidualValues) {
  const RobotModel model = testing::MixedModel();
  Random random(3);
  Measurement m;
  m.type = MeasurementType::kPose;
  m.joints = testing::RandomJoints(model, &random);
  m.joints2 = testing::RandomJoints(model, &random);
  const Measurement truth = PredictMeasurement(model, model.nominal, m);
  // A measured orientation turned by 0.1 rad about z in the target frame:
  // the rotation rows are the weighted log of that turn, -0.1 about z.
  m = truth;
  m.position += Eigen::Vector3d(0.001, 0.002, 0.003);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(truth.rotation.norm(), truth.rotation.normalized())
          .toRotationMatrix() *
      Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::AngleAxisd aa(R);
  m.rotation = aa.angle() * aa.axis();
  const Eigen::VectorXd r = ResidualAt(model, model.nominal, m, 2.0);
  EXPECT_NEAR(r[0], -0.001, 1e-12);
  EXPECT_NEAR(r[1], -0.002, 1e-12);
  EXPECT_NEAR(r[2], -0.003, 1e-12);
  EXPECT_NEAR(r[3], 0.0, 1e-10);
  EXPECT_NEAR(r[4], 0.0, 1e-10);
  EXPECT_NEAR(r[5], -0.2, 1e-10);
  // Distance: the predicted distance minus the measured one.
  m.type = MeasurementType::kDistance;
  m.distance = 0.5;
  const double predicted = (MeasuredPoint(model, model.nominal, m.joints) -
                            MeasuredPoint(model, model.nominal, m.joints2))
                               .norm();
  EXPECT_NEAR(ResidualAt(model, model.nominal, m, 1.0)[0], predicted - 0.5,
              1e-12);
}

TEST(MeasurementResidualTest, ToolAnglesOnlyMoveTheOrientation) {
  const RobotModel model = MixedModelWithToolAngles();
  Measurement m = RandomPose(model, 4);
  Eigen::MatrixXd J;
  std::string error;
  ASSERT_TRUE(MeasurementJacobian(model, model.nominal, m, 1.0, &J, &error));
  // The last three free parameters are tool.rx, ry, rz.
  EXPECT_EQ(J.topRightCorner(3, 3).norm(), 0.0);
  EXPECT_GT(J.bottomRightCorner(3, 3).norm(), 0.5);
  m.type = MeasurementType::kPosition;
  ASSERT_TRUE(MeasurementJacobian(model, model.nominal, m, 1.0, &J, &error));
  EXPECT_EQ(J.rightCols(3).norm(), 0.0);
}

TEST(MeasurementResidualTest, ResidualIsPredictedMinusMeasured) {
  const RobotModel m = Puma560PaperModel();
  auto shared = std::make_shared<const RobotModel>(m);
  Eigen::VectorXd q(6);
  q << 0.1, 0.2, -0.3, 0.4, 0.5, -0.6;
  const Eigen::Vector3d measured(1.0, 2.0, 3.0);
  Measurement position;
  position.joints = q;
  position.position = measured;
  std::unique_ptr<ceres::CostFunction> cost(
      MeasurementResidual::Create(shared, position));
  ASSERT_EQ(cost->parameter_block_sizes().size(), 8u);
  ASSERT_EQ(cost->num_residuals(), 3);
  const std::vector<const double*> blocks = BlockPointers(m, m.nominal.data());
  double r[3];
  ASSERT_TRUE(cost->Evaluate(blocks.data(), r, nullptr));
  const Eigen::Vector3d expected = MeasuredPoint(m, m.nominal, q) - measured;
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(r[k], expected[k]);
}

TEST(PoolJacobiansTest, SameResultForAnyThreadCount) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  ASSERT_TRUE(JointLattice::Create(m, 3, &lattice, &error));
  const Eigen::MatrixXd joints = lattice.AllJointValues();
  RowMatrixXd one, two, five;
  PoolJacobianOptions options;
  options.num_threads = 1;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &one, &error));
  options.num_threads = 2;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &two, &error));
  options.num_threads = 5;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &five, &error));
  EXPECT_EQ(one.rows(), 3 * 729);
  EXPECT_TRUE(one == two);
  EXPECT_TRUE(one == five);
  // And each block equals the single-pose (auto-diff) Jacobian: to
  // rounding through the analytic path, bit for bit through auto-diff.
  Eigen::MatrixXd J;
  ASSERT_TRUE(MeasurementJacobian(m, m.nominal,
                                  MeasurementPlan(joints.middleRows(100, 1))[0],
                                  1.0, &J, &error));
  EXPECT_LE((Eigen::MatrixXd(one.middleRows(300, 3)) - J).cwiseAbs().maxCoeff(),
            1e-13);
  options.analytic = false;
  ASSERT_TRUE(PoolJacobians(m, m.nominal, joints, options, &one, &error));
  EXPECT_TRUE(Eigen::MatrixXd(one.middleRows(300, 3)) == J);
}

TEST(StackedJacobianTest, DistanceBetweenCoincidingPointsIsRefused) {
  // The same joint values twice: bad input for every function.
  const RobotModel m = Puma560PaperModel();
  Measurement d;
  d.type = MeasurementType::kDistance;
  d.joints = Eigen::VectorXd::Zero(6);
  d.joints2 = d.joints;
  std::string error;
  EXPECT_FALSE(CheckMeasurement(m, d, &error));
  EXPECT_NE(error.find("identical"), std::string::npos) << error;
  Eigen::MatrixXd J;
  EXPECT_FALSE(StackedJacobian(m, m.nominal, {d}, 1.0, &J, &error));
  EXPECT_NE(error.find("measurement 0"), std::string::npos) << error;
  // Different joint values with the same measured point (joint 6 one turn
  // apart): the norm's Jacobian would be NaN.
  d.joints[5] = -1.0;
  d.joints2[5] = -1.0 + 2 * M_PI;
  ASSERT_TRUE(CheckMeasurement(m, d, &error)) << error;
  EXPECT_FALSE(StackedJacobian(m, m.nominal, {d}, 1.0, &J, &error));
  EXPECT_NE(error.find("coincide"), std::string::npos) << error;
}

// The pool of the PUMA's 4^6 lattice with its identifiability analysed
// through at most max_analysis_rows rows; a failure with the message.
::testing::AssertionResult AnalysedPumaLattice(int max_analysis_rows,
                                               CandidatePool* pool,
                                               CandidatePoolSummary* summary) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  if (!JointLattice::Create(m, 4, &lattice, &error)) {
    return ::testing::AssertionFailure() << error;
  }
  CandidatePoolOptions options;
  options.check_identifiability = true;
  options.max_analysis_rows = max_analysis_rows;
  if (!BuildCandidatePool(m, m.nominal, lattice.AllJointValues(), options, pool,
                          summary)) {
    return ::testing::AssertionFailure() << summary->message;
  }
  return ::testing::AssertionSuccess();
}

TEST(BuildCandidatePoolTest, SamplesWholeBlocksForTheIdentifiabilityCheck) {
  // Sampling every k-th row of a position pool with k a multiple of 3
  // analyses only the x rows (the --levels=9 bug); whole blocks it must be.
  RowMatrixXd stacked(12, 2);
  for (int r = 0; r < 12; ++r) stacked.row(r) << r, 100 + r;
  const Eigen::MatrixXd sample = SampleBlocks(stacked, 3, 7);
  ASSERT_EQ(sample.rows(), 6);
  // Two different whole poses (rows 3k, 3k+1, 3k+2), in pool order.
  for (int b = 0; b < 2; ++b) {
    EXPECT_EQ(static_cast<int>(sample(3 * b, 0)) % 3, 0);
    for (int r = 1; r < 3; ++r) {
      EXPECT_EQ(sample(3 * b + r, 0), sample(3 * b, 0) + r);
    }
  }
  EXPECT_LT(sample(0, 0), sample(3, 0));
  EXPECT_EQ(SampleBlocks(stacked, 3, 7), sample);  // deterministic
  EXPECT_EQ(SampleBlocks(stacked, 3, 12).rows(), 12);

  // A 4^6 lattice analysed through at most 300 rows: 100 whole poses, all
  // 27 parameters identifiable.
  CandidatePool pool;
  CandidatePoolSummary summary;
  ASSERT_TRUE(AnalysedPumaLattice(300, &pool, &summary));
  EXPECT_EQ(summary.identifiability.num_equations, 300);
  EXPECT_EQ(summary.identifiability.rank, 27);
  EXPECT_EQ(pool.size(), 4096);
  EXPECT_TRUE(summary.held.empty());
}

TEST(BuildCandidatePoolTest, SampleDoesNotAliasWithTheLattice) {
  // A 4^6 lattice analysed through 1024 of its 4096 poses: every 4th pose
  // (the old stride) keeps joint 6 at one level and loses rank 4; a random
  // subset identifies all 27 parameters (the --levels=10 bug: 10^6 poses
  // through 10^5).
  CandidatePool pool;
  CandidatePoolSummary summary;
  ASSERT_TRUE(AnalysedPumaLattice(3 * 1024, &pool, &summary));
  EXPECT_EQ(summary.identifiability.rank, 27);
}

TEST(BuildCandidatePoolTest, AutoFixHoldsTheRedundantParameterFixed) {
  // Base z offset free as well: B.d and L1.d move the point alike.
  RobotModel m = Puma560PaperModel();
  m.SetFree(kD, true);
  JointLattice lattice;
  std::string error;
  ASSERT_TRUE(JointLattice::Create(m, 3, &lattice, &error)) << error;
  CandidatePoolOptions options;
  options.check_identifiability = true;
  CandidatePool pool;
  CandidatePoolSummary summary;
  EXPECT_FALSE(BuildCandidatePool(m, m.nominal, lattice.AllJointValues(),
                                  options, &pool, &summary));
  EXPECT_NE(summary.message.find("not identifiable"), std::string::npos)
      << summary.message;
  EXPECT_EQ(summary.free.size(), 28);  // refused: nothing held
  options.auto_fix = true;
  ASSERT_TRUE(BuildCandidatePool(m, m.nominal, lattice.AllJointValues(),
                                 options, &pool, &summary))
      << summary.message;
  EXPECT_EQ(summary.held.size(), 1u);
  EXPECT_EQ(summary.held[0].stage, HoldStage::kAutoFix);
  EXPECT_EQ(summary.free.size(), 27);
  EXPECT_EQ(m.num_free(), 28);  // the model is not changed
  EXPECT_EQ(pool.num_parameters(), 27);
}

TEST(PoolJacobiansTest, BadInputGivesMessages) {
  const RobotModel m = Puma560PaperModel();
  std::string error;
  RowMatrixXd out;
  Eigen::MatrixXd joints = Eigen::MatrixXd::Zero(4, 6);
  joints(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(
      PoolJacobians(m, m.nominal, joints, PoolJacobianOptions(), &out, &error));
  EXPECT_NE(error.find("pool pose 2"), std::string::npos) << error;
  EXPECT_FALSE(PoolJacobians(m, m.nominal, joints.leftCols(5),
                             PoolJacobianOptions(), &out, &error));
  EXPECT_NE(error.find("expected 6 joint values"), std::string::npos) << error;
  Eigen::MatrixXd J;
  EXPECT_FALSE(MeasurementJacobian(m, m.nominal.head(20),
                                   MeasurementPlan(joints.topRows(1))[0], 1.0,
                                   &J, &error));
  EXPECT_NE(error.find("expected 48 parameter values, got 20"),
            std::string::npos)
      << error;
}

}  // namespace
}  // namespace activecal
