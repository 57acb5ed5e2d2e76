// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// identify's headline on 6D data (calibration_report.h, PoseErrorRms): the
// position RMS (mm) and the rotation RMS (mrad) apart, each what the fit's
// own residual rows give once the rotation weight is taken out, so the
// position RMS is a position error whatever --rotation_weight; the
// position-only line is unchanged.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/simulation.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "test_util.h"

namespace activecal {
namespace {

struct Fit6d {
  CalibrationSummary summary;
  std::vector<Measurement> data;
};

// The README's UR10e example (23 camera poses), all 30 separable
// parameters, no model selection.
Fit6d CalibrateUr10e(double rotation_weight) {
  Fit6d fit;
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(testing::LoadShippedUr("ur10e.urdf", &robot, &error)) << error;
  EXPECT_TRUE(ReadMeasurementsCsv(
      std::string(ACTIVECAL_DATA_DIR) + "/figaroh_ur10e/measurements.csv",
      robot.model, &fit.data, &error))
      << error;
  CalibrationOptions options;
  options.parameter_set = ParameterSet::kFull;
  options.model_selection = ModelSelectionMethod::kNone;
  options.identification.rotation_weight_m_per_rad = rotation_weight;
  Calibrate(robot.model, fit.data, options, &fit.summary);
  EXPECT_EQ(fit.summary.stage, CalibrationStage::kDone) << fit.summary.message;
  return fit;
}

std::string Mm3(double metres) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.3f", 1e3 * metres);
  return text;
}

TEST(PoseErrorRmsTest, PositionAndRotationEqualTheResidualRowsUnweighted) {
  for (const double w : {0.1, 1.0}) {
    SCOPED_TRACE(w);
    const Fit6d fit = CalibrateUr10e(w);
    const CalibrationSummary& s = fit.summary;
    ASSERT_EQ(s.stage, CalibrationStage::kDone);
    const IdentificationSummary& id = s.identification;
    // The residual rows of each pose: 3 position (m), 3 rotation times w.
    ASSERT_EQ(id.residuals.size(), 6 * static_cast<int>(s.training.size()));
    double position2 = 0, rotation2 = 0;
    for (size_t i = 0; i < s.training.size(); ++i) {
      ASSERT_EQ(s.training[i].type, MeasurementType::kPose);
      position2 += id.residuals.segment<3>(6 * i).squaredNorm();
      rotation2 += (id.residuals.segment<3>(6 * i + 3) / w).squaredNorm();
    }
    const double n = static_cast<double>(s.training.size());
    const PoseErrorRms rms = PoseErrorRmsOf(s.model, id.parameters, s.training);
    EXPECT_EQ(rms.num_poses, 23);
    EXPECT_NEAR(rms.position_m, std::sqrt(position2 / n), 1e-9);
    EXPECT_NEAR(rms.rotation_rad, std::sqrt(rotation2 / n), 1e-9);
    // The weighted residual is neither (the rotations weigh in with w).
    EXPECT_GT(std::abs(id.rms_m - rms.position_m), 1e-5);
    // The one-line result and the table print the split, not rms_m.
    const std::string line = CalibrationResultLine(s);
    EXPECT_NE(line.find("RMS position " + Mm3(rms.position_m) +
                        " mm, rotation " + Mm3(rms.rotation_rad) + " mrad"),
              std::string::npos)
        << line;
    EXPECT_EQ(line.find(Mm3(id.rms_m) + " mm"), std::string::npos) << line;
    const std::string text = CalibrationResultText(s, {});
    EXPECT_NE(text.find("6D poses (23): position RMS " + Mm3(rms.position_m) +
                        " mm, rotation RMS " + Mm3(rms.rotation_rad) + " mrad"),
              std::string::npos)
        << text;
    // The JSON's pose_errors.
    const std::string json = CalibrationJson(s, {});
    EXPECT_NE(json.find("\"pose_errors\""), std::string::npos);
    EXPECT_NE(json.find("\"position_rms_m\""), std::string::npos);
  }
}

TEST(PoseErrorRmsTest, PositionOnlyDataKeepTheResidualLine) {
  const RobotModel m = Puma560PaperModel();
  std::vector<Measurement> data;
  std::vector<int64_t> poses;
  std::string error;
  JointLattice lattice;
  ASSERT_TRUE(JointLattice::Create(m, 5, &lattice, &error)) << error;
  ASSERT_TRUE(SimulateAtRandomLatticePoses(m, Puma560TrueParameters(), lattice,
                                           30, 1e-4, 3, &poses, &data, &error))
      << error;
  EXPECT_EQ(PoseErrorRmsOf(m, m.nominal, data).num_poses, 0);
  CalibrationSummary s;
  Calibrate(m, data, CalibrationOptions(), &s);
  ASSERT_EQ(s.stage, CalibrationStage::kDone) << s.message;
  const std::string line = CalibrationResultLine(s);
  EXPECT_NE(line.find(", RMS " + Mm3(s.identification.rms_m) + " mm"),
            std::string::npos)
      << line;
  EXPECT_EQ(line.find("mrad"), std::string::npos) << line;
  EXPECT_EQ(CalibrationJson(s, {}).find("pose_errors"), std::string::npos);
  EXPECT_EQ(CalibrationResultText(s, {}).find("6D poses"), std::string::npos);
}

}  // namespace
}  // namespace activecal
