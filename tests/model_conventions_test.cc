// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The URDF-joint and frame conventions, the tip transform and several
// markers: forward kinematics against an independent composition of
// Eigen::Isometry3d transforms, the robot file round trip, and the model's
// structural checks.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <limits>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/measurement.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/frames_file.h"
#include "activecal/io/robot_file.h"
#include "test_util.h"

namespace activecal {
namespace {

Eigen::Matrix3d Rpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Isometry3d Pose(const Eigen::Vector3d& t, const Eigen::Matrix3d& R) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

// The tip frame of a frame-base, URDF-joint model, composed independently.
Eigen::Isometry3d ReferenceTip(const RobotModel& m, const Eigen::VectorXd& p,
                               const Eigen::VectorXd& q) {
  const double* b = p.data();
  Eigen::Isometry3d T =
      Pose(Eigen::Vector3d(b[0], b[1], b[2]), Rpy(b[3], b[4], b[5]));
  for (int i = 0; i < m.num_joints(); ++i) {
    const Link& l = m.links[i];
    const double* c = p.data() + m.block_offset(i + 1);
    const double s = c[kUrdfOffset] + c[kUrdfGain] * q[i];
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (l.joint_type == JointType::kRevolute) {
      motion.linear() = Eigen::AngleAxisd(s, l.axis).toRotationMatrix();
    } else {
      motion.translation() = s * l.axis;
    }
    T = T * Pose(l.origin_xyz, l.origin_rotation) *
        Pose(Eigen::Vector3d(c[0], c[1], c[2]), Rpy(c[3], c[4], c[5])) * motion;
  }
  return T * Pose(m.tip.translation, m.tip.rotation);
}

TEST(ModelConventionsTest, UrdfJointsMatchIsometryComposition) {
  const RobotModel m = testing::UrdfStyleModel();
  std::string error;
  ASSERT_TRUE(m.Validate(&error)) << error;
  EXPECT_EQ(m.num_parameters(), 6 + 4 * 8 + 2 * 6);
  Random random(5);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::VectorXd p = m.nominal;
    for (int i = 0; i < p.size(); ++i) p[i] += 0.05 * random.Gaussian();
    const Eigen::VectorXd q = testing::RandomJoints(m, &random);
    const Eigen::Isometry3d tip = ReferenceTip(m, p, q);
    for (int k = 0; k < m.num_markers(); ++k) {
      const double* mk = p.data() + m.block_offset(m.marker_block(k));
      const Eigen::Vector3d expected =
          tip * Eigen::Vector3d(mk[0], mk[1], mk[2]);
      EXPECT_LT((MeasuredPoint(m, p, q, k) - expected).norm(), 1e-12);
      Eigen::Matrix3d R;
      Eigen::Vector3d t;
      TargetFrame(m, p, q, &R, &t, k);
      EXPECT_LT((R - tip.linear() * Rpy(mk[3], mk[4], mk[5])).norm(), 1e-12);
      EXPECT_LT((t - expected).norm(), 1e-12);
    }
  }
}

TEST(ModelConventionsTest, ParameterNamesAndUnitsFollowTheConvention) {
  RobotModel m = testing::UrdfStyleModel();
  m.links[2].free[kUrdfOffset] = true;  // prismatic: a length
  const std::vector<std::string> names = m.ParameterNames();
  EXPECT_EQ(names[0], "B.x");
  EXPECT_EQ(names[5], "B.rz");
  EXPECT_EQ(names[6], "joint1.x");
  EXPECT_EQ(names[6 + 6], "joint1.offset");
  EXPECT_EQ(names[6 + 7], "joint1.gain");
  EXPECT_EQ(names[m.block_offset(m.marker_block(1))], "marker2.x");
  EXPECT_STREQ(m.ParameterUnit(m.ParameterIndex("joint1.offset")), "rad");
  EXPECT_STREQ(m.ParameterUnit(m.ParameterIndex("joint3.offset")), "m");
  EXPECT_STREQ(m.ParameterUnit(m.ParameterIndex("joint3.rx")), "rad");
  EXPECT_STREQ(m.ParameterUnit(m.ParameterIndex("joint3.gain")), "1");
  EXPECT_STREQ(m.ParameterUnit(m.ParameterIndex("B.z")), "m");
  int within = -1;
  EXPECT_EQ(m.BlockOf(m.ParameterIndex("marker2.y"), &within),
            m.marker_block(1));
  EXPECT_EQ(within, 1);
  EXPECT_EQ(m.MarkerIndex("marker2"), 1);
  EXPECT_EQ(m.MarkerIndex("2"), 1);
  EXPECT_EQ(m.MarkerIndex("1"), 0);
  EXPECT_EQ(m.MarkerIndex("3"), -1);
  EXPECT_EQ(m.MarkerIndex("nope"), -1);
  // Free flags address the right block entry.
  const int i = m.ParameterIndex("joint2.ry");
  m.SetFree(i, false);
  EXPECT_FALSE(m.IsFree(i));
  EXPECT_TRUE(m.IsFree(i - 1));
  EXPECT_TRUE(m.IsFree(i + 1));
  EXPECT_FALSE(m.links[1].free[kUrdfRy]);
}

TEST(ModelConventionsTest, RobotFileRoundTripKeepsStructureAndValues) {
  const RobotModel m = testing::UrdfStyleModel();
  Random random(9);
  Eigen::VectorXd values = m.nominal;
  for (int i = 0; i < values.size(); ++i) values[i] += 0.01 * random.Gaussian();
  for (AngleUnit unit : {AngleUnit::kRadian, AngleUnit::kDegree}) {
    RobotFileOptions options;
    options.angle_unit = unit;
    const std::string text = RobotFileText(m, values, options);
    RobotDescription back;
    std::string error;
    ASSERT_TRUE(ParseRobotDescription(text, "round.yaml", &back, &error))
        << error << "\n"
        << text;
    const RobotModel& r = back.model;
    ASSERT_EQ(r.num_parameters(), m.num_parameters());
    EXPECT_EQ(r.ParameterNames(), m.ParameterNames());
    EXPECT_EQ(r.FreeParameterIndices(), m.FreeParameterIndices());
    EXPECT_EQ(r.num_markers(), 2);
    const double tol = unit == AngleUnit::kRadian ? 0.0 : 1e-15;
    EXPECT_LE((r.nominal - values).cwiseAbs().maxCoeff(), tol);
    for (int j = 0; j < m.num_joints(); ++j) {
      EXPECT_EQ(r.links[j].convention, LinkConvention::kUrdf);
      EXPECT_EQ(r.links[j].joint_type, m.links[j].joint_type);
      EXPECT_LE((r.links[j].origin_xyz - m.links[j].origin_xyz).norm(), 0.0);
      // The origin's rotation re-reads exactly (as rpy or as its matrix).
      EXPECT_EQ(r.links[j].origin_rotation, m.links[j].origin_rotation);
      EXPECT_LE((r.links[j].axis - m.links[j].axis).norm(), 1e-15);
    }
    // So does the tip's (an angle-axis rotation: written as its matrix).
    EXPECT_EQ(r.tip.rotation, m.tip.rotation);
    EXPECT_LT((r.tip.translation - m.tip.translation).norm(), 1e-15);
    const Eigen::VectorXd q = testing::RandomJoints(m, &random);
    EXPECT_LT(
        (MeasuredPoint(r, r.nominal, q, 1) - MeasuredPoint(m, values, q, 1))
            .norm(),
        1e-13);
  }
}

// A continuous joint (no limits in its URDF) has unbounded ends: written as
// -.inf / .inf, read back (a --model_out of such a robot was unreadable:
// "limits[0]: must be finite"); a finite joint's "inf" is still refused.
TEST(ModelConventionsTest, RobotFileRoundTripsAContinuousJoint) {
  RobotModel m = testing::UrdfStyleModel();
  m.links[1].joint_min = -std::numeric_limits<double>::infinity();
  m.links[1].joint_max = std::numeric_limits<double>::infinity();
  for (AngleUnit unit : {AngleUnit::kRadian, AngleUnit::kDegree}) {
    RobotFileOptions options;
    options.angle_unit = unit;
    const std::string text = RobotFileText(m, m.nominal, options);
    EXPECT_NE(text.find("[-.inf, .inf]"), std::string::npos) << text;
    RobotDescription back;
    std::string error;
    ASSERT_TRUE(ParseRobotDescription(text, "round.yaml", &back, &error))
        << error << "\n"
        << text;
    EXPECT_EQ(back.model.links[1].joint_min, m.links[1].joint_min);
    EXPECT_EQ(back.model.links[1].joint_max, m.links[1].joint_max);
    EXPECT_EQ(back.model.links[0].joint_min, m.links[0].joint_min);
  }
  std::string text = RobotFileText(m, m.nominal);
  const size_t at = text.find("[-.inf, .inf]");
  ASSERT_NE(at, std::string::npos);
  RobotDescription back;
  std::string error;
  EXPECT_FALSE(ParseRobotDescription(text.replace(at, 13, "[.inf, -.inf]"),
                                     "bad.yaml", &back, &error));
}

TEST(ModelConventionsTest, RpyRoundTripIncludingGimbalLock) {
  Random random(3);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d rpy(M_PI * (2 * random.Uniform() - 1),
                              0.5 * M_PI * (2 * random.Uniform() - 1),
                              M_PI * (2 * random.Uniform() - 1));
    const Eigen::Matrix3d R = Rpy(rpy[0], rpy[1], rpy[2]);
    EXPECT_LT((RpyRotation(rpy[0], rpy[1], rpy[2]) - R).norm(), 1e-14);
    const Eigen::Vector3d back = RotationToRpy(R);
    EXPECT_LT((Rpy(back[0], back[1], back[2]) - R).norm(), 1e-12);
  }
  // At and near gimbal lock, where the small entries R21, R22 carry the
  // roll: 1.57079632679 is a common way to write pi/2 in a URDF.
  for (double sign : {1.0, -1.0}) {
    for (double gap : {0.0, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-6,
                       M_PI / 2 - 1.57079632679}) {
      for (int trial = 0; trial < 20; ++trial) {
        const double r = M_PI * (2 * random.Uniform() - 1);
        const double y = M_PI * (2 * random.Uniform() - 1);
        const Eigen::Matrix3d R = Rpy(r, sign * (M_PI / 2 - gap), y);
        const Eigen::Vector3d back = RotationToRpy(R);
        EXPECT_LT((Rpy(back[0], back[1], back[2]) - R).norm(), 1e-14)
            << "gap " << gap;
      }
    }
  }
}

// The angles written for a rotation (robot YAML files, URDF export): read
// back, they give the rotation, at and near pitch +-90 deg too (issue #26:
// never a snapped pitch), and a rotation made from short decimals is
// written with the same decimals, in radians and in degrees (so the robot
// files written before keep their bytes).
TEST(ModelConventionsTest, ShortRpyReadsBackToTheRotation) {
  Random random(8);
  const double eps = std::numeric_limits<double>::epsilon();
  for (double sign : {1.0, -1.0}) {
    for (double gap :
         {0.0, 1e-15, 1e-12, 1e-9, 1e-6, 1e-4, 4.4e-3, 4.6e-3, 0.3, 1.5}) {
      for (int trial = 0; trial < 20; ++trial) {
        const double r = M_PI * (2 * random.Uniform() - 1);
        const double y = M_PI * (2 * random.Uniform() - 1);
        const Eigen::Matrix3d R = RpyRotation(r, sign * (M_PI / 2 - gap), y);
        for (double unit : {1.0, M_PI / 180}) {
          const Eigen::Vector3d a = RotationToShortRpy(R, unit) * unit;
          EXPECT_LE((RpyRotation(a[0], a[1], a[2]) - R).cwiseAbs().maxCoeff(),
                    8 * eps)
              << "gap " << gap << " unit " << unit;
        }
      }
    }
  }
  // Short decimals, pitch beyond +-90 deg among them (the other branch),
  // come back as they were; at exactly +-90 deg, roll is 0.
  const Eigen::Vector3d short_angles[] = {{0.1, 0.2, 0.3},
                                          {0, 1.5708, 0},
                                          {0, -1.5707963267948966, 2},
                                          {1.570796327, 0, 0},
                                          {0, 0, 3.14159},
                                          {0.2, -1.569, 0.1},
                                          {0.01, -0.02, 1.0},
                                          {0, 0, 0},
                                          {3.141592653589793, 0, 0},
                                          {0.3, 2.0, -0.1},
                                          {1.5708, -1.5708, -1.5708}};
  for (const Eigen::Vector3d& v : short_angles) {
    const Eigen::Matrix3d R = RpyRotation(v[0], v[1], v[2]);
    EXPECT_EQ(RotationToShortRpy(R), v) << v.transpose();
    const Eigen::Vector3d deg = v * 50;  // degrees, also short
    const Eigen::Vector3d rad = deg * (M_PI / 180);
    EXPECT_EQ(
        RotationToShortRpy(RpyRotation(rad[0], rad[1], rad[2]), M_PI / 180),
        deg)
        << deg.transpose();
  }
  // In a robot file: the digits as they were.
  RobotModel m = testing::UrdfStyleModel();
  m.links[0].origin_rotation = RpyRotation(0.1, 0.2, 0.3);
  m.links[1].origin_rotation = RpyRotation(0.0, 1.5707963267948966, -0.4);
  const std::string text = RobotFileText(m, m.nominal);
  EXPECT_NE(text.find("rpy: [0.1, 0.2, 0.3]"), std::string::npos) << text;
  EXPECT_NE(text.find("rpy: [0, 1.5707963267948966, -0.4]"), std::string::npos)
      << text;
}

// A rotation no rpy angles give exactly (a URDF origin read from urdfdom's
// quaternion, at and near pitch 90 deg) is written as its matrix and read
// back bit for bit, so a robot file (and a Python pickle, which is one)
// holds the model exactly; a bad matrix is refused with file:line.
TEST(ModelConventionsTest, RobotFileHoldsRotationsExactly) {
  RobotModel m = testing::UrdfStyleModel();
  m.links[0].origin_rotation =
      Eigen::Quaterniond(0.7071067811140325, 0.7071067812590626, 0, 0)
          .normalized()
          .toRotationMatrix();  // urdfdom's rpy="1.570796327 0 0"
  m.links[1].origin_rotation =
      RpyRotation(0.2, -(M_PI / 2 - 1e-9), 0.1) * RpyRotation(0.3, 0.0, 0.0);
  m.links[2].origin_rotation = RpyRotation(0.3, 1.5707963267948966, 0.0);
  for (AngleUnit unit : {AngleUnit::kRadian, AngleUnit::kDegree}) {
    RobotFileOptions options;
    options.angle_unit = unit;
    RobotDescription back;
    std::string text;
    ASSERT_TRUE(testing::RobotFileRoundTrip(m, m.nominal, options, "r.yaml",
                                            &back, &text));
    for (int j = 0; j < m.num_joints(); ++j) {
      EXPECT_EQ(back.model.links[j].origin_rotation, m.links[j].origin_rotation)
          << j << "\n"
          << text;
    }
    EXPECT_EQ(back.model.tip.rotation, m.tip.rotation);
    if (unit == AngleUnit::kRadian) {
      EXPECT_NE(text.find("rotation: [1, 0, 0, 0, -2.0510348974767112e-10, "
                          "-1, 0, 1, -2.0510348974767112e-10]"),
                std::string::npos)
          << text;
    }
  }
  std::string text = RobotFileText(m, m.nominal);
  const size_t at = text.find("rotation: [1, 0, 0,");
  ASSERT_NE(at, std::string::npos);
  const size_t end = text.find(']', at) + 1;
  struct Case {
    const char* replacement;
    const char* message;
  };
  const Case cases[] = {
      {"rotation: [1, 0, 0, 0, 1, 0, 0, 0]",
       "links[0].origin.rotation: expected the 9 entries of a rotation "
       "matrix, row by row"},
      {"rotation: [1, 0, 0, 0, 1, 0, 0, 0, 1.01]",
       "links[0].origin.rotation: not a rotation matrix (orthonormal to "
       "1e-9, determinant +1)"},
      {"rotation: [1, 0, 0, 0, 1, 0, 0, 0, -1]", "not a rotation matrix"},
      {"rotation: [1, 0, 0, 0, 1, 0, 0, 0, x]",
       "links[0].origin.rotation[8]: expected a number, got 'x'"},
      {"rpy: [0, 0, 0], rotation: [1, 0, 0, 0, 1, 0, 0, 0, 1]",
       "links[0].origin.rotation: give rpy or rotation, not both"},
  };
  for (const Case& c : cases) {
    std::string bad = text;
    bad.replace(at, end - at, c.replacement);
    RobotDescription back;
    std::string error;
    EXPECT_FALSE(ParseRobotDescription(bad, "bad.yaml", &back, &error))
        << c.replacement;
    EXPECT_NE(error.find(c.message), std::string::npos) << error;
    EXPECT_EQ(error.rfind("bad.yaml:", 0), 0u) << error;
  }
}

TEST(ModelConventionsTest, StructuralErrorsAreNamed) {
  struct Case {
    const char* name;
    void (*edit)(RobotModel*);
    const char* message;
  };
  const Case cases[] = {
      {"urdf base",
       [](RobotModel* m) { m->base.convention = LinkConvention::kUrdf; },
       "convention 'urdf' is for joints"},
      {"frame link",
       [](RobotModel* m) { m->links[1].convention = LinkConvention::kFrame; },
       "convention 'frame' is only allowed for the base"},
      {"axis not unit", [](RobotModel* m) { m->links[0].axis *= 2.0; },
       "the axis a unit vector"},
      {"origin not a rotation",
       [](RobotModel* m) { m->links[1].origin_rotation *= 1.001; },
       "link 'joint2': the URDF origin's rotation is not a rotation matrix "
       "(orthonormal, determinant +1)"},
      {"origin a reflection",
       [](RobotModel* m) { m->links[2].origin_rotation.col(0) *= -1.0; },
       "link 'joint3': the URDF origin's rotation is not a rotation matrix"},
      {"origin not finite",
       [](RobotModel* m) {
         m->links[0].origin_rotation(1, 1) =
             std::numeric_limits<double>::quiet_NaN();
       },
       "link 'joint1': the URDF origin's rotation is not a rotation matrix"},
      {"no markers", [](RobotModel* m) { m->markers.clear(); }, "no markers"},
      {"duplicate names", [](RobotModel* m) { m->markers[1].name = "tool"; },
       "two parameter blocks are named 'tool'"},
  };
  for (const Case& c : cases) {
    RobotModel m = testing::UrdfStyleModel();
    c.edit(&m);
    m.nominal.conservativeResize(m.num_parameters());
    std::string error;
    EXPECT_FALSE(m.Validate(&error)) << c.name;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.name << ": " << error;
  }
}

TEST(ModelConventionsTest, MeasurementOfAMissingMarkerIsRefused) {
  const RobotModel m = testing::UrdfStyleModel();
  Measurement x;
  x.joints = Eigen::VectorXd::Zero(m.num_joints());
  x.marker = 2;
  std::string error;
  EXPECT_FALSE(CheckMeasurement(m, x, &error));
  EXPECT_NE(error.find("marker 3 is not a marker of the model (it has 2)"),
            std::string::npos)
      << error;
  x.marker = 1;
  EXPECT_TRUE(CheckMeasurement(m, x, &error)) << error;
}

}  // namespace
}  // namespace activecal

namespace activecal {
namespace {

TEST(FramesFileTest, RoundTripAndMarkerList) {
  RobotDescription robot;
  robot.model = testing::UrdfStyleModel();
  Random random(4);
  Eigen::VectorXd values = robot.model.nominal;
  for (int i = 0; i < values.size(); ++i) values[i] += 0.01 * random.Gaussian();
  const std::string text = FramesFileText(robot.model, values, "test");
  RobotDescription back = robot;
  std::string error;
  ASSERT_TRUE(ParseFramesFile(text, "frames.yaml", &back, &error)) << error;
  const RobotModel& m = robot.model;
  EXPECT_EQ(back.model.num_markers(), 2);
  EXPECT_EQ(back.model.block_name(m.marker_block(1)), "marker2");
  // Base and markers from the file, links untouched.
  EXPECT_EQ(back.model.nominal.head(6), values.head(6));
  const int markers = m.block_offset(m.marker_block(0));
  EXPECT_EQ(back.model.nominal.tail(12), values.tail(12));
  EXPECT_EQ(back.model.nominal.segment(6, markers - 6),
            m.nominal.segment(6, markers - 6));
  // Three markers in degrees: the model grows a block, the free flags of
  // the first marker carry over.
  ASSERT_TRUE(ParseFramesFile(
      "angle_unit: deg\nbase: {xyz: [1, 2, 3], rpy: [0, 0, 90]}\n"
      "markers:\n  - {name: a, xyz: [0, 0, 0.1]}\n  - {name: b, xyz: [0.1, "
      "0, 0]}\n  - {name: c, xyz: [0, 0.1, 0], rpy: [0, 180, 0]}\n",
      "f.yaml", &back, &error))
      << error;
  EXPECT_EQ(back.model.num_markers(), 3);
  EXPECT_EQ(back.model.num_parameters(), m.num_parameters() + 6);
  EXPECT_EQ(back.model.MarkerIndex("c"), 2);
  EXPECT_DOUBLE_EQ(back.model.nominal[5], M_PI / 2);
  EXPECT_EQ(back.model.markers[2].free, m.markers[0].free);
  EXPECT_DOUBLE_EQ(
      back.model
          .nominal[back.model.block_offset(back.model.marker_block(2)) + 4],
      M_PI);
}

TEST(FramesFileTest, TrueMarkerValuesStayWithoutAMarkerList) {
  RobotDescription robot;
  robot.model = testing::UrdfStyleModel();
  robot.true_parameters = robot.model.nominal;
  robot.true_parameters.tail(12).setConstant(0.07);
  const Eigen::VectorXd truth = robot.true_parameters;
  std::string error;
  ASSERT_TRUE(
      ParseFramesFile("base: {xyz: [1, 2, 3]}\n", "f.yaml", &robot, &error))
      << error;
  EXPECT_EQ(robot.true_parameters.tail(12), truth.tail(12));
  EXPECT_EQ(robot.true_parameters.head(3), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(robot.model.nominal.head(3), Eigen::Vector3d(1, 2, 3));
  // A base takes no name.
  EXPECT_FALSE(ParseFramesFile("base: {name: b, xyz: [1, 2, 3]}\n", "f.yaml",
                               &robot, &error));
  EXPECT_NE(error.find("base.name: unknown field"), std::string::npos) << error;
}

TEST(FramesFileTest, BadFramesAreNamed) {
  RobotDescription urdf_style;
  urdf_style.model = testing::UrdfStyleModel();
  RobotDescription puma;
  puma.model = Puma560PaperModel();
  struct Case {
    const char* name;
    RobotDescription* robot;
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"dh base", &puma, "base: {xyz: [0, 0, 0]}\n",
       "f.yaml:1:7: base: the robot's base is a hayati block, not a 6-DOF "
       "frame"},
      {"twice", &urdf_style,
       "markers:\n  - {name: a, xyz: [0, 0, 0]}\n  - {name: a, xyz: [0, 0, "
       "1]}\n",
       "marker 'a' is listed twice"},
      {"bad number", &urdf_style, "base: {xyz: [0, x, 0]}\n",
       "f.yaml:1:17: base.xyz[1]: expected a number, got 'x'"},
      {"unknown", &urdf_style, "bse: {}\n", "bse: unknown field"},
      {"unit", &urdf_style, "angle_unit: grad\n", "expected 'rad' or 'deg'"},
  };
  for (const Case& c : cases) {
    RobotDescription robot = *c.robot;
    std::string error;
    EXPECT_FALSE(ParseFramesFile(c.text, "f.yaml", &robot, &error)) << c.name;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.name << ": " << error;
    EXPECT_EQ(robot.model.nominal, c.robot->model.nominal) << c.name;
  }
}

}  // namespace
}  // namespace activecal

namespace activecal {
namespace {

TEST(MarkerColumnTest, MeasurementsNameTheirMarker) {
  const RobotModel m = testing::UrdfStyleModel();
  Random random(6);
  std::vector<Measurement> plan(4);
  for (int i = 0; i < 4; ++i) {
    plan[i].type = i == 3 ? MeasurementType::kPose : MeasurementType::kPosition;
    plan[i].marker = i % 2;
    plan[i].joints = testing::RandomJoints(m, &random);
  }
  std::vector<Measurement> measured;
  std::string error;
  ASSERT_TRUE(
      SimulateMeasurements(m, m.nominal, plan, {}, 1, &measured, &error))
      << error;
  const std::string text = MeasurementsCsvText(m, measured);
  EXPECT_EQ(text.rfind("type,marker,", 0), 0u) << text;
  std::vector<Measurement> back;
  ASSERT_TRUE(ParseMeasurementsCsv(text, "m.csv", m, &back, &error)) << error;
  ASSERT_EQ(back.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(back[i].marker, i % 2);
    EXPECT_EQ(back[i].position, measured[i].position);
  }
  // Numbers and an empty field; a marker the model does not have.
  const std::string head =
      "type,marker,q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m\n";
  ASSERT_TRUE(ParseMeasurementsCsv(
      head + "position,2,0,0,0,0,1,2,3\nposition,,0,0,0,0,1,2,3\n", "m.csv", m,
      &back, &error))
      << error;
  EXPECT_EQ(back[0].marker, 1);
  EXPECT_EQ(back[1].marker, 0);
  EXPECT_FALSE(ParseMeasurementsCsv(head + "position,smr7,0,0,0,0,1,2,3\n",
                                    "m.csv", m, &back, &error));
  EXPECT_NE(error.find("m.csv:2: marker: 'smr7' is not a marker of the model "
                       "(its markers: tool, marker2, or their numbers 1..2)"),
            std::string::npos)
      << error;
  // A file without the column is all first-marker measurements.
  const std::string plain = MeasurementsCsvText(m, {measured[0], measured[2]});
  EXPECT_EQ(plain.rfind("type,q1_rad", 0), 0u) << plain;
}

}  // namespace
}  // namespace activecal
