// URDF chains as robots: the chain found, the structure read, and forward
// kinematics checked against an independent implementation, orocos KDL
// (through kdl_parser), to 1e-12 m over random configurations.

#include "activecal/io/urdf_robot.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <sstream>
#include <string>

#include "activecal/io/csv_files.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/io/urdf_export.h"
#include "test_util.h"

namespace activecal {
namespace {

std::string DataFile(const std::string& name) {
  return std::string(ACTIVECAL_DATA_DIR) + "/" + name;
}

std::string TestFile(const std::string& name) {
  return std::string(ACTIVECAL_TEST_DATA_DIR) + "/" + name;
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

// activecal's tip frame against KDL's for the same chain.
void CompareWithKdl(const std::string& path, const std::string& base,
                    const std::string& tip) {
  const std::string xml = Read(path);
  RobotDescription robot;
  UrdfChainOptions options;
  options.base_link = base;
  options.tip_link = tip;
  std::string error;
  ASSERT_TRUE(ParseUrdfRobot(xml, path, options, &robot, &error)) << error;
  const RobotModel& m = robot.model;
  KDL::Tree tree;
  ASSERT_TRUE(kdl_parser::treeFromString(xml, tree));
  KDL::Chain chain;
  ASSERT_TRUE(tree.getChain(base, tip, chain));
  ASSERT_EQ(static_cast<int>(chain.getNrOfJoints()), m.num_joints());
  KDL::ChainFkSolverPos_recursive fk(chain);
  Random random(17);
  double worst = 0.0, worst_rotation = 0.0;
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::VectorXd q = RandomInside(m, &random);
    KDL::JntArray kq(m.num_joints());
    for (int j = 0; j < m.num_joints(); ++j) kq(j) = q[j];
    KDL::Frame frame;
    ASSERT_GE(fk.JntToCart(kq, frame), 0);
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    ForwardKinematics(m, m.nominal, q, &R, &t);
    for (int r = 0; r < 3; ++r) {
      worst = std::max(worst, std::abs(t[r] - frame.p(r)));
      for (int c = 0; c < 3; ++c) {
        worst_rotation =
            std::max(worst_rotation, std::abs(R(r, c) - frame.M(r, c)));
      }
    }
  }
  EXPECT_LT(worst, 1e-12) << path << ": largest position difference (m)";
  EXPECT_LT(worst_rotation, 1e-12) << path << ": largest rotation entry";
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
    KDL::Tree tree;
    ASSERT_TRUE(kdl_parser::treeFromString(xml, tree)) << xml;
    KDL::Chain chain;
    ASSERT_TRUE(tree.getChain("base_link", "tip", chain));
    ASSERT_EQ(static_cast<int>(chain.getNrOfJoints()), m.num_joints());
    KDL::ChainFkSolverPos_recursive fk(chain);
    Random random(21);
    double worst = 0.0;
    for (int trial = 0; trial < 300; ++trial) {
      const Eigen::VectorXd q = testing::RandomJoints(m, &random);
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
          worst = std::max(worst, std::abs(R(r, c) - frame.M(r, c)));
        }
      }
    }
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

}  // namespace
}  // namespace activecal
