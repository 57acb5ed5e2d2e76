// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The UR ROS driver's kinematics file (io/ur_kinematics.h) of a calibrated
// UR (calibration_export.h: MakeUrCalibration).

#include "activecal/io/ur_kinematics.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "activecal/calibration/calibration_export.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/io/urdf_robot.h"
#include "test_util.h"

namespace activecal {
namespace {

using testing::DataFile;

RobotModel Ur10e() {
  RobotDescription robot;
  std::string error;
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  EXPECT_TRUE(LoadUrdfRobot(DataFile("ur10e.urdf"), chain, &robot, &error))
      << error;
  return robot.model;
}

UrKinematics Export(const RobotModel& model, const Eigen::VectorXd& values,
                    UrCalibration* ur = nullptr) {
  UrCalibration local;
  if (!ur) ur = &local;
  std::string error;
  EXPECT_TRUE(MakeUrCalibration(model, values, {}, "test", ur, &error))
      << error;
  UrKinematics k;
  EXPECT_TRUE(ParseUrKinematics(ur->text, "out.yaml", &k, &error)) << error;
  return k;
}

TEST(UrKinematicsTest, NominalUr10eIsUrDescriptionsDefaultKinematics) {
  // ur_description's config/ur10e/default_kinematics.yaml, value for value
  // (Universal_Robots_ROS2_Description 2.4.5, compared 2026-12-02).
  const double v[6][6] = {
      {0, 0, 0.1807, 0, 0, 0},
      {0, 0, 0, 1.570796327, 0, 0},
      {-0.6127, 0, 0, 0, 0, 0},
      {-0.57155, 0, 0.17415, 0, 0, 0},
      {0, -0.11985, -2.458164590756244e-11, 1.570796327, 0, 0},
      {0, 0.11655, -2.390480459346185e-11, 1.570796326589793, 3.141592653589793,
       3.141592653589793}};
  const RobotModel model = Ur10e();
  UrCalibration ur;
  const UrKinematics k = Export(model, model.nominal, &ur);
  for (int j = 0; j < 6; ++j) {
    const Eigen::Vector3d xyz(v[j][0], v[j][1], v[j][2]);
    EXPECT_LT((k.joints[j].xyz - xyz).cwiseAbs().maxCoeff(), 1e-12)
        << kUrKinematicsEntries[j];
    // As rotations: wrist_3's (roll, pi, pi) is (roll - pi, 0, 0) too.
    const Eigen::Matrix3d R = RpyRotation<double>(v[j][3], v[j][4], v[j][5]);
    const Eigen::Vector3d& a = k.joints[j].rpy;
    EXPECT_LT((RpyRotation<double>(a[0], a[1], a[2]) - R).cwiseAbs().maxCoeff(),
              1e-12)
        << kUrKinematicsEntries[j];
  }
  EXPECT_LT(ur.worst_m, 1e-12);
  EXPECT_NE(ur.text.find("kinematics:\n  shoulder:\n    x: 0\n    y: 0\n    "
                         "z: 0.1807\n"),
            std::string::npos)
      << ur.text;
  EXPECT_NE(ur.text.find("  hash: activecal_"), std::string::npos);
  EXPECT_EQ(ur.text.rfind("# test\n", 0), 0u);
}

TEST(UrKinematicsTest, PerturbedCalibrationRoundTrips) {
  const RobotModel model = Ur10e();
  Random random(11);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd values = model.nominal;
    for (int j = 0; j < 6; ++j) {
      const int b = model.block_offset(j + 1);
      for (int k = 0; k < 3; ++k) {
        values[b + kUrdfX + k] += 2e-3 * (random.Uniform() - 0.5);
        values[b + kUrdfRx + k] += 4e-3 * (random.Uniform() - 0.5);
      }
      values[b + kUrdfOffset] += 0.02 * (random.Uniform() - 0.5);
    }
    // A base registration stays out of the file.
    values.head(model.block_size(0)).setConstant(0.3);
    UrCalibration ur;
    const UrKinematics k = Export(model, values, &ur);
    EXPECT_LT(ur.worst_m, 1e-9);
    EXPECT_LT(ur.worst_rad, 1e-9);
    // Independently of the export's own check: a pose not among its own.
    Eigen::VectorXd q(6);
    q << 0.3, -1.1, 1.7, -0.4, 2.2, -2.9;
    Eigen::Matrix3d R, R_ur;
    Eigen::Vector3d t, t_ur;
    ForwardKinematics(model, values, q, &R, &t);
    // Without the base block: the chain from base_link.
    Eigen::Matrix3d RB;
    Eigen::Vector3d tB;
    LinkTransform(model.base, values.data(), 0.0, &RB, &tB);
    UrTool0Pose(k, q, &R_ur, &t_ur);
    EXPECT_LT((RB.transpose() * (t - tB) - t_ur).norm(), 1e-9);
    EXPECT_LT(
        Eigen::AngleAxisd((RB.transpose() * R).transpose() * R_ur).angle(),
        1e-9);
  }
}

TEST(UrKinematicsTest, PitchNearNinetyDegreesRoundTrips) {
  const RobotModel model = Ur10e();
  for (double pitch :
       {M_PI / 2, M_PI / 2 - 1e-9, -M_PI / 2, -M_PI / 2 + 1e-7}) {
    // The elbow's origin turned to pitch +-90 deg (nominal rotation: none).
    Eigen::VectorXd values = model.nominal;
    const int b = model.block_offset(3);
    values[b + kUrdfRy] = pitch;
    values[b + kUrdfRx] = 0.2;
    UrCalibration ur;
    const UrKinematics k = Export(model, values, &ur);
    EXPECT_LT(ur.worst_m, 1e-9) << pitch;
    EXPECT_LT(ur.worst_rad, 1e-9) << pitch;
    EXPECT_NEAR(std::abs(k.joints[2].rpy[1]), M_PI / 2, 2e-7) << pitch;
  }
}

TEST(UrKinematicsTest, NonUrRobotsAreRefused) {
  std::string error;
  UrCalibration ur;
  const RobotModel puma = Puma560PaperModel();
  EXPECT_FALSE(MakeUrCalibration(puma, puma.nominal, {}, "", &ur, &error));
  EXPECT_EQ(error,
            "the robot is not a UR: joint 1 ('L1') is not a URDF joint (a UR "
            "is loaded from its URDF)");
  RobotDescription iiwa;
  ASSERT_TRUE(LoadUrdfRobot(DataFile("kuka_iiwa14.urdf"), {}, &iiwa, &error))
      << error;
  EXPECT_FALSE(
      MakeUrCalibration(iiwa.model, iiwa.model.nominal, {}, "", &ur, &error));
  EXPECT_EQ(error, "the robot is not a UR: a UR has 6 joints, the model has 7");
  // A UR10e loaded to another tip (the flange, x forward): the rebuilt
  // chain ends at tool0.
  RobotDescription flange;
  UrdfChainOptions chain;
  chain.tip_link = "flange";
  ASSERT_TRUE(LoadUrdfRobot(DataFile("ur10e.urdf"), chain, &flange, &error))
      << error;
  EXPECT_FALSE(MakeUrCalibration(flange.model, flange.model.nominal, {}, "",
                                 &ur, &error));
  EXPECT_NE(error.find("the written UR kinematics do not reproduce the "
                       "calibrated model"),
            std::string::npos)
      << error;
  // A calibrated gain cannot be written.
  RobotModel model = Ur10e();
  Eigen::VectorXd values = model.nominal;
  values[model.block_offset(2) + kUrdfGain] = 1.001;
  EXPECT_FALSE(MakeUrCalibration(model, values, {}, "", &ur, &error));
  EXPECT_NE(error.find("joint 2 ('shoulder_lift_joint') has a calibrated "
                       "gain 1.001"),
            std::string::npos)
      << error;
}

TEST(UrKinematicsTest, BadFilesAreNamed) {
  UrKinematics k;
  std::string error;
  EXPECT_FALSE(ParseUrKinematics("kinematics: {shoulder: {x: 0}}\n", "k.yaml",
                                 &k, &error));
  EXPECT_NE(error.find("k.yaml:1:"), std::string::npos) << error;
}

}  // namespace
}  // namespace activecal
