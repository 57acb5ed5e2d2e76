#include "activecal/estimation/identification.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "test_util.h"

namespace activecal {
namespace {

std::vector<Measurement> PumaMeasurements(int num_poses, double noise,
                                          uint64_t seed) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(m, 5, &lattice, &error));
  Random random(seed);
  const std::vector<int64_t> poses =
      random.SampleWithoutReplacement(lattice.size(), num_poses);
  Eigen::MatrixXd joints(num_poses, 6);
  for (int i = 0; i < num_poses; ++i) {
    joints.row(i) = lattice.JointValues(poses[i]).transpose();
  }
  std::vector<Measurement> out;
  EXPECT_TRUE(SimulateMeasurements(m, Puma560TrueParameters(),
                                   MeasurementPlan(joints), {noise, 0.0},
                                   seed + 1000, &out, &error))
      << error;
  return out;
}

TEST(IdentificationTest, NoiseFreeRecoversTrueValues) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  IdentificationSummary summary;
  Identify(m, PumaMeasurements(30, 0.0, 3), m.nominal, IdentificationOptions(),
           &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.termination_type, TerminationType::kConvergence);
  EXPECT_LT((summary.parameters - truth).cwiseAbs().maxCoeff(), 1e-8)
      << summary.BriefReport();
  EXPECT_LT(summary.rms_m, 1e-9);
}

TEST(IdentificationTest, NoisyEstimatesWithinFourStd) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd truth = ExtractFree(m, Puma560TrueParameters());
  for (uint64_t seed : {1, 2, 3, 4}) {
    IdentificationSummary summary;
    Identify(m, PumaMeasurements(30, 0.01, seed), m.nominal,
             IdentificationOptions(), &summary);
    ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
        << summary.message;
    ASSERT_EQ(summary.estimates.size(), 27);
    for (int k = 0; k < 27; ++k) {
      EXPECT_LT(std::abs(summary.estimates[k] - truth[k]),
                4 * summary.standard_deviations[k])
          << summary.names[k] << " seed " << seed;
    }
    // sigma estimates the 1 cm noise (90 - 27 = 63 degrees of freedom).
    EXPECT_GT(summary.sigma_m, 0.006);
    EXPECT_LT(summary.sigma_m, 0.014);
  }
}

TEST(IdentificationTest, TooFewPosesIsReported) {
  const RobotModel m = Puma560PaperModel();
  IdentificationSummary summary;
  Identify(m, PumaMeasurements(8, 0.01, 1), m.nominal, IdentificationOptions(),
           &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kFailure);
  EXPECT_NE(summary.message.find("too few equations: 24"), std::string::npos)
      << summary.message;
  EXPECT_EQ(summary.estimates.size(), 0);
}

TEST(IdentificationTest, ZeroDegreesOfFreedomIsRefused) {
  // 9 position poses, 27 rows for 27 parameters: the estimates fit the data
  // exactly and nothing is left to estimate the noise; never std 0.
  const RobotModel m = Puma560PaperModel();
  IdentificationSummary summary;
  Identify(m, PumaMeasurements(9, 0.01, 1), m.nominal, IdentificationOptions(),
           &summary);
  EXPECT_NE(summary.termination_type, TerminationType::kConvergence);
  EXPECT_NE(summary.message.find("0 degrees of freedom"), std::string::npos)
      << summary.message;
  EXPECT_EQ(summary.standard_deviations.size(), 0);
}

TEST(IdentificationTest, ExactDataFlagsNoOutliers) {
  // Noise-free data: the median residual row is ~0, which must not make
  // every rounding-level residual an outlier.
  const RobotModel m = Puma560PaperModel();
  IdentificationSummary summary;
  IdentificationOptions options;
  options.robust_loss = RobustLoss::kHuber;
  options.robust_scale_m = 0.001;
  Identify(m, PumaMeasurements(30, 0.0, 3), m.nominal, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_TRUE(summary.outliers.empty()) << summary.outliers.size();
}

TEST(IdentificationTest, StartingAtTheSolutionCountsZeroIterations) {
  const RobotModel m = Puma560PaperModel();
  IdentificationSummary summary;
  Identify(m, PumaMeasurements(30, 0.0, 3), Puma560TrueParameters(),
           IdentificationOptions(), &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_GE(summary.iterations, 0);
}

TEST(IdentificationTest, UnidentifiableParametersAreNamed) {
  // Tool z and L6.d both move the point along the same axis (L6 has
  // alpha = 0): together they are not identifiable.
  RobotModel m = Puma560PaperModel();
  m.markers[0].free[2] = true;
  IdentificationSummary summary;
  Identify(m, PumaMeasurements(30, 0.01, 1), m.nominal, IdentificationOptions(),
           &summary);
  EXPECT_NE(summary.termination_type, TerminationType::kConvergence);
  EXPECT_NE(summary.message.find("rank 27 < 28"), std::string::npos)
      << summary.message;
  EXPECT_NE(summary.message.find("L6.d"), std::string::npos);
  EXPECT_NE(summary.message.find("tool.z"), std::string::npos);
}

TEST(IdentificationTest, BadInputIsReportedNotCrashed) {
  const RobotModel m = Puma560PaperModel();
  std::vector<Measurement> data = PumaMeasurements(30, 0.01, 1);
  IdentificationSummary summary;
  data[4].position[1] = std::nan("");
  Identify(m, data, m.nominal, IdentificationOptions(), &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_NE(summary.message.find("measurement 4"), std::string::npos)
      << summary.message;
  data = PumaMeasurements(30, 0.01, 1);
  data[7].joints.resize(5);
  Identify(m, data, m.nominal, IdentificationOptions(), &summary);
  EXPECT_NE(summary.termination_type, TerminationType::kConvergence);
  EXPECT_NE(
      summary.message.find("measurement 7: joints: expected 6 joint values"),
      std::string::npos)
      << summary.message;
  data = PumaMeasurements(30, 0.01, 1);
  data[2].joints[0] = std::nan("");
  Identify(m, data, m.nominal, IdentificationOptions(), &summary);
  EXPECT_NE(summary.termination_type, TerminationType::kConvergence);
  EXPECT_NE(summary.message.find("measurement 2"), std::string::npos);
  Eigen::VectorXd initial = m.nominal;
  initial[5] = std::numeric_limits<double>::infinity();
  Identify(m, PumaMeasurements(30, 0.01, 1), initial, IdentificationOptions(),
           &summary);
  EXPECT_NE(summary.termination_type, TerminationType::kConvergence);
  EXPECT_NE(summary.message.find("initial values"), std::string::npos);
  Identify(m, std::vector<Measurement>{}, m.nominal, IdentificationOptions(),
           &summary);
  EXPECT_NE(summary.termination_type, TerminationType::kConvergence);
  EXPECT_NE(summary.message.find("too few equations: 0"), std::string::npos)
      << summary.message;
}

TEST(IdentificationTest, JointGainsAreRecovered) {
  // The PUMA with its six joint gains free as well (33 parameters); the
  // true gains differ from 1.
  RobotModel m = Puma560PaperModel();
  for (Link& l : m.links) l.free[kGain] = true;
  Eigen::VectorXd truth = Puma560TrueParameters();
  const double gains[6] = {1.002, 0.995, 1.01, 0.99, 1.005, 0.98};
  for (int j = 0; j < 6; ++j) truth[6 * (j + 1) + kGain] = gains[j];
  Random random(9);
  Eigen::MatrixXd joints(60, 6);
  for (int i = 0; i < 60; ++i) {
    joints.row(i) = testing::RandomJoints(m, &random).transpose();
  }
  std::vector<Measurement> data;
  std::string error;
  ASSERT_TRUE(SimulateMeasurements(m, truth, MeasurementPlan(joints), {}, 1,
                                   &data, &error));
  IdentificationSummary summary;
  Identify(m, data, m.nominal, IdentificationOptions(), &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.num_free, 33);
  EXPECT_LT((summary.parameters - truth).cwiseAbs().maxCoeff(), 1e-8)
      << summary.BriefReport();
}

TEST(IdentificationTest, MixedModelRedundanciesAreNamed) {
  // Every parameter of every link free, as a first-time user might write:
  // the analysis must name the overlapping ones rather than solve.
  const RobotModel m = testing::MixedModel();
  Random random(9);
  Eigen::MatrixXd joints(60, 4);
  for (int i = 0; i < 60; ++i) {
    joints.row(i) = testing::RandomJoints(m, &random).transpose();
  }
  std::vector<Measurement> data;
  std::string error;
  ASSERT_TRUE(SimulateMeasurements(m, m.nominal, MeasurementPlan(joints), {}, 1,
                                   &data, &error));
  IdentificationSummary summary;
  Identify(m, data, m.nominal, IdentificationOptions(), &summary);
  EXPECT_NE(summary.termination_type, TerminationType::kConvergence);
  EXPECT_NE(summary.message.find("not identifiable"), std::string::npos);
  EXPECT_GT(summary.identifiability.unidentifiable.size(), 0u);
  EXPECT_EQ(summary.identifiability.num_free - summary.identifiability.rank,
            static_cast<int>(summary.identifiability.unidentifiable.size()));
}

}  // namespace
}  // namespace activecal
