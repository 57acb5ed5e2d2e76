// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Identification from 6D pose, distance and mixed measurements; robust
// losses against gross outliers; identifiability repair.

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/residuals/jacobians.h"
#include "test_util.h"

namespace activecal {
namespace {

// The PUMA with its tool orientation free; the true tool angles are not 0.
RobotModel PumaWithToolAngles(Eigen::VectorXd* truth) {
  RobotModel m = Puma560PaperModel();
  m.markers[0].free[3] = m.markers[0].free[4] = m.markers[0].free[5] = true;
  *truth = Puma560TrueParameters();
  truth->tail(3) << 0.02, -0.01, 0.03;
  return m;
}

std::vector<Measurement> Plan(const RobotModel& m, MeasurementType type, int n,
                              uint64_t seed) {
  Random random(seed);
  std::vector<Measurement> plan(n);
  for (Measurement& x : plan) {
    x.type = type;
    x.joints = testing::RandomJoints(m, &random);
    x.joints2 = testing::RandomJoints(m, &random);
  }
  return plan;
}

std::vector<Measurement> Simulate(const RobotModel& m,
                                  const Eigen::VectorXd& truth,
                                  const std::vector<Measurement>& plan,
                                  double position_noise, double rotation_noise,
                                  uint64_t seed) {
  SimulationNoise noise;
  noise.position_m = position_noise;
  noise.rotation_rad = rotation_noise;
  std::vector<Measurement> out;
  std::string error;
  EXPECT_TRUE(SimulateMeasurements(m, truth, plan, noise, seed, &out, &error))
      << error;
  return out;
}

int CountOutside(const IdentificationSummary& s, const RobotModel& m,
                 const Eigen::VectorXd& truth, double k) {
  const Eigen::VectorXd t = ExtractFree(m, truth);
  int outside = 0;
  for (int i = 0; i < t.size(); ++i) {
    if (std::abs(s.estimates[i] - t[i]) > k * s.standard_deviations[i]) {
      ++outside;
    }
  }
  return outside;
}

TEST(MeasurementTypesTest, PoseMeasurementsIdentifyToolOrientation) {
  Eigen::VectorXd truth;
  const RobotModel m = PumaWithToolAngles(&truth);
  ASSERT_EQ(m.num_free(), 30);
  const auto plan = Plan(m, MeasurementType::kPose, 30, 1);
  IdentificationSummary s;
  Identify(m, Simulate(m, truth, plan, 0, 0, 2), m.nominal,
           IdentificationOptions(), &s);
  ASSERT_EQ(s.termination_type, TerminationType::kConvergence) << s.message;
  EXPECT_LT((s.parameters - truth).cwiseAbs().maxCoeff(), 1e-8);
  // With noise: 0.1 mm and 0.2 mrad, weight = sigma_p / sigma_r.
  IdentificationOptions options;
  options.rotation_weight_m_per_rad = 0.5;
  for (uint64_t seed : {3, 4, 5}) {
    Identify(m, Simulate(m, truth, plan, 1e-4, 2e-4, seed), m.nominal, options,
             &s);
    ASSERT_EQ(s.termination_type, TerminationType::kConvergence) << s.message;
    EXPECT_EQ(CountOutside(s, m, truth, 4.0), 0) << "seed " << seed;
    // The weighted rows share one noise level: s estimates 1e-4.
    EXPECT_NEAR(s.sigma_m, 1e-4, 2.5e-5);
  }
}

TEST(MeasurementTypesTest, PositionMeasurementsCannotSeeToolOrientation) {
  Eigen::VectorXd truth;
  const RobotModel m = PumaWithToolAngles(&truth);
  const auto plan = Plan(m, MeasurementType::kPosition, 30, 1);
  IdentificationSummary s;
  Identify(m, Simulate(m, truth, plan, 0, 0, 2), m.nominal,
           IdentificationOptions(), &s);
  EXPECT_NE(s.termination_type, TerminationType::kConvergence);
  for (const char* name : {"tool.rx has no effect", "tool.ry has no effect",
                           "tool.rz has no effect"}) {
    EXPECT_NE(s.message.find(name), std::string::npos) << s.message;
  }
}

TEST(MeasurementTypesTest, MixedMeasurementsInOneIdentification) {
  Eigen::VectorXd truth;
  const RobotModel m = PumaWithToolAngles(&truth);
  std::vector<Measurement> plan = Plan(m, MeasurementType::kPosition, 20, 1);
  for (const auto& x : Plan(m, MeasurementType::kPose, 10, 2))
    plan.push_back(x);
  for (const auto& x : Plan(m, MeasurementType::kDistance, 20, 3)) {
    plan.push_back(x);
  }
  IdentificationSummary s;
  Identify(m, Simulate(m, truth, plan, 0, 0, 4), m.nominal,
           IdentificationOptions(), &s);
  ASSERT_EQ(s.termination_type, TerminationType::kConvergence) << s.message;
  EXPECT_EQ(s.num_residuals, 20 * 3 + 10 * 6 + 20 * 1);
  EXPECT_EQ(s.residual_norms.size(), 50);
  EXPECT_LT((s.parameters - truth).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(MeasurementTypesTest, DistancesCannotSeeTheBaseAndAutoFixRepairsIt) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  const auto data =
      Simulate(m, truth, Plan(m, MeasurementType::kDistance, 80, 5), 0, 0, 6);
  IdentificationSummary s;
  Identify(m, data, m.nominal, IdentificationOptions(), &s);
  EXPECT_NE(s.termination_type, TerminationType::kConvergence);
  EXPECT_NE(s.message.find("not identifiable"), std::string::npos);
  // The distance between two points is blind to the base frame: every
  // suggested parameter set leaves the rest identifiable.
  Eigen::MatrixXd J;
  std::string error;
  ASSERT_TRUE(StackedJacobian(m, m.nominal, data, 1.0, &J, &error));
  const std::vector<int> fix = SuggestParametersToFix(J);
  const IdentifiabilityReport before = AnalyzeIdentifiability(m, J);
  EXPECT_EQ(static_cast<int>(fix.size()), before.num_free - before.rank);
  RobotModel fixed = m;
  const std::vector<int> free = m.FreeParameterIndices();
  std::set<std::string> names;
  for (int c : fix) {
    fixed.SetFree(free[c], false);
    names.insert(m.FreeParameterNames()[c]);
  }
  // The four base parameters are among them.
  for (const char* b : {"B.gamma", "B.alpha", "B.a", "B.beta"}) {
    EXPECT_EQ(names.count(b), 1u) << b;
  }
  // Fixed at the truth, the rest is recovered exactly.
  Eigen::VectorXd initial = m.nominal;
  for (int c : fix) initial[free[c]] = truth[free[c]];
  Identify(fixed, data, initial, IdentificationOptions(), &s);
  ASSERT_EQ(s.termination_type, TerminationType::kConvergence) << s.message;
  EXPECT_LT((s.parameters - truth).cwiseAbs().maxCoeff(), 1e-7);
}

TEST(MeasurementTypesTest, RedundantBaseOffsetIsNamedAndSuggested) {
  // B.d (base z offset) and L1.d move the arm along the same axis.
  RobotModel m = Puma560PaperModel();
  m.base.free[kD] = true;
  const auto data =
      Simulate(m, Puma560TrueParameters(),
               Plan(m, MeasurementType::kPosition, 40, 7), 0, 0, 8);
  IdentificationSummary s;
  Identify(m, data, m.nominal, IdentificationOptions(), &s);
  EXPECT_NE(s.termination_type, TerminationType::kConvergence);
  EXPECT_NE(s.message.find("B.d"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("L1.d"), std::string::npos) << s.message;
  Eigen::MatrixXd J;
  std::string error;
  ASSERT_TRUE(StackedJacobian(m, m.nominal, data, 1.0, &J, &error));
  const std::vector<int> fix = SuggestParametersToFix(J);
  ASSERT_EQ(fix.size(), 1u);
  const std::string name = m.FreeParameterNames()[fix[0]];
  EXPECT_TRUE(name == "B.d" || name == "L1.d") << name;
}

TEST(MeasurementTypesTest, RobustLossResistsTenPercentGrossOutliers) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  std::vector<Measurement> data = Simulate(
      m, truth, Plan(m, MeasurementType::kPosition, 80, 11), 1e-3, 0, 12);
  // 10% gross errors of 3 to 10 cm, all one way (the tracker locked on a
  // second reflector mounted above the first).
  Random random(13);
  std::set<int> corrupted;
  for (int64_t i : random.SampleWithoutReplacement(data.size(), 8)) {
    data[i].position.z() += 0.03 + 0.07 * random.Uniform();
    corrupted.insert(static_cast<int>(i));
  }
  IdentificationSummary plain;
  Identify(m, data, m.nominal, IdentificationOptions(), &plain);
  ASSERT_EQ(plain.termination_type, TerminationType::kConvergence);
  EXPECT_GT(CountOutside(plain, m, truth, 4.0), 0)
      << "the plain fit should be pulled away by the outliers";

  for (RobustLoss loss : {RobustLoss::kCauchy, RobustLoss::kHuber}) {
    IdentificationOptions options;
    options.robust_loss = loss;
    options.robust_scale_m = 3e-3;
    IdentificationSummary robust;
    Identify(m, data, m.nominal, options, &robust);
    ASSERT_EQ(robust.termination_type, TerminationType::kConvergence)
        << robust.message;
    EXPECT_EQ(CountOutside(robust, m, truth, 4.0), 0)
        << RobustLossToString(loss) << "\n"
        << robust.BriefReport();
    // Exactly the corrupted measurements are flagged.
    EXPECT_EQ(std::set<int>(robust.outliers.begin(), robust.outliers.end()),
              corrupted)
        << RobustLossToString(loss);
    EXPECT_NEAR(robust.sigma_m, 1e-3, 2e-4) << RobustLossToString(loss);
  }
}

TEST(MeasurementTypesTest, RobustOptionsAreChecked) {
  IdentificationOptions options;
  options.robust_loss = RobustLoss::kHuber;
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("robust_scale_m"), std::string::npos) << error;
  options.robust_scale_m = 0.01;
  options.rotation_weight_m_per_rad = -1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("rotation_weight"), std::string::npos) << error;
  testing::ExpectEnumParsing(StringToRobustLoss, "cauchy", RobustLoss::kCauchy,
                             "tukey");
}

TEST(MeasurementTypesTest, BadMeasurementsAreNamed) {
  const RobotModel m = Puma560PaperModel();
  auto data = Simulate(m, Puma560TrueParameters(),
                       Plan(m, MeasurementType::kDistance, 40, 1), 0, 0, 2);
  data[3].joints2[2] = 10.0;  // outside joint 3's range
  IdentificationSummary s;
  Identify(m, data, m.nominal, IdentificationOptions(), &s);
  EXPECT_NE(s.termination_type, TerminationType::kConvergence);
  EXPECT_NE(s.message.find("measurement 3: second pose joints"),
            std::string::npos)
      << s.message;
  data[3].joints2[2] = 0.0;
  data[5].distance = -1.0;
  Identify(m, data, m.nominal, IdentificationOptions(), &s);
  EXPECT_NE(s.termination_type, TerminationType::kConvergence);
  EXPECT_NE(s.message.find("measurement 5: measured distance"),
            std::string::npos)
      << s.message;
}

}  // namespace
}  // namespace activecal
