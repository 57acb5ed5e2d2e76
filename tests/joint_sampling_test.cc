// Sobol and random pools (core/joint_sampling.h): inside the ranges,
// seeded, evenly spread (every one-dimensional projection of 2^k Sobol
// points puts one point in each of 2^k equal bins), one turn for full-turn
// joints, bad input refused.

#include "activecal/core/joint_sampling.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <set>
#include <string>
#include <vector>

#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "test_util.h"

namespace activecal {
namespace {

TEST(JointSamplingTest, InsideTheRangesAndSeeded) {
  const RobotModel model = Puma560PaperModel();
  for (JointSampling s : {JointSampling::kSobol, JointSampling::kRandom}) {
    Eigen::MatrixXd a, b, c;
    std::string error;
    ASSERT_TRUE(SampleJointValues(model, s, 5000, 3, &a, &error)) << error;
    ASSERT_TRUE(SampleJointValues(model, s, 5000, 3, &b, &error));
    ASSERT_TRUE(SampleJointValues(model, s, 5000, 4, &c, &error));
    EXPECT_EQ(a, b);
    EXPECT_GT((a - c).cwiseAbs().maxCoeff(), 0.1);
    ASSERT_EQ(a.rows(), 5000);
    ASSERT_EQ(a.cols(), model.num_joints());
    for (int i = 0; i < a.rows(); ++i) {
      EXPECT_TRUE(model.CheckJointValues(a.row(i).transpose(), &error))
          << error;
    }
  }
}

TEST(JointSamplingTest, SobolProjectionsAreStratified) {
  const RobotModel model = Puma560PaperModel();
  const int kBins = 1024;
  Eigen::MatrixXd q;
  std::string error;
  ASSERT_TRUE(
      SampleJointValues(model, JointSampling::kSobol, kBins, 11, &q, &error));
  for (int j = 0; j < model.num_joints(); ++j) {
    const Link& l = model.links[j];
    // The PUMA's joint 6 spans 532 deg: sampled over one turn.
    const double width = std::min(l.joint_max - l.joint_min, 2 * M_PI);
    std::vector<int> count(kBins, 0);
    for (int i = 0; i < kBins; ++i) {
      const double u = (q(i, j) - l.joint_min) / width;
      ++count[std::min(kBins - 1, static_cast<int>(u * kBins))];
    }
    for (int b = 0; b < kBins; ++b) {
      ASSERT_EQ(count[b], 1) << "joint " << j + 1 << " bin " << b;
    }
  }
  // Random draws are not stratified: some bin of 1024 stays empty.
  ASSERT_TRUE(
      SampleJointValues(model, JointSampling::kRandom, kBins, 11, &q, &error));
  std::vector<int> count(kBins, 0);
  const Link& l = model.links[0];
  for (int i = 0; i < kBins; ++i) {
    const double u = (q(i, 0) - l.joint_min) / (l.joint_max - l.joint_min);
    ++count[std::min(kBins - 1, static_cast<int>(u * kBins))];
  }
  EXPECT_NE(std::count(count.begin(), count.end(), 0), 0);
}

TEST(JointSamplingTest, FullTurnJointSampledOverOneTurn) {
  RobotModel model = Puma560PaperModel();
  model.links[0].joint_min = -2 * M_PI;
  model.links[0].joint_max = 2 * M_PI;
  Eigen::MatrixXd q;
  std::string error;
  ASSERT_TRUE(
      SampleJointValues(model, JointSampling::kSobol, 4096, 1, &q, &error));
  EXPECT_GE(q.col(0).minCoeff(), -2 * M_PI);
  EXPECT_LT(q.col(0).maxCoeff(), 0.0);  // [-2 pi, 0): one turn
  EXPECT_GT(q.col(0).maxCoeff(), -0.01);
}

TEST(JointSamplingTest, SubsampleRowsDoesNotAliasWithTheLattice) {
  // 4^6 lattice rows, 1,024 kept: every 4th row would hold joint 6 at its
  // first level; a random subset sees all four levels of every joint.
  const RobotModel model = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  ASSERT_TRUE(JointLattice::Create(model, 4, &lattice, &error)) << error;
  const Eigen::MatrixXd all = lattice.AllJointValues();
  const Eigen::MatrixXd subset = SubsampleRows(all, 1024);
  ASSERT_EQ(subset.rows(), 1024);
  for (int j = 0; j < model.num_joints(); ++j) {
    std::set<double> values(subset.col(j).data(),
                            subset.col(j).data() + subset.rows());
    EXPECT_EQ(values.size(), 4u) << "joint " << j + 1;
  }
  // Rows of the input, in its order, deterministic; all rows when few.
  EXPECT_EQ(SubsampleRows(all, 1024), subset);
  EXPECT_EQ(SubsampleRows(all, 5000), all);
  int64_t next = 0;
  for (int i = 0; i < subset.rows(); ++i) {
    while (next < all.rows() && all.row(next) != subset.row(i)) ++next;
    ASSERT_LT(next, all.rows()) << "row " << i << " out of order";
    ++next;
  }
}

TEST(JointSamplingTest, BadInput) {
  RobotModel model = Puma560PaperModel();
  Eigen::MatrixXd q;
  std::string error;
  EXPECT_FALSE(
      SampleJointValues(model, JointSampling::kSobol, 0, 1, &q, &error));
  EXPECT_NE(error.find("pool size"), std::string::npos) << error;
  model.links[2].joint_max = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(
      SampleJointValues(model, JointSampling::kSobol, 10, 1, &q, &error));
  EXPECT_NE(error.find("joint 3"), std::string::npos) << error;
  JointSampling s;
  EXPECT_TRUE(JointSamplingFromString("random", &s));
  EXPECT_EQ(s, JointSampling::kRandom);
  EXPECT_FALSE(JointSamplingFromString("halton", &s));
}

}  // namespace
}  // namespace activecal
