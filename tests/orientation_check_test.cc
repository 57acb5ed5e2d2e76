// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The orientation convention hint (estimation/orientation_check.h).

#include "activecal/estimation/orientation_check.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "activecal/core/euler_angles.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "test_util.h"

namespace activecal {
namespace {

std::vector<Measurement> Poses(double noise) {
  return testing::SimulatedPuma(30, 5, MeasurementType::kPose, {noise, noise},
                                9);
}

// The orientations as a device in `written` wrote them, read as `read`.
std::vector<Measurement> Misread(std::vector<Measurement> m,
                                 const EulerConvention& written,
                                 const EulerConvention& read) {
  for (Measurement& x : m) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(x.rotation.norm(), x.rotation.normalized())
            .toRotationMatrix();
    const Eigen::AngleAxisd aa(EulerAnglesToRotationMatrix(
        RotationMatrixToEulerAngles(R, written), read));
    x.rotation = aa.angle() * aa.axis();
  }
  return m;
}

TEST(OrientationCheckTest, SilentForCorrectDataAtTheNominalAndTrueModels) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> m = Poses(1e-4);
  const PoseFit at_truth = PoseFitOf(model, Puma560TrueParameters(), m);
  EXPECT_EQ(at_truth.num_poses, 30);
  EXPECT_LT(at_truth.rotation_rms_rad, 1e-3);
  EXPECT_LT(at_truth.position_rms_m, 1e-3);
  EXPECT_FALSE(OrientationFitsBadly(at_truth));
  // The nominal geometry (what a registration sees): still silent.
  const PoseFit at_nominal = PoseFitOf(model, model.nominal, m);
  EXPECT_FALSE(OrientationFitsBadly(at_nominal))
      << at_nominal.rotation_rms_rad << " " << at_nominal.position_rms_m;
}

TEST(OrientationCheckTest, PrintedForTheWrongConvention) {
  const RobotModel model = Puma560PaperModel();
  EulerConvention intrinsic, extrinsic, zyx;
  extrinsic.frame = EulerFrame::kExtrinsic;
  zyx.axes = EulerAxes::kZYX;
  for (const EulerConvention& wrong : {extrinsic, zyx}) {
    const PoseFit fit =
        PoseFitOf(model, model.nominal, Misread(Poses(1e-4), intrinsic, wrong));
    EXPECT_TRUE(OrientationFitsBadly(fit))
        << fit.rotation_rms_rad << " " << fit.position_rms_m;
  }
  PoseFit fit;
  fit.num_poses = 40;
  fit.rotation_rms_rad = 0.612;
  fit.position_rms_m = 0.0031;
  EXPECT_EQ(OrientationHint(fit, "a, b, c as intrinsic XYZ, deg (m.yaml)"),
            "orientations fit badly (between 40 poses, relative rotations "
            "differ from the model's by 612 mrad RMS, distances by 3.1 mm): "
            "check the orientation convention (a, b, c as intrinsic XYZ, deg "
            "(m.yaml))");
}

TEST(OrientationCheckTest, TheThresholdsAreCrossed) {
  PoseFit fit;
  fit.num_poses = 10;
  fit.position_rms_m = 0.001;
  fit.rotation_rms_rad = 0.049;
  EXPECT_FALSE(OrientationFitsBadly(fit));  // below 50 mrad
  fit.rotation_rms_rad = 0.051;
  EXPECT_TRUE(OrientationFitsBadly(fit));
  fit.rotation_rms_rad = 0.3;
  fit.position_rms_m = 0.31;  // points off by more than the frames (at 1 m)
  EXPECT_FALSE(OrientationFitsBadly(fit));
  fit.position_rms_m = 0.29;
  EXPECT_TRUE(OrientationFitsBadly(fit));
  fit.num_poses = 0;
  EXPECT_FALSE(OrientationFitsBadly(fit));
}

}  // namespace
}  // namespace activecal
