// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Sobol and random pools (core/joint_sampling.h): inside the ranges,
// seeded, evenly spread (every one-dimensional projection of 2^k Sobol
// points puts one point in each of 2^k equal bins), one turn for full-turn
// joints, bad input refused.

#include "activecal/core/joint_sampling.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "activecal/calibration/selection_pool.h"
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

// Issue 26, item 13: a robot with a continuous joint got no pool at all
// (lattice, Sobol and random: "no finite range"). Such a joint takes one
// turn, [-pi, pi) (a joint bounded on one side: one turn from that bound),
// the end left out as for full-turn ranges: every pool kind has distinct
// poses inside the limits, and the selection pool over them is
// identifiable.
RobotModel PumaWithUnboundedJoints() {
  RobotModel model = Puma560PaperModel();
  const double inf = std::numeric_limits<double>::infinity();
  model.links[3].joint_min = -inf;  // joint 4 continuous
  model.links[3].joint_max = inf;
  model.links[5].joint_max = inf;  // joint 6 bounded below only (-176 deg)
  return model;
}

TEST(JointSamplingTest, ContinuousJointsAreSampledOverOneTurn) {
  const RobotModel model = PumaWithUnboundedJoints();
  const double low6 = model.links[5].joint_min;
  double low = 0, width = 0;
  bool one_turn = false;
  std::string error;
  ASSERT_TRUE(PoolJointRange(model, 3, &low, &width, &one_turn, &error));
  EXPECT_EQ(low, -M_PI);
  EXPECT_EQ(width, 2 * M_PI);
  EXPECT_TRUE(one_turn);
  ASSERT_TRUE(PoolJointRange(model, 5, &low, &width, &one_turn, &error));
  EXPECT_EQ(low, low6);
  EXPECT_TRUE(one_turn);
  ASSERT_TRUE(PoolJointRange(model, 0, &low, &width, &one_turn, &error));
  EXPECT_FALSE(one_turn);  // a range narrower than a turn: both ends
  // Sobol: stratified over the turn, [-pi, pi), never pi itself.
  const int kBins = 1024;
  Eigen::MatrixXd q;
  ASSERT_TRUE(
      SampleJointValues(model, JointSampling::kSobol, kBins, 7, &q, &error))
      << error;
  std::vector<int> count(kBins, 0);
  for (int i = 0; i < kBins; ++i) {
    ASSERT_GE(q(i, 3), -M_PI);
    ASSERT_LT(q(i, 3), M_PI);
    ASSERT_GE(q(i, 5), low6);
    ASSERT_LT(q(i, 5), low6 + 2 * M_PI);
    ++count[static_cast<int>((q(i, 3) + M_PI) / (2 * M_PI) * kBins)];
  }
  EXPECT_EQ(*std::min_element(count.begin(), count.end()), 1);
  EXPECT_EQ(*std::max_element(count.begin(), count.end()), 1);
  ASSERT_TRUE(
      SampleJointValues(model, JointSampling::kRandom, 2000, 7, &q, &error));
  EXPECT_GE(q.col(3).minCoeff(), -M_PI);
  EXPECT_LT(q.col(3).maxCoeff(), M_PI);
  EXPECT_GT(q.col(3).maxCoeff() - q.col(3).minCoeff(), 6.0);
  // The lattice: -pi + 2 pi k / levels, a different pose each.
  JointLattice lattice;
  ASSERT_TRUE(JointLattice::Create(model, 4, &lattice, &error)) << error;
  EXPECT_TRUE(lattice.one_turn(3));
  EXPECT_TRUE(lattice.one_turn(5));
  for (int k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(lattice.Angle(3, k), -M_PI + M_PI / 2 * k);
    EXPECT_DOUBLE_EQ(lattice.Angle(5, k), low6 + M_PI / 2 * k);
  }
  const Eigen::MatrixXd all = lattice.AllJointValues();
  for (int i = 0; i < all.rows(); ++i) {
    ASSERT_TRUE(model.CheckJointValues(all.row(i).transpose(), &error))
        << error;
  }
}

TEST(JointSamplingTest, PoolsWithAContinuousJointAreIdentifiable) {
  const RobotModel base = PumaWithUnboundedJoints();
  JointLattice lattice;
  std::string error;
  ASSERT_TRUE(JointLattice::Create(base, 3, &lattice, &error)) << error;
  std::vector<Eigen::MatrixXd> pools = {lattice.AllJointValues()};
  for (JointSampling s : {JointSampling::kSobol, JointSampling::kRandom}) {
    Eigen::MatrixXd q;
    ASSERT_TRUE(SampleJointValues(base, s, 500, 3, &q, &error)) << error;
    pools.push_back(q);
  }
  for (const Eigen::MatrixXd& joints : pools) {
    // No pose twice (a turn's end is its start).
    std::set<std::vector<double>> distinct;
    for (int i = 0; i < joints.rows(); ++i) {
      std::vector<double> row(joints.cols());
      for (int j = 0; j < joints.cols(); ++j) row[j] = joints(i, j);
      distinct.insert(row);
    }
    EXPECT_EQ(static_cast<int>(distinct.size()), joints.rows());
    RobotModel model = base;
    SelectionPoolOptions options;
    options.parameter_set = ParameterSet::kFile;  // the paper's 27
    CandidatePool pool;
    SelectionPoolSummary summary;
    EXPECT_TRUE(BuildSelectionPool(&model, joints, options, &pool, &summary))
        << summary.message;
    EXPECT_EQ(summary.termination_type, TerminationType::kConvergence);
    EXPECT_EQ(model.num_free(), 27);
  }
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
  // A prismatic joint without a finite range has no turn to sample.
  RobotModel mixed = testing::MixedModel();  // joint 3 prismatic
  mixed.links[2].joint_max = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(
      SampleJointValues(mixed, JointSampling::kSobol, 10, 1, &q, &error));
  EXPECT_EQ(error, "joint 3 (L3) has no finite range to sample");
  JointLattice lattice;
  EXPECT_FALSE(JointLattice::Create(mixed, 3, &lattice, &error));
  EXPECT_EQ(error, "lattice: joint 3 (L3) has no finite range");
  testing::ExpectEnumParsing(JointSamplingFromString, "random",
                             JointSampling::kRandom, "halton");
}

}  // namespace
}  // namespace activecal
