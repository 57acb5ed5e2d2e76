// The URDF-joint and frame conventions, the tip transform and several
// markers: forward kinematics against an independent composition of
// Eigen::Isometry3d transforms, the robot file round trip, and the model's
// structural checks.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/measurement.h"
#include "activecal/core/random.h"
#include "activecal/core/robot_file.h"
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
    T = T *
        Pose(l.origin_xyz,
             Rpy(l.origin_rpy[0], l.origin_rpy[1], l.origin_rpy[2])) *
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
      EXPECT_LE((r.links[j].origin_rpy - m.links[j].origin_rpy).norm(),
                10 * tol);
      EXPECT_LE((r.links[j].axis - m.links[j].axis).norm(), 1e-15);
    }
    // The tip goes through roll-pitch-yaw: the same transform to rounding.
    EXPECT_LT((r.tip.rotation - m.tip.rotation).norm(), 1e-14);
    EXPECT_LT((r.tip.translation - m.tip.translation).norm(), 1e-15);
    const Eigen::VectorXd q = testing::RandomJoints(m, &random);
    EXPECT_LT(
        (MeasuredPoint(r, r.nominal, q, 1) - MeasuredPoint(m, values, q, 1))
            .norm(),
        1e-13);
  }
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
  for (double pitch : {M_PI / 2, -M_PI / 2}) {
    const Eigen::Matrix3d R = Rpy(0.3, pitch, -0.7);
    const Eigen::Vector3d back = RotationToRpy(R);
    EXPECT_LT((Rpy(back[0], back[1], back[2]) - R).norm(), 1e-12);
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
