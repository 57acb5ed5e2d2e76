// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The metrology frames as ROS 2 static transforms (io/ros_frames.h): the
// script and the TFMessage YAML read back to the model's transforms; the
// readers' forms and errors.

#include "activecal/io/ros_frames.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "activecal/io/frames_file.h"
#include "activecal/io/robot_loader.h"

namespace activecal {
namespace {

// Written out here, not through the library: R = Rz(rz) Ry(ry) Rx(rx).
Eigen::Matrix4d Pose(double x, double y, double z, double rx, double ry,
                     double rz) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  T.topRightCorner<3, 1>() << x, y, z;
  return T;
}

// The UR10 with a registered base and two markers, one turned by nearly a
// half turn (the quaternion's hard case) and one at pitch 90 deg.
RobotDescription Ur10WithFrames() {
  RobotDescription robot;
  std::string error;
  RobotLoadOptions options;
  options.chain.tip_link = "tool0";
  EXPECT_TRUE(LoadRobot(std::string(ACTIVECAL_DATA_DIR) + "/ur10.urdf", options,
                        &robot, &error))
      << error;
  EXPECT_TRUE(ParseFramesFile(
      "base: {xyz: [1.25, -0.5, 0.125], rpy: [0.1, -0.2, 2.5]}\n"
      "markers:\n"
      "  - {name: smr1, xyz: [0.01, 0.02, 0.13], rpy: [3.14159, 0.001, "
      "-0.002]}\n"
      "  - {name: smr2, xyz: [-0.05, 0, 0.1], rpy: [0.3, 1.5707963267948966, "
      "0]}\n",
      "frames.yaml", &robot, &error))
      << error;
  return robot;
}

std::vector<Eigen::Matrix4d> ExpectedUr10() {
  return {Pose(1.25, -0.5, 0.125, 0.1, -0.2, 2.5),
          Pose(0.01, 0.02, 0.13, 3.14159, 0.001, -0.002),
          Pose(-0.05, 0, 0.1, 0.3, M_PI / 2, 0)};
}

void ExpectUr10Transforms(const std::vector<RosTransform>& t,
                          const std::string& what) {
  ASSERT_EQ(t.size(), 3u) << what;
  const std::vector<Eigen::Matrix4d> expected = ExpectedUr10();
  const char* parents[] = {"tracker", "tool0", "tool0"};
  const char* children[] = {"base_link", "smr1", "smr2"};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(t[k].frame_id, parents[k]) << what;
    EXPECT_EQ(t[k].child_frame_id, children[k]) << what;
    EXPECT_LT((t[k].Matrix() - expected[k]).cwiseAbs().maxCoeff(), 1e-12)
        << what << " transform " << k << "\n"
        << t[k].Matrix() << "\nexpected\n"
        << expected[k];
    EXPECT_GE(t[k].rotation.w(), 0.0) << what;
    EXPECT_NEAR(t[k].rotation.norm(), 1.0, 1e-15) << what;
  }
}

RosFramesOptions Ur10Options() {
  RosFramesOptions options;
  options.device_frame = "tracker";
  options.base_frame = "base_link";
  options.tip_frame = "tool0";
  return options;
}

TEST(RosFramesTest, ScriptAndYamlReadBackToTheModelsTransforms) {
  const RobotDescription robot = Ur10WithFrames();
  std::vector<RosTransform> transforms;
  std::string error;
  ASSERT_TRUE(MetrologyRosTransforms(robot.model, robot.model.nominal,
                                     Ur10Options(), &transforms, &error))
      << error;
  ExpectUr10Transforms(transforms, "MetrologyRosTransforms");

  const std::string script =
      StaticTransformPublisherScript(transforms, "calibrated\nby a test");
  EXPECT_EQ(script.rfind("#!/bin/sh\n# calibrated\n# by a test\n", 0), 0u)
      << script;
  EXPECT_NE(script.find("ros2 run tf2_ros static_transform_publisher --x 1.25 "
                        "--y -0.5 --z 0.125 --qx "),
            std::string::npos)
      << script;
  EXPECT_NE(script.find("--frame-id tracker --child-frame-id base_link &\n"),
            std::string::npos);
  EXPECT_EQ(script.substr(script.size() - 5), "wait\n");
  std::vector<RosTransform> back;
  ASSERT_TRUE(
      ParseStaticTransformPublisherScript(script, "frames.sh", &back, &error))
      << error;
  ExpectUr10Transforms(back, "script");
  // Shortest round-trip numbers: the same doubles.
  for (size_t k = 0; k < back.size(); ++k) {
    EXPECT_EQ(back[k].translation, transforms[k].translation);
    EXPECT_EQ(back[k].rotation.coeffs(), transforms[k].rotation.coeffs());
  }

  const std::string yaml = Tf2StaticTransformsYaml(transforms, "calibrated");
  ASSERT_TRUE(ParseTf2StaticTransformsYaml(yaml, "tf.yaml", &back, &error))
      << error;
  ExpectUr10Transforms(back, "yaml");
  for (size_t k = 0; k < back.size(); ++k) {
    EXPECT_EQ(back[k].translation, transforms[k].translation);
    EXPECT_EQ(back[k].rotation.coeffs(), transforms[k].rotation.coeffs());
  }
  // The TFMessage layout (python/tests/test_export.py reads it with
  // PyYAML, as ROS 2 does).
  EXPECT_EQ(yaml.rfind("# calibrated\ntransforms:\n  - header:\n"
                       "      stamp: {sec: 0, nanosec: 0}\n"
                       "      frame_id: \"tracker\"\n"
                       "    child_frame_id: \"base_link\"\n"
                       "    transform:\n"
                       "      translation: {x: 1.25, y: -0.5, z: 0.125}\n"
                       "      rotation: {x: ",
                       0),
            0u)
      << yaml;
  // 0 as 0.0: a float, not an int, for YAML 1.1 readers.
  EXPECT_NE(yaml.find("translation: {x: -0.05, y: 0.0, z: 0.1}"),
            std::string::npos)
      << yaml;
}

// The quaternion, not roll-pitch-yaw: at pitch +-90 deg (where rpy is
// singular) and at half turns about each axis the transform is exact.
TEST(RosFramesTest, SingularAndHalfTurnRotations) {
  RobotDescription robot = Ur10WithFrames();
  const double angles[][3] = {{0.3, M_PI / 2, -0.4}, {0.3, -M_PI / 2, 2.0},
                              {M_PI, 0, 0},          {0, M_PI, 0},
                              {0, 0, M_PI},          {M_PI, M_PI / 2, M_PI}};
  for (const auto& a : angles) {
    robot.model.nominal.segment(3, 3) << a[0], a[1], a[2];
    std::vector<RosTransform> transforms, back;
    std::string error;
    ASSERT_TRUE(MetrologyRosTransforms(robot.model, robot.model.nominal,
                                       Ur10Options(), &transforms, &error));
    ASSERT_TRUE(ParseTf2StaticTransformsYaml(
        Tf2StaticTransformsYaml(transforms), "tf.yaml", &back, &error))
        << error;
    const Eigen::Matrix4d expected = Pose(1.25, -0.5, 0.125, a[0], a[1], a[2]);
    EXPECT_LT((back[0].Matrix() - expected).cwiseAbs().maxCoeff(), 1e-12)
        << a[0] << " " << a[1] << " " << a[2];
  }
}

// Random rotations, large angles included: the quaternion has w >= 0 (one
// of the two of each rotation) and gives the matrix back.
TEST(RosFramesTest, RandomRotationsHaveCanonicalQuaternions) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  int negative_from_eigen = 0;
  for (int n = 0; n < 200; ++n) {
    const double a = angle(rng), b = angle(rng) / 2, c = angle(rng);
    const Eigen::Matrix4d T = Pose(0.1, 0.2, 0.3, a, b, c);
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    negative_from_eigen += Eigen::Quaterniond(R).w() < 0;
    const RosTransform t =
        RosTransformFromMatrix("a", "b", R, T.topRightCorner<3, 1>());
    EXPECT_GE(t.rotation.w(), 0.0);
    EXPECT_LT((t.Matrix() - T).cwiseAbs().maxCoeff(), 1e-14);
  }
  // The sign choice is activecal's, not a property of the conversion.
  EXPECT_GT(negative_from_eigen, 0);
}

// A base that is not a 6-DOF frame (the PUMA's DH base) is robot geometry:
// only the markers are written.
TEST(RosFramesTest, DhBaseHasNoBaseTransform) {
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(LoadRobot(std::string(ACTIVECAL_DATA_DIR) + "/puma560.yaml",
                        RobotLoadOptions(), &robot, &error))
      << error;
  std::vector<RosTransform> transforms;
  ASSERT_TRUE(MetrologyRosTransforms(robot.model, robot.model.nominal,
                                     RosFramesOptions(), &transforms, &error))
      << error;
  ASSERT_EQ(transforms.size(), static_cast<size_t>(robot.model.num_markers()));
  EXPECT_EQ(transforms[0].frame_id, "tip");
  const double* m = robot.model.nominal.data() +
                    robot.model.block_offset(robot.model.marker_block(0));
  EXPECT_LT((transforms[0].Matrix() - Pose(m[0], m[1], m[2], m[3], m[4], m[5]))
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
}

TEST(RosFramesTest, BadFrameNames) {
  const RobotDescription robot = Ur10WithFrames();
  std::vector<RosTransform> transforms;
  std::string error;
  RosFramesOptions options = Ur10Options();
  options.device_frame = "my tracker";
  EXPECT_FALSE(MetrologyRosTransforms(robot.model, robot.model.nominal, options,
                                      &transforms, &error));
  EXPECT_EQ(error,
            "device frame 'my tracker' has ' ': use letters, digits, '_', "
            "'-', '.' and '/'");
  options = Ur10Options();
  options.base_frame = "/base_link";
  EXPECT_FALSE(MetrologyRosTransforms(robot.model, robot.model.nominal, options,
                                      &transforms, &error));
  EXPECT_EQ(error,
            "base frame '/base_link' starts with '/' (tf2 frame ids do not)");
  options = Ur10Options();
  options.tip_frame = "";
  EXPECT_FALSE(MetrologyRosTransforms(robot.model, robot.model.nominal, options,
                                      &transforms, &error));
  EXPECT_EQ(error, "tip frame '' is empty");
  options = Ur10Options();
  options.device_frame = "base_link";
  EXPECT_FALSE(MetrologyRosTransforms(robot.model, robot.model.nominal, options,
                                      &transforms, &error));
  EXPECT_EQ(error, "the device frame and the base frame are both 'base_link'");
  options = Ur10Options();
  options.device_frame = "smr2";  // a marker's name
  EXPECT_FALSE(MetrologyRosTransforms(robot.model, robot.model.nominal, options,
                                      &transforms, &error));
  EXPECT_EQ(error,
            "marker 'smr2' has the name of another frame (the device, base "
            "or tip frame, or another marker): tf2 frames need one parent");
  EXPECT_TRUE(transforms.empty());  // untouched on failure
}

std::vector<RosTransform> ReadScript(const std::string& text, bool* ok,
                                     std::string* error) {
  std::vector<RosTransform> t;
  *ok = ParseStaticTransformPublisherScript(text, "f.sh", &t, error);
  return t;
}

// A text and the one error its reader gives.
struct BadText {
  std::string text, message;
};

// Every case refused by parse(text, &transforms, &error), the error
// exactly its message.
template <typename Parse>
void ExpectRefused(const std::vector<BadText>& cases, Parse parse) {
  for (const BadText& c : cases) {
    std::vector<RosTransform> t;
    std::string error;
    EXPECT_FALSE(parse(c.text, &t, &error)) << c.text;
    EXPECT_EQ(error, c.message) << c.text;
  }
}

TEST(RosFramesTest, ScriptForms) {
  bool ok;
  std::string error;
  const Eigen::Matrix4d expected = Pose(1, 2, 3, 0.1, 0.2, 0.3);
  const Eigen::Quaterniond q(expected.topLeftCorner<3, 3>());
  char quaternion[128];
  std::snprintf(quaternion, sizeof(quaternion), "%.17g %.17g %.17g %.17g",
                q.x(), q.y(), q.z(), q.w());
  // ROS 2 flags with angles (R = Rz(yaw) Ry(pitch) Rx(roll)), continued
  // over lines; the positional forms (ROS 1, old ROS 2).
  const std::string text =
      "# comment\n\n"
      "ros2 run tf2_ros static_transform_publisher --x 1 --y 2 --z 3 \\\n"
      "   --roll 0.1 --pitch 0.2 --yaw 0.3 --frame-id a --child-frame-id b\n"
      "rosrun tf2_ros static_transform_publisher 1 2 3 0.3 0.2 0.1 a c &\n"
      "ros2 run tf2_ros static_transform_publisher 1 2 3 " +
      std::string(quaternion) + " a d\n" +
      "ros2 run tf2_ros static_transform_publisher --frame-id a "
      "--child-frame-id e\n"
      "wait\n";
  const std::vector<RosTransform> t = ReadScript(text, &ok, &error);
  ASSERT_TRUE(ok) << error;
  ASSERT_EQ(t.size(), 4u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(t[k].frame_id, "a");
    EXPECT_LT((t[k].Matrix() - expected).cwiseAbs().maxCoeff(), 1e-15) << k;
  }
  EXPECT_EQ(t[1].child_frame_id, "c");
  EXPECT_EQ(t[3].child_frame_id, "e");
  EXPECT_EQ(t[3].Matrix(), Eigen::Matrix4d::Identity());
}

TEST(RosFramesTest, ScriptErrors) {
  const std::string cmd = "ros2 run tf2_ros static_transform_publisher ";
  const std::vector<BadText> cases = {
      {"echo hi\n",
       "f.sh:1: expected a 'ros2 run tf2_ros static_transform_publisher ...' "
       "command, got 'echo hi'"},
      {"\n" + cmd + "--x 1 --frame-id a\n",
       "f.sh:2: --frame-id and --child-frame-id are required"},
      {cmd + "--x one --frame-id a --child-frame-id b\n",
       "f.sh:1: --x: expected a number, got 'one'"},
      {cmd + "--x 1 --x 2 --frame-id a --child-frame-id b\n",
       "f.sh:1: --x given twice"},
      {cmd + "--frame-id a --child-frame-id b --scale 2\n",
       "f.sh:1: unknown argument '--scale' (expected --x --y --z, --qx --qy "
       "--qz --qw or --roll --pitch --yaw, --frame-id, --child-frame-id)"},
      {cmd + "--frame-id a --child-frame-id\n",
       "f.sh:1: --child-frame-id: missing its value"},
      {cmd + "--qw 1 --yaw 2 --frame-id a --child-frame-id b\n",
       "f.sh:1: both a quaternion (--qx ...) and angles (--roll ...) given"},
      {cmd + "1 2 3 a b\n",
       "f.sh:1: expected the flags --x ... --child-frame-id, or 9 (x y z qx "
       "qy qz qw frame child) or 8 (x y z yaw pitch roll frame child) "
       "arguments, got 5"},
      {cmd + "0 0 0 0 0 0 0 a b\n",
       "f.sh:1: the quaternion (0, 0, 0, 0) is not a unit quaternion "
       "(squared norm 0)"},
      {cmd + "--x 1 \\\n",
       "f.sh:1: the file ends in a line continuation ('\\')"},
  };
  ExpectRefused(cases, [](const std::string& text, std::vector<RosTransform>* t,
                          std::string* error) {
    return ParseStaticTransformPublisherScript(text, "f.sh", t, error);
  });
}

// tf2's tolerance: a squared norm within 0.01 of 1 is normalised, beyond
// it refused.
TEST(RosFramesTest, QuaternionNormThreshold) {
  for (double norm2 : {1.0095, 0.9905, 1.0105, 0.9895}) {
    const double w = std::sqrt(norm2);
    const std::string yaml =
        "transforms:\n  - header: {frame_id: a}\n    child_frame_id: b\n"
        "    transform:\n      translation: {x: 0.0, y: 0.0, z: 0.0}\n"
        "      rotation: {x: 0.0, y: 0.0, z: 0.0, w: " +
        std::to_string(w) + "}\n";
    std::vector<RosTransform> t;
    std::string error;
    const bool ok = ParseTf2StaticTransformsYaml(yaml, "tf.yaml", &t, &error);
    EXPECT_EQ(ok, std::abs(norm2 - 1) < 0.01) << norm2 << ": " << error;
    if (ok) {
      EXPECT_EQ(t[0].rotation.w(), 1.0);
    } else {
      EXPECT_EQ(error.rfind("tf.yaml:6:17: transforms[0].transform.rotation: "
                            "the quaternion (0, 0, 0, ",
                            0),
                0u)
          << error;
    }
  }
}

TEST(RosFramesTest, YamlErrors) {
  const std::vector<BadText> cases = {
      {"- 1\n",
       "tf.yaml:1:1: expected a mapping with transforms (a "
       "tf2_msgs/msg/TFMessage)"},
      {"transforms: 3\n",
       "tf.yaml:1:13: transforms: expected a list of "
       "transforms"},
      {"frames: []\n",
       "tf.yaml:1:1: frames: unknown field (expected one of: transforms)"},
      {"transforms:\n  - child_frame_id: b\n",
       "tf.yaml:2:5: transforms[0].header: missing"},
      {"transforms:\n  - {header: {frame_id: a}, child_frame_id: b, "
       "transform: {translation: {x: 0, y: 0}, rotation: {x: 0, y: 0, z: 0, "
       "w: 1}}}\n",
       "tf.yaml:2:73: transforms[0].transform.translation.z: missing"},
      {"transforms:\n  - {header: {frame_id: a}, child_frame_id: b, "
       "transform: {translation: {x: 0, y: 0, z: 1m}, rotation: {x: 0, y: "
       "0, z: 0, w: 1}}}\n",
       "tf.yaml:2:89: transforms[0].transform.translation.z: expected a "
       "number, got '1m'"},
      {"transforms:\n  - {header: {frame_id: ''}, child_frame_id: b}\n",
       "tf.yaml:2:5: transforms[0]: empty frame id"},
  };
  ExpectRefused(cases, [](const std::string& text, std::vector<RosTransform>* t,
                          std::string* error) {
    return ParseTf2StaticTransformsYaml(text, "tf.yaml", t, error);
  });
}

}  // namespace
}  // namespace activecal
