// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Warnings that mean something (issue #29): the outlier rule (chi-square
// per measurement, robust scale per class of rows, Bonferroni) at its
// threshold, and a calibration of every shipped robot on clean simulated
// data with small seeded errors warns of nothing, while the UR10's data
// read as a UR10e's still name what is wrong.

#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/core/free_set.h"
#include "activecal/core/joint_sampling.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/estimate_warnings.h"
#include "activecal/estimation/identification.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"

namespace activecal {
namespace {

std::string Data(const std::string& name) {
  return std::string(ACTIVECAL_DATA_DIR) + "/" + name;
}

std::vector<Measurement> Plan(int n, MeasurementType type, int dofs) {
  std::vector<Measurement> plan(n);
  for (Measurement& m : plan) {
    m.type = type;
    m.joints = Eigen::VectorXd::Zero(dofs);
  }
  return plan;
}

// The threshold is the chi-square quantile of the dimension at
// 1 - probability / N; d^2 just below it is not flagged, just above it is.
TEST(OutlierRuleTest, BonferroniChiSquareThresholdIsCrossed) {
  const int n = 100;
  const std::vector<Measurement> plan = Plan(n, MeasurementType::kPosition, 6);
  const boost::math::chi_squared_distribution<double> chi2(3);
  const double quantile =
      boost::math::quantile(boost::math::complement(chi2, 0.01 / n));
  // Every row 1 mm: the robust scale is 1.4826 mm.
  const double scale = 1.4826e-3;
  for (const double factor : {1 - 1e-6, 1 + 1e-6}) {
    Eigen::VectorXd r = Eigen::VectorXd::Constant(3 * n, 1e-3);
    // Measurement 7's three rows equal: d^2 = 3 (v / scale)^2.
    r.segment(21, 3).setConstant(scale * std::sqrt(factor * quantile / 3));
    Eigen::VectorXd d2, threshold;
    OutlierStatistics(plan, r, 0.01, 1e-6, &d2, &threshold);
    EXPECT_NEAR(threshold[7], quantile, 1e-12 * quantile);
    EXPECT_NEAR(d2[0], 3 / (1.4826 * 1.4826), 1e-12);
    EXPECT_EQ(d2[7] > threshold[7], factor > 1) << factor;
  }
}

// Rows of different units have their own scales: a pose's weighted
// rotation rows (0.01 mm) do not make its position rows (2 mm) improbable,
// nor a quiet axis (z, 0.5 mm) a noisy one (x, 2 mm).
TEST(OutlierRuleTest, RowClassesHaveTheirOwnScale) {
  const int n = 23;
  const std::vector<Measurement> plan = Plan(n, MeasurementType::kPose, 6);
  Random random(5);
  Eigen::VectorXd r(6 * n);
  for (int i = 0; i < n; ++i) {
    for (int t = 0; t < 6; ++t) {
      r[6 * i + t] = (t == 2 ? 5e-4 : t < 3 ? 2e-3 : 1e-5) * random.Gaussian();
    }
  }
  Eigen::VectorXd d2, threshold;
  OutlierStatistics(plan, r, 0.01, 1e-9, &d2, &threshold);
  for (int i = 0; i < n; ++i) EXPECT_LE(d2[i], threshold[i]) << i;
  // A gross position error is still found (10 robust std on one row).
  r[6 * 4 + 1] = 0.02;
  OutlierStatistics(plan, r, 0.01, 1e-9, &d2, &threshold);
  for (int i = 0; i < n; ++i) EXPECT_EQ(d2[i] > threshold[i], i == 4) << i;
}

// "Moved from nominal" needs both: more than 5 std and more than 5 mm (a
// length) / 10 mrad (an angle); each side of each threshold.
TEST(MovedWarningTest, LargeAndSignificant) {
  const RobotModel m = Puma560PaperModel();
  const std::vector<int> free = m.FreeParameterIndices();
  const int p = static_cast<int>(free.size());
  int length = -1;
  for (int k = 0; k < p && length < 0; ++k) {
    const int block = m.BlockOf(free[k]);
    if (block != 0 && !m.is_marker_block(block) &&
        std::string(m.ParameterUnit(free[k])) == "m") {
      length = k;
    }
  }
  ASSERT_GE(length, 0);
  auto warned = [&](double moved, double sd) {
    IdentificationSummary s;
    s.names = m.FreeParameterNames();
    s.estimates = ExtractFree(m, m.nominal);
    s.standard_deviations = Eigen::VectorXd::Constant(p, 1e-5);
    s.correlation = Eigen::MatrixXd::Identity(p, p);
    s.estimates[length] += moved;
    s.standard_deviations[length] = sd;
    return !EstimateWarnings(m, s, {}).empty();
  };
  EXPECT_TRUE(warned(0.0051, 0.001));     // 5.1 mm, 5.1 std
  EXPECT_FALSE(warned(0.0049, 0.0001));   // 4.9 mm, 49 std
  EXPECT_FALSE(warned(0.0051, 0.00103));  // 5.1 mm, 4.95 std
}

struct RobotCase {
  const char* file;
  const char* tip_link;
};

// Calibrates `file`'s robot on clean 6D data: the nominal values of the
// calibrated set (the full set of a URDF, the file's free set of a YAML
// robot) perturbed by 1 mm / 1 mrad (seeded; the PUMA file's own true
// values differ from nominal by up to 0.3 rad, a wrong nominal model),
// 0.1 mm / 0.1 mrad device noise, 60 random poses.
CalibrationSummary CalibrateClean(const RobotCase& robot_case, uint64_t seed) {
  RobotDescription robot;
  std::string error;
  RobotLoadOptions load;
  load.chain.tip_link = robot_case.tip_link;
  EXPECT_TRUE(LoadRobot(Data(robot_case.file), load, &robot, &error)) << error;
  const RobotModel& model = robot.model;
  const bool urdf = IsUrdfPath(robot_case.file);
  Eigen::VectorXd truth = model.nominal;
  {
    const FreeSet set =
        urdf ? ParameterSetFreeSet(model, ParameterSet::kFull, true)
             : FreeSet(model);
    Random random(seed);
    for (int i : set.Indices()) {
      const std::string unit = model.ParameterUnit(i);
      const double scale = unit == "m" ? 1e-3 : unit == "rad" ? 1e-3 : 0.0;
      truth[i] += scale * random.Gaussian();
    }
  }
  Eigen::MatrixXd joints;
  EXPECT_TRUE(SampleJointValues(model, JointSampling::kRandom, 60, seed,
                                &joints, &error))
      << error;
  SimulationNoise noise;
  noise.position_m = 1e-4;
  noise.rotation_rad = 1e-4;
  std::vector<Measurement> data;
  EXPECT_TRUE(SimulateMeasurements(
      model, truth, MeasurementPlan(joints, MeasurementType::kPose), noise,
      seed + 1, &data, &error))
      << error;
  CalibrationOptions options;
  options.parameter_set = urdf ? ParameterSet::kFull : ParameterSet::kFile;
  options.model_selection = ModelSelectionMethod::kNone;
  options.identification.rotation_weight_m_per_rad = 1.0;  // 0.1 mm / 0.1 mrad
  CalibrationSummary summary;
  Calibrate(model, data, options, &summary);
  return summary;
}

class CleanDataTest : public ::testing::TestWithParam<RobotCase> {};

TEST_P(CleanDataTest, NoWarningNoOutlier) {
  for (uint64_t seed : {1u, 2u}) {
    const CalibrationSummary s = CalibrateClean(GetParam(), seed);
    ASSERT_EQ(s.termination_type, TerminationType::kConvergence) << s.message;
    std::string all;
    for (const std::string& w : s.warnings) all += w + "\n";
    EXPECT_TRUE(s.warnings.empty())
        << GetParam().file << " seed " << seed << ":\n"
        << all;
    // Quiet because the moves are small, not because they are not
    // significant: the old rule (more than 5 std) fired here.
    const std::vector<int> free = s.model.FreeParameterIndices();
    int significant = 0;
    for (size_t k = 0; k < free.size(); ++k) {
      const int block = s.model.BlockOf(free[k]);
      if (block == 0 || s.model.is_marker_block(block)) continue;
      const double moved =
          s.identification.estimates[k] - s.model.nominal[free[k]];
      if (std::abs(moved) > 5 * s.identification.standard_deviations[k]) {
        ++significant;
      }
    }
    EXPECT_GT(significant, 0) << GetParam().file;
    EXPECT_TRUE(s.identification.outliers.empty())
        << GetParam().file << " seed " << seed << ": "
        << s.identification.outliers.size() << " outliers";
  }
}

INSTANTIATE_TEST_SUITE_P(ShippedRobots, CleanDataTest,
                         ::testing::Values(RobotCase{"puma560.yaml", ""},
                                           RobotCase{"ur10e.urdf", "tool0"},
                                           RobotCase{"ur10.urdf", "tool0"},
                                           RobotCase{"kuka_iiwa14.urdf", ""}),
                         [](const ::testing::TestParamInfo<RobotCase>& info) {
                           std::string name = info.param.file;
                           return name.substr(0, name.find('.'));
                         });

}  // namespace
}  // namespace activecal
