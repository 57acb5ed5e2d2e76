#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/residuals/position_residual.h"
#include "test_util.h"

namespace activecal {
namespace {

// Central differences of the measured point with respect to each free
// parameter, step h scaled to the parameter.
Eigen::MatrixXd CentralDifferenceJacobian(const RobotModel& m,
                                          const Eigen::VectorXd& p,
                                          const Eigen::VectorXd& q) {
  const std::vector<int> free = m.FreeParameterIndices();
  Eigen::MatrixXd J(3, free.size());
  for (size_t c = 0; c < free.size(); ++c) {
    const double h = 1e-6 * std::max(1.0, std::abs(p[free[c]]));
    Eigen::VectorXd plus = p, minus = p;
    plus[free[c]] += h;
    minus[free[c]] -= h;
    J.col(c) =
        (MeasuredPoint(m, plus, q) - MeasuredPoint(m, minus, q)) / (2 * h);
  }
  return J;
}

void CheckJacobiansAgainstCentralDifferences(const RobotModel& m,
                                             uint64_t seed) {
  Random random(seed);
  for (int trial = 0; trial < 25; ++trial) {
    Eigen::VectorXd p = m.nominal;
    for (int i = 0; i < p.size(); ++i) p[i] += 0.1 * random.Gaussian();
    const Eigen::VectorXd q = testing::RandomJoints(m, &random);
    Eigen::MatrixXd J;
    std::string error;
    ASSERT_TRUE(PositionJacobian(m, p, q, &J, &error)) << error;
    const Eigen::MatrixXd N = CentralDifferenceJacobian(m, p, q);
    ASSERT_EQ(J.rows(), 3);
    ASSERT_EQ(J.cols(), m.num_free());
    for (int c = 0; c < J.cols(); ++c) {
      EXPECT_LT((J.col(c) - N.col(c)).norm(),
                1e-7 * std::max(1.0, N.col(c).norm()))
          << m.FreeParameterNames()[c] << " trial " << trial;
    }
  }
}

TEST(PositionResidualTest, PumaJacobianMatchesCentralDifferences) {
  CheckJacobiansAgainstCentralDifferences(Puma560PaperModel(), 1);
}

TEST(PositionResidualTest, MixedModelJacobianMatchesCentralDifferences) {
  // Standard DH, Hayati, modified DH, a prismatic joint, gains, tool.
  CheckJacobiansAgainstCentralDifferences(testing::MixedModel(), 2);
}

TEST(PositionResidualTest, ResidualIsPredictedMinusMeasured) {
  const RobotModel m = Puma560PaperModel();
  auto shared = std::make_shared<const RobotModel>(m);
  Eigen::VectorXd q(6);
  q << 0.1, 0.2, -0.3, 0.4, 0.5, -0.6;
  const Eigen::Vector3d measured(1.0, 2.0, 3.0);
  std::unique_ptr<ceres::CostFunction> cost(
      PositionResidual::Create(shared, q, measured));
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
  ASSERT_TRUE(
      PoolPositionJacobians(m, m.nominal, joints, options, &one, &error));
  options.num_threads = 2;
  ASSERT_TRUE(
      PoolPositionJacobians(m, m.nominal, joints, options, &two, &error));
  options.num_threads = 5;
  ASSERT_TRUE(
      PoolPositionJacobians(m, m.nominal, joints, options, &five, &error));
  EXPECT_EQ(one.rows(), 3 * 729);
  EXPECT_TRUE(one == two);
  EXPECT_TRUE(one == five);
  // And each block equals the single-pose Jacobian.
  Eigen::MatrixXd J;
  ASSERT_TRUE(
      PositionJacobian(m, m.nominal, joints.row(100).transpose(), &J, &error));
  EXPECT_TRUE(Eigen::MatrixXd(one.middleRows(300, 3)) == J);
}

TEST(PoolJacobiansTest, BadInputGivesMessages) {
  const RobotModel m = Puma560PaperModel();
  std::string error;
  RowMatrixXd out;
  Eigen::MatrixXd joints = Eigen::MatrixXd::Zero(4, 6);
  joints(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(PoolPositionJacobians(m, m.nominal, joints,
                                     PoolJacobianOptions(), &out, &error));
  EXPECT_NE(error.find("pool pose 2"), std::string::npos) << error;
  EXPECT_FALSE(PoolPositionJacobians(m, m.nominal, joints.leftCols(5),
                                     PoolJacobianOptions(), &out, &error));
  EXPECT_NE(error.find("expected 6 joint values"), std::string::npos) << error;
  Eigen::MatrixXd J;
  EXPECT_FALSE(PositionJacobian(m, m.nominal.head(20), Eigen::VectorXd::Zero(6),
                                &J, &error));
  EXPECT_NE(error.find("expected 45 parameter values, got 20"),
            std::string::npos)
      << error;
}

}  // namespace
}  // namespace activecal
