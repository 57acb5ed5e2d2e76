// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// URDF chains as robots: the chain found, the structure read, and forward
// kinematics checked against an independent implementation, orocos KDL
// (through kdl_parser), to 1e-12 m over random configurations.

#include "activecal/io/urdf_robot.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <charconv>
#include <fstream>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <limits>
#include <sstream>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/urdf_export.h"
#include "activecal/io/xml_text.h"
#include "test_util.h"

namespace activecal {
namespace {

using testing::DataFile;

std::string TestFile(const std::string& name) {
  return std::string(ACTIVECAL_TEST_DATA_DIR) + "/" + name;
}

// Shortest text that reads back to `v`.
std::string Text(double v) {
  char buffer[64];
  const auto end = std::to_chars(buffer, buffer + sizeof(buffer), v);
  return std::string(buffer, end.ptr);
}

std::string Read(const std::string& path) {
  std::string text, error;
  EXPECT_TRUE(ReadTextFile(path, &text, &error)) << error;
  return text;
}

// Joint values for KDL, and for activecal (the same: chain order).
Eigen::VectorXd RandomInside(const RobotModel& m, Random* random) {
  Eigen::VectorXd q(m.num_joints());
  for (int j = 0; j < m.num_joints(); ++j) {
    const Link& l = m.links[j];
    const double lo = std::isfinite(l.joint_min) ? l.joint_min : -M_PI;
    const double hi = std::isfinite(l.joint_max) ? l.joint_max : M_PI;
    q[j] = lo + (hi - lo) * random->Uniform();
  }
  return q;
}

// The largest difference, over `trials` random configurations inside the
// limits (RandomInside, drawn with `seed`), between activecal's tip frame of
// `m` at `values` and KDL's for the chain base..tip of `xml` (kdl_parser builds
// its own tree from the text, reading every origin from urdfdom's quaternion):
// position entries (m) in *position, rotation-matrix entries in *rotation.
void KdlDifference(const std::string& xml, const std::string& base,
                   const std::string& tip, const RobotModel& m,
                   const Eigen::VectorXd& values, double* position,
                   double* rotation, int trials = 500, uint64_t seed = 17) {
  *position = *rotation = std::numeric_limits<double>::infinity();
  KDL::Tree tree;
  ASSERT_TRUE(kdl_parser::treeFromString(xml, tree)) << xml;
  KDL::Chain chain;
  ASSERT_TRUE(tree.getChain(base, tip, chain));
  ASSERT_EQ(static_cast<int>(chain.getNrOfJoints()), m.num_joints());
  KDL::ChainFkSolverPos_recursive fk(chain);
  Random random(seed);
  double worst = 0.0, worst_rotation = 0.0;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q = RandomInside(m, &random);
    KDL::JntArray kq(m.num_joints());
    for (int j = 0; j < m.num_joints(); ++j) kq(j) = q[j];
    KDL::Frame frame;
    ASSERT_GE(fk.JntToCart(kq, frame), 0);
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    ForwardKinematics(m, values, q, &R, &t);
    for (int r = 0; r < 3; ++r) {
      worst = std::max(worst, std::abs(t[r] - frame.p(r)));
      for (int c = 0; c < 3; ++c) {
        worst_rotation =
            std::max(worst_rotation, std::abs(R(r, c) - frame.M(r, c)));
      }
    }
  }
  *position = worst;
  *rotation = worst_rotation;
}

// activecal's tip frame against KDL's for the same chain of URDF text.
void CompareTextWithKdl(const std::string& xml, const std::string& source,
                        const std::string& base, const std::string& tip) {
  RobotDescription robot;
  UrdfChainOptions options;
  options.base_link = base;
  options.tip_link = tip;
  std::string error;
  ASSERT_TRUE(ParseUrdfRobot(xml, source, options, &robot, &error)) << error;
  double position, rotation;
  KdlDifference(xml, base, tip, robot.model, robot.model.nominal, &position,
                &rotation);
  EXPECT_LT(position, 1e-12) << source << ": largest position difference (m)";
  EXPECT_LT(rotation, 1e-12) << source << ": largest rotation entry";
}

void CompareWithKdl(const std::string& path, const std::string& base,
                    const std::string& tip) {
  CompareTextWithKdl(Read(path), path, base, tip);
}

TEST(UrdfRobotTest, Ur10MatchesKdl) {
  CompareWithKdl(DataFile("ur10.urdf"), "base_link", "tool0");
  CompareWithKdl(DataFile("ur10e.urdf"), "base_link", "flange");
}

TEST(UrdfRobotTest, SevenAxisArmOnARailMatchesKdl) {
  CompareWithKdl(TestFile("arm7_rail.urdf"), "world", "tcp");
  // A chain that ends inside the arm, and one that starts on it.
  CompareWithKdl(TestFile("arm7_rail.urdf"), "world", "camera");
  CompareWithKdl(TestFile("arm7_rail.urdf"), "mount", "tcp");
}

// A chain whose every origin has pitch `pitch` (text, as written in a
// URDF): a fixed joint, a revolute, a prismatic and a continuous joint, and
// a fixed joint after them (the tip transform).
std::string PitchChain(const std::string& pitch) {
  auto origin = [&](const char* xyz, const char* roll, const char* yaw) {
    return std::string("<origin xyz=\"") + xyz + "\" rpy=\"" + roll + " " +
           pitch + " " + yaw + "\"/>";
  };
  return "<robot name=\"pitch\"><link name=\"base\"/><link name=\"a\"/>"
         "<link name=\"b\"/><link name=\"c\"/><link name=\"d\"/>"
         "<link name=\"e\"/>"
         "<joint name=\"fixed_in\" type=\"fixed\"><parent link=\"base\"/>"
         "<child link=\"a\"/>" +
         origin("0.1 0.2 0.3", "0.2", "0.1") +
         "</joint><joint name=\"rev\" type=\"revolute\"><parent "
         "link=\"a\"/><child link=\"b\"/>" +
         origin("0.3 -0.1 0.2", "0.2", "0.1") +
         "<axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\" "
         "effort=\"1\" velocity=\"1\"/></joint>"
         "<joint name=\"pri\" type=\"prismatic\"><parent link=\"b\"/>"
         "<child link=\"c\"/>" +
         origin("0 0.2 0.1", "-0.3", "0.4") +
         "<axis xyz=\"1 0 0\"/><limit lower=\"0\" upper=\"1\" "
         "effort=\"1\" velocity=\"1\"/></joint>"
         "<joint name=\"cont\" type=\"continuous\"><parent link=\"c\"/>"
         "<child link=\"d\"/>" +
         origin("0.2 0 0", "0.5", "-0.2") +
         "<axis xyz=\"0 1 0\"/></joint>"
         "<joint name=\"fixed_out\" type=\"fixed\"><parent link=\"d\"/>"
         "<child link=\"e\"/>" +
         origin("0 0 0.15", "0.1", "0.3") + "</joint></robot>";
}

// Issue #26, item 1: urdfdom's getRPY snaps a pitch within 0.256 deg of
// +-90 deg (|sin(pitch)| >= 0.99999) to +-90 deg, so origins on moving
// joints read through it were turned by up to 4.5 mrad (0.9 mm at the tip
// for the rpy="0.2 -1.569 0.1"); fixed joints were read right.
// Every origin is now read from urdfdom's quaternion: KDL's forward
// kinematics to 1e-12 at pitch exactly +-pi/2, within 1e-12 .. 1e-4 rad of
// it, just inside (0.252 deg) and outside (0.264 deg) the snapping band,
// and far from it. (Failed before the fix from the 1e-9 gap on: 1e-9 m.)
TEST(UrdfRobotTest, OriginsNearPitch90MatchKdl) {
  const double gaps[] = {0.0,    1e-12,  1e-9, 1e-6, 1e-4,
                         4.4e-3, 4.6e-3, 0.3,  1.2};
  for (double sign : {1.0, -1.0}) {
    for (double gap : gaps) {
      const std::string pitch = Text(sign * (M_PI / 2 - gap));
      SCOPED_TRACE("pitch " + pitch);
      CompareTextWithKdl(PitchChain(pitch), "pitch.urdf", "base", "d");
      CompareTextWithKdl(PitchChain(pitch), "pitch.urdf", "base", "e");
      // The moving joints' origins are the quaternions' rotations.
      RobotDescription robot;
      std::string error;
      UrdfChainOptions options;
      options.tip_link = "e";
      ASSERT_TRUE(
          ParseUrdfRobot(PitchChain(pitch), "p.urdf", options, &robot, &error))
          << error;
      const double p = sign * (M_PI / 2 - gap);
      const Eigen::Matrix3d exact = RpyRotation(0.5, p, -0.2);
      EXPECT_LT(
          (robot.model.links[2].origin_rotation - exact).cwiseAbs().maxCoeff(),
          1e-15);
    }
  }
  // The origin and the common 4-digit pi/2.
  for (const char* pitch : {"-1.569", "1.5708", "-1.5708", "1.57079632679"}) {
    SCOPED_TRACE(pitch);
    CompareTextWithKdl(PitchChain(pitch), "pitch.urdf", "base", "e");
  }
}

// The same origin on a moving joint and on a fixed joint before a moving
// joint at the identity: the same forward kinematics (0.9 mm apart before).
TEST(UrdfRobotTest, AnOriginIsTheSameOnMovingAndFixedJoints) {
  const std::string origin = "<origin xyz=\"0 0 0.2\" rpy=\"0.2 -1.569 0.1\"/>";
  const std::string joint_tail =
      "<axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\" effort=\"1\" "
      "velocity=\"1\"/></joint><joint name=\"t\" type=\"fixed\"><parent "
      "link=\"b\"/><child link=\"c\"/><origin xyz=\"0.5 0 0\"/></joint>"
      "</robot>";
  const std::string links =
      "<link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>";
  const std::string moving =
      "<robot name=\"m\">" + links +
      "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child "
      "link=\"b\"/>" +
      origin + joint_tail;
  const std::string fixed =
      "<robot name=\"f\">" + links +
      "<link name=\"f\"/><joint name=\"pre\" type=\"fixed\"><parent "
      "link=\"a\"/><child link=\"f\"/>" +
      origin +
      "</joint><joint name=\"j\" type=\"revolute\"><parent link=\"f\"/>"
      "<child link=\"b\"/>" +
      joint_tail;
  RobotDescription a, b;
  std::string error;
  ASSERT_TRUE(ParseUrdfRobot(moving, "moving.urdf", {}, &a, &error)) << error;
  ASSERT_TRUE(ParseUrdfRobot(fixed, "fixed.urdf", {}, &b, &error)) << error;
  for (double q : {-2.0, 0.0, 0.7}) {
    const Eigen::VectorXd qv = Eigen::VectorXd::Constant(1, q);
    EXPECT_LT((MeasuredPoint(a.model, a.model.nominal, qv) -
               MeasuredPoint(b.model, b.model.nominal, qv))
                  .norm(),
              1e-15)
        << q;
  }
}

TEST(UrdfRobotTest, ChainStructure) {
  RobotDescription robot;
  UrdfChainOptions options;
  options.tip_link = "tcp";
  std::string error;
  ASSERT_TRUE(
      LoadUrdfRobot(TestFile("arm7_rail.urdf"), options, &robot, &error))
      << error;
  const RobotModel& m = robot.model;
  EXPECT_EQ(m.name, "arm7_rail");
  ASSERT_EQ(m.num_joints(), 8);
  const char* names[8] = {"rail", "j1", "j2", "j3", "j4", "j5", "j6", "j7"};
  for (int j = 0; j < 8; ++j) {
    EXPECT_EQ(m.links[j].name, names[j]);
    EXPECT_EQ(m.links[j].convention, LinkConvention::kUrdf);
  }
  EXPECT_EQ(m.links[0].joint_type, JointType::kPrismatic);
  EXPECT_EQ(m.links[0].joint_min, 0.0);
  EXPECT_EQ(m.links[0].joint_max, 2.0);
  EXPECT_EQ(m.links[1].joint_min, -2.96);
  // Continuous: unbounded.
  EXPECT_TRUE(std::isinf(m.links[3].joint_min));
  EXPECT_TRUE(std::isinf(m.links[3].joint_max));
  // Axes are unit vectors; j6's (0.6, 0, 0.8) stays as it is.
  EXPECT_LT((m.links[6].axis - Eigen::Vector3d(0.6, 0, 0.8)).norm(), 1e-15);
  EXPECT_EQ(m.base.convention, LinkConvention::kFrame);
  EXPECT_EQ(m.num_markers(), 1);
  EXPECT_EQ(m.num_free(), 0);
  EXPECT_FALSE(m.tip.IsIdentity());
  // The columns the poses and measurements files use, in chain order.
  EXPECT_EQ(JointColumn(m, 0), "q1_m");
  EXPECT_EQ(JointColumn(m, 1), "q2_rad");
}

TEST(UrdfRobotTest, BadChainsAreNamed) {
  const std::string arm = Read(TestFile("arm7_rail.urdf"));
  struct Case {
    const char* name;
    std::string xml;
    UrdfChainOptions options;
    const char* message;
  };
  auto with = [](const std::string& base, const std::string& tip) {
    UrdfChainOptions o;
    o.base_link = base;
    o.tip_link = tip;
    return o;
  };
  std::string floating = arm;
  floating.replace(floating.find("type=\"revolute\""), 15, "type=\"floating\"");
  const Case cases[] = {
      {"malformed xml",
       "<robot name='x'><link name='a'>",
       {},
       "not a valid URDF"},
      {"not xml", "hello", {}, "not a valid URDF"},
      {"two leaves",
       arm,
       {},
       "has 2 leaves (camera, tcp): choose the chain's "
       "end with --tip_link"},
      {"missing tip", arm, with("", "gripper"), "no link named 'gripper'"},
      {"missing base", arm, with("nowhere", "tcp"), "no link named 'nowhere'"},
      {"not a chain", arm, with("camera", "tcp"),
       "link 'tcp' is not below link 'camera'"},
      {"reversed", arm, with("tcp", "world"),
       "link 'world' is not below link 'tcp'"},
      {"floating", floating, with("", "tcp"),
       "joint 'j1' on the chain is floating"},
      {"no moving joint", arm, with("l7", "tcp"),
       "no revolute, continuous or prismatic joint between 'l7' and 'tcp'"},
  };
  for (const Case& c : cases) {
    RobotDescription robot;
    std::string error;
    EXPECT_FALSE(ParseUrdfRobot(c.xml, "arm.urdf", c.options, &robot, &error))
        << c.name;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.name << ": " << error;
    EXPECT_EQ(error.rfind("arm.urdf: ", 0), 0u) << c.name << ": " << error;
  }
  RobotDescription robot;
  std::string error;
  EXPECT_FALSE(LoadUrdfRobot("/nonexistent/robot.urdf", {}, &robot, &error));
  EXPECT_NE(error.find("/nonexistent/robot.urdf"), std::string::npos);
}

TEST(UrdfRobotTest, ChainJointsAsTheFileHasThem) {
  std::vector<UrdfChainJoint> joints;
  UrdfChainOptions options;
  options.tip_link = "tool0";
  std::string error;
  ASSERT_TRUE(UrdfChainJoints(Read(DataFile("ur10e.urdf")), "ur10e.urdf",
                              options, &joints, &error))
      << error;
  ASSERT_EQ(joints.size(), 9u);  // 1 fixed, 6 moving, 2 fixed
  EXPECT_EQ(joints[0].name, "base_link-base_link_inertia");
  EXPECT_FALSE(joints[0].moving);
  EXPECT_EQ(joints[1].name, "shoulder_pan_joint");
  EXPECT_TRUE(joints[1].moving);
  EXPECT_EQ(joints[1].xyz.z(), 0.1807);
  EXPECT_EQ(joints[3].xyz.x(), -0.6127);
  EXPECT_EQ(joints[8].name, "flange-tool0");
}

}  // namespace
}  // namespace activecal

namespace activecal {
namespace {

// Small random calibrations of every URDF joint, a base frame and a marker.
Eigen::VectorXd Perturbed(const RobotModel& m, uint64_t seed) {
  Random random(seed);
  Eigen::VectorXd v = m.nominal;
  for (int i = 0; i < v.size(); ++i) {
    int within = 0;
    const int b = m.BlockOf(i, &within);
    const bool gain = !m.is_marker_block(b) && b > 0 && within == kUrdfGain;
    if (!gain) v[i] += (b == 0 ? 0.5 : 0.01) * random.Gaussian();
  }
  return v;
}

std::vector<Measurement> RandomMeasurements(const RobotModel& m, int n,
                                            uint64_t seed) {
  Random random(seed);
  std::vector<Measurement> out(n);
  for (int i = 0; i < n; ++i) {
    out[i].type = i % 2 ? MeasurementType::kPose : MeasurementType::kPosition;
    out[i].joints = RandomInside(m, &random);
  }
  return out;
}

// Lines of `a` and `b` that differ (same line count required).
std::vector<std::string> ChangedLines(const std::string& a,
                                      const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  std::vector<std::string> changed;
  while (std::getline(sa, la)) {
    if (!std::getline(sb, lb)) return {"(fewer lines)"};
    if (la != lb) changed.push_back(lb);
  }
  if (std::getline(sb, lb)) return {"(more lines)"};
  return changed;
}

void CheckCalibratedExport(const std::string& path, UrdfChainOptions chain,
                           int expected_changed) {
  const std::string xml = Read(path);
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(ParseUrdfRobot(xml, path, chain, &robot, &error)) << error;
  const RobotModel& m = robot.model;
  const Eigen::VectorXd values = Perturbed(m, 3);
  std::string out;
  std::vector<std::string> warnings;
  ASSERT_TRUE(
      CalibratedUrdfText(xml, path, chain, m, values, &out, &warnings, &error))
      << error;
  EXPECT_TRUE(warnings.empty());
  double worst = 1.0;
  ASSERT_TRUE(CheckUrdfAgainstModel(out, "out.urdf", chain, m, values,
                                    RandomMeasurements(m, 200, 5), &worst,
                                    &error))
      << error;
  EXPECT_LT(worst, 1e-9) << path;
  // Only the calibrated joints' origin lines changed.
  const std::vector<std::string> changed = ChangedLines(xml, out);
  EXPECT_EQ(static_cast<int>(changed.size()), expected_changed) << path;
  for (const std::string& line : changed) {
    EXPECT_NE(line.find("<origin"), std::string::npos) << line;
  }
  // And the nominal model written back changes nothing it should not: the
  // reloaded nominal model predicts what the original does.
  ASSERT_TRUE(CalibratedUrdfText(xml, path, chain, m, m.nominal, &out,
                                 &warnings, &error))
      << error;
  ASSERT_TRUE(CheckUrdfAgainstModel(out, "out.urdf", chain, m, m.nominal,
                                    RandomMeasurements(m, 50, 6), &worst,
                                    &error));
  EXPECT_LT(worst, 1e-12);
  // Joints the calibration left at their origin keep every byte.
  EXPECT_EQ(out, xml) << path;
}

TEST(UrdfExportTest, CalibratedUrdfReloadsToTheFittedModel) {
  UrdfChainOptions ur;
  ur.tip_link = "tool0";
  CheckCalibratedExport(DataFile("ur10.urdf"), ur, 6);
  UrdfChainOptions arm;
  arm.tip_link = "tcp";
  CheckCalibratedExport(TestFile("arm7_rail.urdf"), arm, 8);
}

TEST(UrdfExportTest, AJointWithoutOriginGetsOne) {
  std::string xml = Read(TestFile("arm7_rail.urdf"));
  const std::string j5 =
      "<origin xyz=\"0 0.19 0.003\" rpy=\"-1.5707963267948966 0 0.002\"/>";
  ASSERT_NE(xml.find(j5), std::string::npos);
  xml.replace(xml.find(j5), j5.size(), "");
  UrdfChainOptions chain;
  chain.tip_link = "tcp";
  RobotDescription robot;
  std::string error, out;
  ASSERT_TRUE(ParseUrdfRobot(xml, "a.urdf", chain, &robot, &error)) << error;
  const Eigen::VectorXd values = Perturbed(robot.model, 8);
  std::vector<std::string> warnings;
  ASSERT_TRUE(CalibratedUrdfText(xml, "a.urdf", chain, robot.model, values,
                                 &out, &warnings, &error))
      << error;
  double worst = 1.0;
  ASSERT_TRUE(CheckUrdfAgainstModel(out, "out.urdf", chain, robot.model, values,
                                    RandomMeasurements(robot.model, 50, 2),
                                    &worst, &error))
      << error;
  EXPECT_LT(worst, 1e-9);
}

TEST(UrdfExportTest, DhModelsAsUrdfMatchKdl) {
  // The PUMA 560 of the paper (Hayati and DH links, a Hayati base) and a
  // model with every DH convention and a prismatic joint, written as URDF:
  // KDL's forward kinematics of the file against activecal's DH kinematics.
  for (const RobotModel& m : {Puma560PaperModel(), testing::MixedModel()}) {
    Eigen::VectorXd values = m.nominal;
    if (m.name == "mixed") {
      for (int b = 1; b <= m.num_joints(); ++b) {
        values[m.block_offset(b) + kGain] = 1.0;  // a URDF has no gains
      }
    }
    std::vector<std::string> warnings;
    const std::string xml = UrdfFromModel(m, values, &warnings);
    EXPECT_TRUE(warnings.empty());
    // 300 configurations (the models' limits are finite: RandomInside
    // draws as testing::RandomJoints does).
    double position, rotation;
    KdlDifference(xml, "base_link", "tip", m, values, &position, &rotation, 300,
                  21);
    const double worst = std::max(position, rotation);
    // The PUMA's base lies 20 m away (Table II's a = 19.882 m): 1e-12
    // relative to that.
    EXPECT_LT(worst, 3e-11) << m.name;
    UrdfChainOptions chain_options;
    chain_options.base_link = "base_link";
    chain_options.tip_link = "tip";
    double reload = 1.0;
    std::string error;
    ASSERT_TRUE(CheckUrdfAgainstModel(xml, "dh.urdf", chain_options, m, values,
                                      RandomMeasurements(m, 100, 4), &reload,
                                      &error))
        << error;
    EXPECT_LT(reload, 1e-9) << m.name;
  }
  // A gain is reported, not silently dropped.
  std::vector<std::string> warnings;
  UrdfFromModel(testing::MixedModel(), testing::MixedModel().nominal,
                &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("'L4' has gain 0.98"), std::string::npos)
      << warnings[0];
}

// Issue #26, item 2: --urdf_out failed its own reload check by 1.6-3 mm on
// chains with origins near pitch 90 deg (rpy="1.5708 -1.5708 -1.5708", a
// prismatic first joint): the file's origins and the written ones were
// read through urdfdom's snapping getRPY. The export is now exact: the
// calibrated file (full corrections, then offsets only), the URDF written
// from the model, and that model through the robot YAML file all reload
// to 1e-9 m, and KDL agrees with the model to 1e-12 m. (Failed before the
// fix: 2.2e-3 m.)
TEST(UrdfExportTest, Pitch90ChainsExportExactly) {
  UrdfChainOptions chain;
  chain.tip_link = "tool";
  const std::string path = TestFile("pitch90_arm.urdf");
  CheckCalibratedExport(path, chain, 6);
  const std::string xml = Read(path);
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(ParseUrdfRobot(xml, path, chain, &robot, &error)) << error;
  const RobotModel& m = robot.model;
  const std::vector<Measurement> measurements = RandomMeasurements(m, 100, 7);
  // --parameter_set=offsets: joint offsets, base frame and tool point.
  Eigen::VectorXd offsets = m.nominal;
  for (int b = 1; b <= m.num_joints(); ++b) {
    offsets[m.block_offset(b) + kUrdfOffset] = 0.003 * b - 0.01;
  }
  offsets.head(6) << 0.1, -0.2, 0.3, 0.01, -0.02, 0.5;
  offsets.tail(6).head(3) << 0.01, 0.02, 0.03;
  std::string out;
  std::vector<std::string> warnings;
  ASSERT_TRUE(
      CalibratedUrdfText(xml, path, chain, m, offsets, &out, &warnings, &error))
      << error;
  double worst = 1.0;
  ASSERT_TRUE(CheckUrdfAgainstModel(out, "out.urdf", chain, m, offsets,
                                    measurements, &worst, &error))
      << error;
  EXPECT_LT(worst, 1e-9) << "offsets";
  // The URDF written from the model (links base_link .. tip), from the
  // model read from the file and from the model through the YAML file.
  const Eigen::VectorXd values = Perturbed(m, 11);
  RobotDescription yaml;
  ASSERT_TRUE(
      ParseRobotDescription(RobotFileText(m, values), "m.yaml", &yaml, &error))
      << error;
  UrdfChainOptions generated;
  generated.base_link = "base_link";
  generated.tip_link = "tip";
  Random random(3);
  const std::vector<const RobotModel*> models = {&m, &yaml.model};
  for (const RobotModel* model : models) {
    const Eigen::VectorXd& v = model == &m ? values : yaml.model.nominal;
    const std::string text = UrdfFromModel(*model, v, &warnings);
    EXPECT_TRUE(warnings.empty());
    ASSERT_TRUE(CheckUrdfAgainstModel(text, "gen.urdf", generated, *model, v,
                                      measurements, &worst, &error))
        << error;
    EXPECT_LT(worst, 1e-9) << (model == &m ? "from the URDF" : "from YAML");
    // KDL's chain starts at base_link: the model at the identity base.
    Eigen::VectorXd at_base = v;
    at_base.head(6).setZero();
    double position, rotation;
    KdlDifference(text, "base_link", "tip", *model, at_base, &position,
                  &rotation);
    EXPECT_LT(position, 1e-12);
    EXPECT_LT(rotation, 1e-12);
    // The robot YAML file holds the origins to rounding: the same points.
    const Eigen::VectorXd q = RandomInside(m, &random);
    EXPECT_LT(
        (MeasuredPoint(*model, v, q) - MeasuredPoint(m, values, q)).norm(),
        1e-14);
  }
}

// One escape for the URDF writer and the HTML report: the five characters,
// the apostrophe as each reader wants it, UTF-8 untouched.
TEST(XmlTextTest, FiveCharactersAndTheApostropheOfEachWriter) {
  const std::string text = "a&b <c> \"d\" it's \u00b5m";
  EXPECT_EQ(EscapeXmlText(text, XmlApostrophe::kNamed),
            "a&amp;b &lt;c&gt; &quot;d&quot; it&apos;s \u00b5m");
  EXPECT_EQ(EscapeXmlText(text, XmlApostrophe::kNumeric),
            "a&amp;b &lt;c&gt; &quot;d&quot; it&#39;s \u00b5m");
  EXPECT_EQ(EscapeXmlText("", XmlApostrophe::kNamed), "");
}

// Issue #26, item 10: a joint name holding an XML entity (name="j2 &amp;
// b", the joint "j2 & b") was compared as raw attribute text: "cannot find
// the <joint ...> element". Names are compared as the parser reads them
// (entities and character references replaced, either quote) and written
// escaped. (Failed before the fix.)
TEST(UrdfExportTest, JointNamesWithXmlEntities) {
  std::string xml = Read(TestFile("arm7_rail.urdf"));
  const std::pair<std::string, std::string> renames[] = {
      {"name=\"j2\"", "name=\"j2 &amp; b\""},
      {"name=\"j3\"", "name='a &lt;3&gt;'"},
      {"name=\"j4\"", "name=\"say &quot;4&quot;\""},
      {"name=\"j5\"", "name=\"it&apos;s 5\""},
      {"name=\"j6\"", "name=\"&#106;&#x36;\""}};
  for (const auto& [from, to] : renames) {
    ASSERT_NE(xml.find(from), std::string::npos) << from;
    xml.replace(xml.find(from), from.size(), to);
  }
  UrdfChainOptions chain;
  chain.tip_link = "tcp";
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(ParseUrdfRobot(xml, "names.urdf", chain, &robot, &error))
      << error;
  const RobotModel& m = robot.model;
  const std::vector<std::string> names = {
      "rail", "j1", "j2 & b", "a <3>", "say \"4\"", "it's 5", "j6", "j7"};
  for (int j = 0; j < m.num_joints(); ++j) EXPECT_EQ(m.links[j].name, names[j]);
  const Eigen::VectorXd values = Perturbed(m, 12);
  std::string out;
  std::vector<std::string> warnings;
  ASSERT_TRUE(CalibratedUrdfText(xml, "names.urdf", chain, m, values, &out,
                                 &warnings, &error))
      << error;
  double worst = 1.0;
  const std::vector<Measurement> measurements = RandomMeasurements(m, 50, 9);
  ASSERT_TRUE(CheckUrdfAgainstModel(out, "out.urdf", chain, m, values,
                                    measurements, &worst, &error))
      << error;
  EXPECT_LT(worst, 1e-9);
  const std::vector<std::string> changed = ChangedLines(xml, out);
  EXPECT_EQ(changed.size(), 8u);
  for (const std::string& line : changed) {
    EXPECT_NE(line.find("<origin"), std::string::npos) << line;
  }
  // Written from the model: the names escaped, read back as they were.
  const std::string text = UrdfFromModel(m, values, &warnings);
  EXPECT_NE(text.find("name=\"j2 &amp; b\""), std::string::npos);
  EXPECT_NE(text.find("name=\"it&apos;s 5\""), std::string::npos);
  UrdfChainOptions generated;
  generated.base_link = "base_link";
  generated.tip_link = "tip";
  RobotDescription back;
  ASSERT_TRUE(ParseUrdfRobot(text, "gen.urdf", generated, &back, &error))
      << error;
  for (int j = 0; j < m.num_joints(); ++j) {
    EXPECT_EQ(back.model.links[j].name, names[j]);
  }
  ASSERT_TRUE(CheckUrdfAgainstModel(text, "gen.urdf", generated, m, values,
                                    measurements, &worst, &error))
      << error;
  EXPECT_LT(worst, 1e-9);
  KDL::Tree tree;
  EXPECT_TRUE(kdl_parser::treeFromString(text, tree));
}

// The elements <joint name="..."> of a URDF's text, in order.
std::vector<std::string> JointElements(const std::string& xml) {
  std::vector<std::string> out;
  for (size_t at = xml.find("<joint "); at != std::string::npos;
       at = xml.find("<joint ", at + 1)) {
    out.push_back(xml.substr(at, xml.find("</joint>", at) - at));
  }
  return out;
}

// Issue #26, item 11: a model with continuous joints (unbounded ranges)
// was written as type="revolute" without limits, which urdfdom refuses.
// Unbounded revolute joints are written continuous, finite ones revolute
// with their limits; ranges a URDF cannot hold (one end unbounded) are
// reported. urdfdom and KDL read the file and it reloads to 1e-9 m.
// (Failed before the fix: "Joint [joint2] is of type REVOLUTE but it does
// not specify limits".)
TEST(UrdfExportTest, ContinuousJointsAreWrittenContinuous) {
  const double inf = std::numeric_limits<double>::infinity();
  RobotModel urdf_style = testing::UrdfStyleModel();
  urdf_style.links[0].joint_min = -inf;  // one end: continuous, reported
  urdf_style.links[1].joint_min = -inf;  // continuous
  urdf_style.links[1].joint_max = inf;
  urdf_style.links[2].joint_max = inf;  // prismatic: reported
  // A DH model from a robot YAML file with a continuous joint.
  RobotModel mixed = testing::MixedModel();
  for (int b = 1; b <= mixed.num_joints(); ++b) {
    mixed.nominal[mixed.block_offset(b) + kGain] = 1.0;
  }
  mixed.links[3].joint_min = -inf;
  mixed.links[3].joint_max = inf;
  RobotDescription yaml;
  std::string error;
  ASSERT_TRUE(ParseRobotDescription(RobotFileText(mixed, mixed.nominal),
                                    "mixed.yaml", &yaml, &error))
      << error;
  UrdfChainOptions generated;
  generated.base_link = "base_link";
  generated.tip_link = "tip";
  for (const RobotModel* m : {&urdf_style, &yaml.model}) {
    SCOPED_TRACE(m->name);
    std::vector<std::string> warnings;
    const std::string xml = UrdfFromModel(*m, m->nominal, &warnings);
    const std::vector<std::string> joints = JointElements(xml);
    ASSERT_EQ(static_cast<int>(joints.size()), m->num_joints() + 1);
    for (int j = 0; j < m->num_joints(); ++j) {
      const Link& l = m->links[j];
      const bool revolute = l.joint_type == JointType::kRevolute;
      const bool bounded =
          std::isfinite(l.joint_min) && std::isfinite(l.joint_max);
      const char* type = !revolute ? "type=\"prismatic\""
                         : bounded ? "type=\"revolute\""
                                   : "type=\"continuous\"";
      EXPECT_NE(joints[j].find(type), std::string::npos) << joints[j];
      EXPECT_EQ(joints[j].find("<limit") == std::string::npos,
                revolute && !bounded)
          << joints[j];
    }
    RobotDescription back;
    ASSERT_TRUE(ParseUrdfRobot(xml, "gen.urdf", generated, &back, &error))
        << error;
    for (int j = 0; j < m->num_joints(); ++j) {
      const Link& l = m->links[j];
      const Link& r = back.model.links[j];
      if (std::isfinite(l.joint_min) && std::isfinite(l.joint_max)) {
        EXPECT_EQ(r.joint_min, l.joint_min);
        EXPECT_EQ(r.joint_max, l.joint_max);
      } else if (l.joint_type == JointType::kRevolute) {
        EXPECT_TRUE(std::isinf(r.joint_min) && std::isinf(r.joint_max));
      }
    }
    double worst = 1.0;
    ASSERT_TRUE(CheckUrdfAgainstModel(xml, "gen.urdf", generated, *m,
                                      m->nominal, RandomMeasurements(*m, 50, 3),
                                      &worst, &error))
        << error;
    EXPECT_LT(worst, 1e-9);
    // KDL's chain starts at base_link: a 6-DOF base at the identity.
    Eigen::VectorXd at_base = m->nominal;
    if (m->base.convention == LinkConvention::kFrame) at_base.head(6).setZero();
    double position, rotation;
    KdlDifference(xml, "base_link", "tip", *m, at_base, &position, &rotation);
    EXPECT_LT(position, 1e-12);
    EXPECT_LT(rotation, 1e-12);
    if (m == &urdf_style) {
      ASSERT_EQ(warnings.size(), 2u);
      EXPECT_NE(warnings[0].find("joint 'joint1' has the range [-inf, 2.5] "
                                 "rad, which a URDF cannot hold"),
                std::string::npos)
          << warnings[0];
      EXPECT_NE(warnings[1].find("joint 'joint3' has the range [-0.1, inf] m"),
                std::string::npos)
          << warnings[1];
    } else {
      EXPECT_TRUE(warnings.empty());
    }
  }
}

// Issue #26, item 12: a robot with a link named "tip_fixed" was written
// with two joints of that name ("joint 'tip_fixed' is not unique"). The
// generated joint takes a name no joint of the model has; the generated
// links (base_link, link1 .. linkN, tip) live apart from the joints' names.
// Every generated name as a link name of the model, and several at once.
// (Failed before the fix for "tip_fixed".)
TEST(UrdfExportTest, GeneratedNamesNeverCollide) {
  const std::vector<std::vector<std::string>> cases = {
      {"tip_fixed"},
      {"base_link"},
      {"link1"},
      {"link2"},
      {"tip"},
      {"tip_fixed_2"},
      {"tip_fixed", "tip_fixed_2", "tip_fixed_3", "tip"}};
  UrdfChainOptions generated;
  generated.base_link = "base_link";
  generated.tip_link = "tip";
  for (const std::vector<std::string>& names : cases) {
    SCOPED_TRACE(names[0]);
    RobotModel m = testing::MixedModel();
    for (int b = 1; b <= m.num_joints(); ++b) {
      m.nominal[m.block_offset(b) + kGain] = 1.0;
    }
    for (size_t k = 0; k < names.size(); ++k) m.links[k].name = names[k];
    std::vector<std::string> warnings;
    const std::string xml = UrdfFromModel(m, m.nominal, &warnings);
    RobotDescription back;
    std::string error;
    ASSERT_TRUE(ParseUrdfRobot(xml, "gen.urdf", generated, &back, &error))
        << error;
    for (int j = 0; j < m.num_joints(); ++j) {
      EXPECT_EQ(back.model.links[j].name, m.links[j].name);
    }
    double worst = 1.0;
    ASSERT_TRUE(CheckUrdfAgainstModel(xml, "gen.urdf", generated, m, m.nominal,
                                      RandomMeasurements(m, 30, 1), &worst,
                                      &error))
        << error;
    EXPECT_LT(worst, 1e-9);
    KDL::Tree tree;
    EXPECT_TRUE(kdl_parser::treeFromString(xml, tree));
  }
}

}  // namespace
}  // namespace activecal
