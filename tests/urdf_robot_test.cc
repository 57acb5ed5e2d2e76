// URDF chains as robots: the chain found, the structure read, and forward
// kinematics checked against an independent implementation, orocos KDL
// (through kdl_parser), to 1e-12 m over random configurations.

#include "activecal/core/urdf_robot.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <sstream>
#include <string>

#include "activecal/core/csv_files.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/random.h"
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
