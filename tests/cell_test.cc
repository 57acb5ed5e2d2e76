// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The cell (cell/): the cell file and its bad input, robot collision
// geometry, the checks at their thresholds, FCL's distances against
// analytic ones, the pool filter and its rejected CSV, the measurable pool,
// the tour, and the hook in BuildSelectionPool.

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>

#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/pool_builder.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/cell/cell_checker.h"
#include "activecal/cell/cell_file.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/cell/measurable_pool.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/cell/rejection_counts.h"
#include "activecal/cell/robot_collision.h"
#include "activecal/cell/tour.h"
#include "activecal/core/joint_sampling.h"
#include "activecal/core/lattice.h"
#include "activecal/core/random.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/selection/greedy.h"
#include "activecal/selection/information_matrix.h"
#include "test_util.h"

namespace activecal {
namespace {

constexpr double kDeg = M_PI / 180.0;
const std::string kData = ACTIVECAL_DATA_DIR;

// Unique per test and process: ctest runs the tests of this binary in
// parallel, and two tests writing one path read each other's half-written
// files.
std::string TempPath(const std::string& name) {
  const ::testing::TestInfo* test =
      ::testing::UnitTest::GetInstance()->current_test_info();
  return ::testing::TempDir() + "/activecal_cell_" +
         std::to_string(static_cast<long>(getpid())) + "_" +
         (test != nullptr ? std::string(test->name()) + "_" : "") + name;
}

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

Cell ParseCellOrDie(const std::string& text, const std::string& dir = "") {
  Cell cell;
  std::string error;
  EXPECT_TRUE(ParseCellFile(text, "cell.yaml", dir, &cell, &error)) << error;
  return cell;
}

std::string CellError(const std::string& text, const std::string& dir = "") {
  Cell cell;
  std::string error;
  EXPECT_FALSE(ParseCellFile(text, "cell.yaml", dir, &cell, &error)) << text;
  return error;
}

// ---------------------------------------------------------------------
// A one-joint stick: a revolute joint about z at (0, 0, 0.5), an arm box
// 0.5 m along x, a prismatic slide along x at its end, the tip after it.

const std::string kStickUrdf = testing::TestDataText("stick.urdf");

struct Fixture {
  RobotDescription robot;
  RobotCollisionModel collision;
  Cell cell;
  CellChecker checker;
};

// Builds the checker of `urdf` (or the robot file `yaml`) in `cell_text`.
bool MakeChecker(const std::string& urdf, const std::string& cell_text,
                 Fixture* f, std::string* error) {
  UrdfChainOptions chain;
  chain.tip_link = "tip";
  if (!ParseUrdfRobot(urdf, "robot.urdf", chain, &f->robot, error) ||
      !ParseUrdfCollision(urdf, "robot.urdf", "", chain, f->robot.model,
                          &f->collision, error) ||
      !ParseCellFile(cell_text, "cell.yaml", "", &f->cell, error)) {
    return false;
  }
  return f->checker.Init(f->robot.model, f->collision, f->cell, error);
}

std::string StickCell(const std::string& extra, double normal_angle_deg = 0,
                      const std::string& device = "") {
  const double a = normal_angle_deg * kDeg;
  char target[200];
  std::snprintf(target, sizeof(target),
                "targets:\n  - {xyz_m: [0, 0, 0], normal: [%.17g, %.17g, 0], "
                "acceptance_deg: 30}\n",
                std::cos(a), std::sin(a));
  return "joint_margin_deg: 3\njoint_margin_m: 0.01\n" + extra +
         (device.empty() ? "device: {type: laser_tracker, xyz_m: [2, 0, 0.5], "
                           "range_m: [1, 6]}\n"
                         : device) +
         target;
}

// `urdf` with one more link, `name`: a 2 x 20 x 20 cm plate (thin along
// x) at `xyz` in link `parent`, fixed to it.
std::string WithFixedPlate(std::string urdf, const std::string& name,
                           const std::string& parent, const std::string& xyz) {
  urdf.replace(urdf.find("  <link name=\"tip\"/>"), 0,
               "  <link name=\"" + name + "\"><collision><origin xyz=\"" + xyz +
                   "\" rpy=\"0 0 0\"/><geometry><box size=\"0.02 0.2 0.2\"/>"
                   "</geometry></collision></link>\n");
  urdf.replace(urdf.find("</robot>"), 0,
               "  <joint name=\"" + name +
                   "_joint\" type=\"fixed\"><parent "
                   "link=\"" +
                   parent + "\"/><child link=\"" + name +
                   "\"/><origin xyz=\"0 0 0\" rpy=\"0 0 0\"/></joint>\n");
  return urdf;
}

PoseVerdict CheckStick(const Fixture& f, double q1, double q2) {
  auto w = f.checker.NewWorkspace();
  const double q[2] = {q1, q2};
  return f.checker.Check(q, w.get());
}

// What blocks the stick's line of sight at q = (0, 0.1) in StickCell(""):
// the link or obstacle, else the verdict.
std::string LineOfSightBlocker(const std::string& urdf) {
  Fixture f;
  std::string error;
  if (!MakeChecker(urdf, StickCell(""), &f, &error)) return error;
  const PoseVerdict v = CheckStick(f, 0.0, 0.1);
  return v.reason == RejectionReason::kLineOfSight ? f.checker.Detail(v)
                                                   : f.checker.Describe(v);
}

TEST(CellCheckTest, TargetExactlyAtTheAcceptanceAnglePassesJustPastFails) {
  // At q = 0 the target is at (0.5, 0, 0.5) and the device straight along
  // +x: the angle is the normal's angle in the tip frame.
  for (double angle : {0.0, 29.0, 30.0}) {
    Fixture f;
    std::string error;
    ASSERT_TRUE(MakeChecker(kStickUrdf, StickCell("", angle), &f, &error))
        << error;
    const PoseVerdict v = CheckStick(f, 0.0, 0.1);
    EXPECT_TRUE(v.feasible()) << angle << ": " << f.checker.Describe(v);
    EXPECT_EQ(v.targets_seen, 1u);
  }
  for (double angle : {30.0 + 1e-6 / kDeg, 31.0, 120.0}) {
    Fixture f;
    std::string error;
    ASSERT_TRUE(MakeChecker(kStickUrdf, StickCell("", angle), &f, &error));
    EXPECT_EQ(CheckStick(f, 0.0, 0.1).reason, RejectionReason::kFacingAway)
        << angle;
  }
}

TEST(CellCheckTest, JointExactlyAtTheMarginPassesJustInsideItFails) {
  Fixture f;
  std::string error;
  // A wide acceptance so that turning the stick keeps the target seen.
  std::string text = StickCell("", 0);
  text.replace(text.find("acceptance_deg: 30"), 18, "acceptance_deg: 90");
  ASSERT_TRUE(MakeChecker(kStickUrdf, text, &f, &error)) << error;
  const double m = 3 * kDeg;
  EXPECT_DOUBLE_EQ(f.checker.joint_margin(0), m);
  EXPECT_DOUBLE_EQ(f.checker.joint_margin(1), 0.01);
  EXPECT_TRUE(CheckStick(f, 1.0 - m, 0.1).feasible());
  EXPECT_TRUE(CheckStick(f, -1.0 + m, 0.1).feasible());
  for (double q1 : {1.0 - m + 1e-9, -1.0 + m - 1e-9, 1.0}) {
    const PoseVerdict v = CheckStick(f, q1, 0.1);
    EXPECT_EQ(v.reason, RejectionReason::kJointMargin) << q1;
    EXPECT_EQ(f.checker.Detail(v), "j1");
  }
  // The prismatic joint's margin is in metres.
  EXPECT_TRUE(CheckStick(f, 0.0, 0.01).feasible());
  EXPECT_TRUE(CheckStick(f, 0.0, 0.19).feasible());
  EXPECT_EQ(CheckStick(f, 0.0, 0.01 - 1e-9).reason,
            RejectionReason::kJointMargin);
  EXPECT_EQ(f.checker.Detail(CheckStick(f, 0.0, 0.2)), "j2");
}

TEST(CellCheckTest, JointMarginOverrideByName) {
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(kStickUrdf,
                          StickCell("joint_margin_override_deg: {j1: 10}\n"),
                          &f, &error))
      << error;
  EXPECT_DOUBLE_EQ(f.checker.joint_margin(0), 10 * kDeg);
  EXPECT_EQ(CheckStick(f, 1.0 - 5 * kDeg, 0.1).reason,
            RejectionReason::kJointMargin);
  // A name the robot does not have: where it was given.
  Fixture g;
  EXPECT_FALSE(MakeChecker(
      kStickUrdf, StickCell("joint_margin_override_deg: {elbow: 10}\n"), &g,
      &error));
  EXPECT_NE(error.find("cell.yaml:3:29: joint_margin_override_deg.elbow: the "
                       "robot has no joint named 'elbow' (joints: j1, j2)"),
            std::string::npos)
      << error;
  // A margin that leaves no range.
  EXPECT_FALSE(MakeChecker(kStickUrdf,
                           StickCell("joint_margin_override_m: {j2: 0.11}\n"),
                           &g, &error));
  EXPECT_NE(error.find("cell.yaml:3:27: joint_margin_override_m.j2: joint "
                       "'j2' has a range of 0.2 m, narrower than twice its "
                       "margin (0.11 m)"),
            std::string::npos)
      << error;
  // The margin of every joint, where it was given, in its unit.
  EXPECT_FALSE(MakeChecker(kStickUrdf, "joint_margin_deg: 60\n", &g, &error));
  EXPECT_NE(error.find("cell.yaml:1:19: joint_margin_deg: joint 'j1' has a "
                       "range of 114.6 deg, narrower than twice its margin "
                       "(60 deg)"),
            std::string::npos)
      << error;
}

TEST(CellCheckTest, OutOfRange) {
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(
      kStickUrdf,
      StickCell("", 0,
                "device: {type: laser_tracker, xyz_m: [2, 0, 0.5], range_m: "
                "[1.45, 6]}\n"),
      &f, &error))
      << error;
  // The target is 2 - 0.5 - q2 from the device.
  EXPECT_TRUE(CheckStick(f, 0.0, 0.05).feasible());
  EXPECT_EQ(CheckStick(f, 0.0, 0.1).reason, RejectionReason::kOutOfRange);
}

TEST(CellCheckTest, LineOfSightBlockedByAnObstacleAndByALink) {
  std::string error;
  {
    Fixture f;
    ASSERT_TRUE(MakeChecker(
        kStickUrdf,
        StickCell("obstacles:\n  - {name: post, type: sphere, radius_m: 0.05, "
                  "xyz_m: [1.3, 0.0, 0.5]}\n"),
        &f, &error))
        << error;
    const PoseVerdict v = CheckStick(f, 0.0, 0.1);
    EXPECT_EQ(v.reason, RejectionReason::kLineOfSight);
    EXPECT_EQ(f.checker.Detail(v), "post");
    // Turned away from the post, the beam passes it (the target still
    // faces the device within 30 deg).
    EXPECT_TRUE(CheckStick(f, 0.3, 0.1).feasible());
  }
  {
    // A link of the robot between the device and the target: a second
    // body fixed to the base, at (1.3, 0, 0.5).
    EXPECT_EQ(LineOfSightBlocker(WithFixedPlate(kStickUrdf, "screen",
                                                "base_link", "1.3 0 0.5")),
              "screen");
  }
}

TEST(CellCheckTest, LineOfSightIgnoresTheTargetsOwnMount) {
  // The target at the slider's origin inside a ball of the slider (its
  // mount, 4 cm in radius: more than the 2 cm line_of_sight_margin_m), the
  // device along +x. The beam leaves the convex ball once and never comes
  // back: that ball is not an occlusion.
  std::string urdf = kStickUrdf;
  urdf.replace(urdf.find("<origin xyz=\"-0.05 0 0\" rpy=\"0 0 0\"/>\n"
                         "      <geometry><sphere radius=\"0.02\"/>"),
               75,
               "<origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n"
               "      <geometry><sphere radius=\"0.04\"/>");
  ASSERT_NE(urdf.find("<sphere radius=\"0.04\"/>"), std::string::npos);
  std::string error;
  {
    Fixture f;
    ASSERT_TRUE(MakeChecker(urdf, StickCell(""), &f, &error)) << error;
    const PoseVerdict v = CheckStick(f, 0.0, 0.1);
    EXPECT_TRUE(v.feasible()) << f.checker.Describe(v);
    EXPECT_EQ(v.targets_seen, 1u);
  }
  {
    // A second shape of the same link that does not hold the target, 0.3 m
    // along the beam: it still blocks.
    EXPECT_EQ(
        LineOfSightBlocker(WithFixedPlate(urdf, "visor", "slider", "0.3 0 0")),
        "visor");
  }
  {
    // The PUMA 560's capsules: its measured point (L6's origin) lies in
    // L6's tool capsule (3 cm in radius). Lines of sight are blocked by
    // other links at some poses, never by the tool the target is on.
    RobotDescription robot;
    ASSERT_TRUE(LoadRobotFile(kData + "/puma560.yaml", &robot, &error))
        << error;
    RobotCollisionModel collision;
    ASSERT_TRUE(LoadRobotCollision(kData + "/puma560.yaml", {}, robot.model,
                                   &collision, &error))
        << error;
    const Cell cell = ParseCellOrDie(
        "self_clearance_m: 0.005\n"
        "device: {type: laser_tracker, xyz_m: [2.0, 0.0, 1.0]}\n"
        "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: "
        "45}]\n");
    CellChecker checker;
    ASSERT_TRUE(checker.Init(robot.model, collision, cell, &error)) << error;
    Eigen::MatrixXd joints;
    ASSERT_TRUE(SampleJointValues(robot.model, JointSampling::kRandom, 3000, 11,
                                  &joints, &error))
        << error;
    PoolFilterSummary s;
    ASSERT_TRUE(FilterPool(checker, joints, {}, &s));
    int64_t by_l6 = 0;
    for (const PoseVerdict& v : s.verdicts) {
      by_l6 += v.reason == RejectionReason::kLineOfSight &&
               checker.Detail(v) == "L6";
    }
    EXPECT_EQ(by_l6, 0);
    EXPECT_GT(s.num_feasible(), 50);
  }
}

TEST(CellCheckTest, MocapNeedsMinCamerasAndCameraIntrinsics) {
  std::string error;
  const std::string cameras =
      "device:\n  type: mocap\n  min_cameras: 2\n  cameras:\n"
      "    - {xyz_m: [2, 0, 0.5], look_at_m: [0.5, 0, 0.5], fov_deg: 60}\n"
      "    - {xyz_m: [2, 0.3, 0.5], look_at_m: [0.5, 0, 0.5], fov_deg: 60}\n"
      "    - {xyz_m: [2, -0.3, 0.5], look_at_m: [3, -0.3, 0.5], fov_deg: 60}\n";
  Fixture f;
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickCell("", 0, cameras), &f, &error))
      << error;
  // Two cameras see it (the third looks away).
  EXPECT_TRUE(CheckStick(f, 0.0, 0.1).feasible());
  Fixture g;
  std::string three = cameras;
  three.replace(three.find("min_cameras: 2"), 14, "min_cameras: 3");
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickCell("", 0, three), &g, &error));
  EXPECT_EQ(CheckStick(g, 0.0, 0.1).reason, RejectionReason::kOutOfView);
  // A pinhole camera: the target projects inside the image, or not.
  const std::string camera =
      "device: {type: camera, xyz_m: [2, 0, 0.5], look_at_m: [0.5, 0, 0.5], "
      "intrinsics: {fx: 1000, fy: 1000, cx: 640, cy: 480, width: 1280, "
      "height: 960}, max_viewing_angle_deg: 20}\n";
  Fixture h;
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickCell("", 0, camera), &h, &error))
      << error;
  EXPECT_TRUE(CheckStick(h, 0.0, 0.1).feasible());
  // Turned by 0.5 rad the target is 0.29 m aside at 1.47 m along the
  // optical axis: 195 px from the centre, inside; its normal is 0.69 rad
  // (40 deg) off the direction to the camera, beyond the camera's 20 deg.
  EXPECT_EQ(CheckStick(h, 0.5, 0.1).reason, RejectionReason::kFacingAway);
  Fixture k;
  std::string narrow = camera;
  narrow.replace(narrow.find("width: 1280"), 11, "width: 700");
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickCell("", 0, narrow), &k, &error));
  // The camera's x (image right) is the base's +y: at q1 = 0.5 the target
  // projects at u = 640 + 195 > 700, out of the image; at q1 = -0.5 at
  // u = 445, inside (and then facing away).
  const bool left =
      CheckStick(k, 0.5, 0.1).reason == RejectionReason::kOutOfView;
  const bool right =
      CheckStick(k, -0.5, 0.1).reason == RejectionReason::kOutOfView;
  EXPECT_NE(left, right);
}

// The device's eyes come from the device itself: a cell made in code is
// checked as a read one is (then named by field alone), a read one names
// the file position of its device.
TEST(CellFileTest, DeviceEyesComeFromTheDevice) {
  Cell made;
  EXPECT_TRUE(DeviceEyes(made).empty());
  made.has_device = true;
  made.device.type = DeviceType::kMocap;
  made.device.cameras.resize(2);
  made.device.cameras[1].position = Eigen::Vector3d(1, 2, 3);
  const std::vector<Cell::Eye> mocap = DeviceEyes(made);
  ASSERT_EQ(mocap.size(), 2u);
  EXPECT_EQ(mocap[1].position, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(mocap[1].field, "device.cameras[1].xyz_m");
  EXPECT_EQ(mocap[1].where, "device.cameras[1].xyz_m");
  made.device.type = DeviceType::kLaserTracker;
  made.device.position = Eigen::Vector3d(2.2, 0.4, 0.9);
  ASSERT_EQ(DeviceEyes(made).size(), 1u);
  EXPECT_EQ(DeviceEyes(made)[0].position, made.device.position);

  const Cell read = ParseCellOrDie(
      "device: {type: laser_tracker, xyz_m: [2.2, 0.4, 0.9]}\n"
      "targets:\n"
      "  - {xyz_m: [0, 0, 0.06], normal: [0, 0, 1], acceptance_deg: 30}\n");
  ASSERT_EQ(DeviceEyes(read).size(), 1u);
  EXPECT_EQ(DeviceEyes(read)[0].where, "cell.yaml:1:9: device.xyz_m");
}

// ---------------------------------------------------------------------
// The UR10e of data/ with its collision geometry.

struct Ur10e {
  RobotDescription robot;
  CellSetup setup;
};

bool LoadUr10e(const std::string& cell_path, Ur10e* u, std::string* error) {
  RobotLoadOptions o;
  o.chain.tip_link = "tool0";
  if (!LoadRobot(kData + "/ur10e.urdf", o, &u->robot, error)) return false;
  CellSetupOptions c;
  c.cell_path = cell_path;
  c.robot_path = kData + "/ur10e.urdf";
  c.chain = o.chain;
  return SetUpCell(c, &u->robot, &u->setup, error);
}

std::string DeviceFreeUrCell() {
  // The example's obstacles and clearances without a device: the first
  // reason is then the collision.
  const std::string path = TempPath("ur_no_device.yaml");
  WriteText(path,
            "joint_margin_deg: 3\nclearance_m: 0.05\nself_clearance_m: 0.01\n"
            "obstacles:\n"
            "  - {name: table, type: plane, normal: [0, 0, 1], offset_m: 0}\n"
            "  - {name: wall, type: box, size_m: [0.1, 4.0, 3.0], xyz_m: "
            "[-0.75, 0, 1.0]}\n");
  return path;
}

PoseVerdict CheckDeg(const CellChecker& c, std::vector<double> deg) {
  Eigen::VectorXd q(deg.size());
  for (size_t j = 0; j < deg.size(); ++j) q[j] = deg[j] * kDeg;
  auto w = c.NewWorkspace();
  return c.Check(q.data(), w.get());
}

TEST(CellUr10eTest, KnownCollisionsAreRejectedWithTheirReason) {
  Ur10e u;
  std::string error;
  ASSERT_TRUE(LoadUr10e(DeviceFreeUrCell(), &u, &error)) << error;
  const CellChecker& c = *u.setup.checker;
  EXPECT_EQ(u.setup.collision.num_shapes(), 12);
  EXPECT_EQ(c.num_targets(), 0);
  // The arm up, the wrist up: free.
  EXPECT_TRUE(CheckDeg(c, {0, -90, 0, -90, 0, 0}).feasible());
  // The elbow folded back onto the arm: the forearm hits the shoulder.
  PoseVerdict v = CheckDeg(c, {0, -90, 170, -90, 0, 0});
  EXPECT_EQ(v.reason, RejectionReason::kSelfCollision);
  EXPECT_EQ(c.Describe(v), "self-collision (shoulder_link, forearm_link)");
  // The arm 30 deg below the horizontal: through the table.
  v = CheckDeg(c, {0, 30, 0, -90, 0, 0});
  EXPECT_EQ(v.reason, RejectionReason::kObstacle);
  EXPECT_EQ(c.Describe(v), "obstacle table (upper_arm_link)");
  // Turned to the back: into the wall.
  v = CheckDeg(c, {180, -45, 0, -90, 0, 0});
  EXPECT_EQ(v.reason, RejectionReason::kObstacle);
  EXPECT_EQ(c.Describe(v), "obstacle wall (forearm_link)");
  // Without the wall in the cell (a skip pair for each link) it passes.
  Cell cell = u.setup.cell;
  for (const CollisionBody& b : u.setup.collision.bodies) {
    cell.skip_pairs.emplace_back(b.name, "wall");
    cell.skip_pair_where.push_back("test");
  }
  CellChecker skip;
  ASSERT_TRUE(skip.Init(u.robot.model, u.setup.collision, cell, &error))
      << error;
  EXPECT_TRUE(CheckDeg(skip, {180, -45, 0, -90, 0, 0}).feasible());
}

TEST(CellUr10eTest, SkipPairsAndSrdf) {
  std::string error;
  const std::string srdf = TempPath("ur.srdf");
  WriteText(srdf,
            "<?xml version=\"1.0\"?>\n<robot name=\"ur10e\">\n"
            "  <disable_collisions link1=\"shoulder_link\" "
            "link2=\"forearm_link\" reason=\"Test\"/>\n</robot>\n");
  const std::string path = TempPath("ur_srdf.yaml");
  WriteText(path, "self_clearance_m: 0.01\nsrdf: " + srdf + "\n");
  Ur10e u;
  ASSERT_TRUE(LoadUr10e(path, &u, &error)) << error;
  Ur10e plain;
  WriteText(TempPath("ur_plain.yaml"), "self_clearance_m: 0.01\n");
  ASSERT_TRUE(LoadUr10e(TempPath("ur_plain.yaml"), &plain, &error)) << error;
  EXPECT_EQ(u.setup.checker->num_self_pairs() + 1,
            plain.setup.checker->num_self_pairs());
  const PoseVerdict v = CheckDeg(*u.setup.checker, {0, -90, 170, -90, 0, 0});
  EXPECT_NE(u.setup.checker->Describe(v),
            "self-collision (shoulder_link, forearm_link)");
  // A skip pair naming nothing the robot or the cell has.
  WriteText(path, "skip_pairs: [[shoulder_link, forarm_link]]\n");
  Ur10e bad;
  EXPECT_FALSE(LoadUr10e(path, &bad, &error));
  EXPECT_NE(error.find(":1:14: skip_pairs[0]: 'forarm_link' is neither a "
                       "link of the robot nor an obstacle"),
            std::string::npos)
      << error;
  // A broken SRDF.
  WriteText(srdf, "<robot><disable_collisions link1=\"a\"/></robot>");
  WriteText(path, "srdf: " + srdf + "\n");
  EXPECT_FALSE(LoadUr10e(path, &bad, &error));
  EXPECT_NE(error.find("srdf: " + srdf +
                       ":1: <disable_collisions> needs link1 "
                       "and link2"),
            std::string::npos)
      << error;
}

// ---------------------------------------------------------------------
// FCL's distances against analytic ones.

// Distance between segments [p0, p1] and [q0, q1] (closest points of two
// segments by the clamped normal equations, Ericson's method).
double SegmentSegmentDistance(const Eigen::Vector3d& p0,
                              const Eigen::Vector3d& p1,
                              const Eigen::Vector3d& q0,
                              const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.dot(d1), e = d2.dot(d2), f = d2.dot(r);
  double s = 0, t = 0;
  const double c = d1.dot(r), b = d1.dot(d2), denom = a * e - b * b;
  s = denom > 1e-14 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

// Distance from p to an axis-aligned box of half sizes h at c, rotated R.
double PointBoxDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& c,
                        const Eigen::Matrix3d& R, const Eigen::Vector3d& h) {
  const Eigen::Vector3d local = R.transpose() * (p - c);
  return (local.cwiseAbs() - h).cwiseMax(0.0).norm();
}

// A slide robot: a prismatic joint along x carrying a ball and a block,
// against a sphere, an axis-aligned box, a turned box and a plane.
const std::string kSlideUrdf = testing::TestDataText("slide.urdf");

TEST(CellDistanceTest, PrimitivesAgainstAnalyticDistances) {
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(
      kSlideUrdf,
      "obstacles:\n"
      "  - {name: globe, type: sphere, radius_m: 0.2, xyz_m: [0.3, 0, 1.0]}\n"
      "  - {name: crate, type: box, size_m: [0.4, 0.4, 0.4], xyz_m: [1.0, "
      "2.0, 0.1]}\n"
      "  - {name: wedge, type: box, size_m: [0.6, 0.2, 0.2], xyz_m: [-1.0, "
      "0.4, -0.7], rpy_rad: [0.3, 0, 0.5]}\n"
      "  - {name: floor, type: plane, normal: [0, 0.6, 0.8], offset_m: "
      "-1.5}\n",
      &f, &error))
      << error;
  auto w = f.checker.NewWorkspace();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d wedge_R =
      (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(0.0, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Vector3d n = Eigen::Vector3d(0, 0.6, 0.8);
  for (double x : {-2.0, -1.0, -0.4, 0.0, 0.35, 0.9, 1.7}) {
    const Eigen::Vector3d ball(x, 0, 0);
    const Eigen::Vector3d block(x, 0.8, 0);
    const Eigen::Vector3d block_h(0.1, 0.15, 0.2);
    std::map<std::string, double> expected;
    expected["ball|globe"] = (ball - Eigen::Vector3d(0.3, 0, 1.0)).norm() - 0.3;
    expected["ball|crate"] =
        PointBoxDistance(ball, {1.0, 2.0, 0.1}, I, {0.2, 0.2, 0.2}) - 0.1;
    expected["ball|wedge"] =
        PointBoxDistance(ball, {-1.0, 0.4, -0.7}, wedge_R, {0.3, 0.1, 0.1}) -
        0.1;
    expected["ball|floor"] = n.dot(ball) - 0.1 + 1.5;
    // Two axis-aligned boxes: the per-axis gaps.
    const Eigen::Vector3d gap =
        ((block - Eigen::Vector3d(1.0, 2.0, 0.1)).cwiseAbs() - block_h -
         Eigen::Vector3d(0.2, 0.2, 0.2))
            .cwiseMax(0.0);
    expected["block|crate"] = gap.norm();
    expected["block|globe"] =
        PointBoxDistance({0.3, 0, 1.0}, block, I, block_h) - 0.2;
    // A box over a plane: its lowest corner.
    double lowest = 1e9;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d c =
          block + Eigen::Vector3d((corner & 1) ? 0.1 : -0.1,
                                  (corner & 2) ? 0.15 : -0.15,
                                  (corner & 4) ? 0.2 : -0.2);
      lowest = std::min(lowest, n.dot(c));
    }
    expected["block|floor"] = lowest + 1.5;
    const double q = x;
    int compared = 0;
    for (const PairDistance& d : f.checker.Distances(&q, w.get())) {
      const std::string key = d.first + "|" + d.second;
      if (!expected.count(key)) continue;
      ++compared;
      const double want = expected[key];
      if (want > 1e-6) {
        EXPECT_NEAR(d.distance_m, want, 2e-6) << key << " at x = " << x;
      } else {
        EXPECT_LT(d.distance_m, 1e-6) << key << " at x = " << x;
      }
    }
    EXPECT_EQ(compared, 7) << "x = " << x;
  }
}

// Capsules of a robot file: a planar arm of three revolute joints.
const char kCapsuleRobot[] = R"(name: planar
angle_unit: rad
links:
  - {name: L1, convention: standard_dh, joint: revolute, limits: [-3, 3], gamma: 0, alpha: 0, a: 0.5, d: 0, free: []}
  - {name: L2, convention: standard_dh, joint: revolute, limits: [-3, 3], gamma: 0, alpha: 0, a: 0.4, d: 0.2, free: []}
  - {name: L3, convention: standard_dh, joint: revolute, limits: [-3, 3], gamma: 0, alpha: 0, a: 0.3, d: 0, free: []}
tool: {x: 0, y: 0, z: 0, rx: 0, ry: 0, rz: 0, free: []}
collision:
  - {link: base, from_m: [0, 0, -0.1], to_m: [0, 0, 0.3], radius_m: 0.05}
  - {link: L2, from_m: [-0.4, 0, 0], to_m: [0, 0, 0], radius_m: 0.04}
  - {link: L3, from_m: [-0.3, 0, 0], to_m: [0, 0, 0], radius_m: 0.03}
)";

TEST(CellDistanceTest, CapsulesAgainstSegmentDistances) {
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(
      ParseRobotDescription(kCapsuleRobot, "planar.yaml", &robot, &error))
      << error;
  RobotCollisionModel collision;
  ASSERT_TRUE(ParseRobotFileCollision(kCapsuleRobot, "planar.yaml", robot.model,
                                      &collision, &error))
      << error;
  EXPECT_EQ(collision.num_shapes(), 3);
  const Cell cell = ParseCellOrDie(
      "obstacles:\n"
      "  - {name: ball, type: sphere, radius_m: 0.1, xyz_m: [0.4, 0.6, 0.3]}\n"
      "  - {name: floor, type: plane, normal: [0, 0, 1], offset_m: -0.3}\n");
  CellChecker checker;
  ASSERT_TRUE(checker.Init(robot.model, collision, cell, &error)) << error;
  // base-L2 and base-L3 (L2-L3 adjacent; L1 has no capsule).
  EXPECT_EQ(checker.num_self_pairs(), 2);
  auto w = checker.NewWorkspace();
  Random random(7);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Vector3d q;
    for (int j = 0; j < 3; ++j) q[j] = -3 + 6 * random.Uniform();
    // The planar arm: frame 2 at the end of link 2 (z = 0.2), x along it.
    const double t1 = q[0], t2 = q[0] + q[1];
    const Eigen::Vector3d o1(0.5 * std::cos(t1), 0.5 * std::sin(t1), 0);
    const Eigen::Vector3d o2 =
        o1 + Eigen::Vector3d(0.4 * std::cos(t2), 0.4 * std::sin(t2), 0.2);
    const Eigen::Vector3d l2_from =
        o2 - Eigen::Vector3d(0.4 * std::cos(t2), 0.4 * std::sin(t2), 0);
    std::map<std::string, double> expected;
    expected["base|L2"] =
        SegmentSegmentDistance({0, 0, -0.1}, {0, 0, 0.3}, l2_from, o2) - 0.09;
    const Eigen::Vector3d ball(0.4, 0.6, 0.3);
    const Eigen::Vector3d d = o2 - l2_from;
    const double s = std::clamp((ball - l2_from).dot(d) / d.dot(d), 0.0, 1.0);
    expected["L2|ball"] = (l2_from + s * d - ball).norm() - 0.14;
    expected["L2|floor"] = 0.2 - 0.04 + 0.3;
    int compared = 0;
    for (const PairDistance& pd : checker.Distances(q.data(), w.get())) {
      const std::string key = pd.first + "|" + pd.second;
      if (!expected.count(key)) continue;
      ++compared;
      if (expected[key] > 1e-6) {
        EXPECT_NEAR(pd.distance_m, expected[key], 2e-6) << key;
      } else {
        EXPECT_LT(pd.distance_m, 1e-6) << key;
      }
    }
    EXPECT_EQ(compared, 3);
  }
}

TEST(CellDistanceTest, CylinderOverAPlaneAgainstItsRim) {
  // A URDF cylinder tilted by the slide's frame: the lowest point of its
  // rim, sampled, against the support-function distance.
  std::string urdf = kSlideUrdf;
  urdf.replace(urdf.find("<sphere radius=\"0.1\"/>"), 22,
               "<cylinder radius=\"0.1\" length=\"0.5\"/>");
  urdf.replace(urdf.find("<origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n      "
                         "<geometry><cylinder"),
               33, "<origin xyz=\"0 0 0\" rpy=\"0.4 0.7 0\"/>");
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(urdf,
                          "obstacles:\n  - {name: floor, type: plane, normal: "
                          "[0, 0, 1], offset_m: -1}\n",
                          &f, &error))
      << error;
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  double lowest = 1e9;
  for (int end = -1; end <= 1; end += 2) {
    for (int k = 0; k < 100000; ++k) {
      const double a = 2 * M_PI * k / 100000;
      const Eigen::Vector3d p =
          R * Eigen::Vector3d(0.1 * std::cos(a), 0.1 * std::sin(a), 0.25 * end);
      lowest = std::min(lowest, p.z());
    }
  }
  auto w = f.checker.NewWorkspace();
  const double q = 0.3;
  bool found = false;
  for (const PairDistance& d : f.checker.Distances(&q, w.get())) {
    if (d.first == "ball" && d.second == "floor") {
      found = true;
      EXPECT_NEAR(d.distance_m, lowest + 1.0, 1e-8);
    }
  }
  EXPECT_TRUE(found);
}

// ---------------------------------------------------------------------
// The cell file and its bad input (docs/bad_input.md).

TEST(CellFileTest, ReadsTheExample) {
  Cell cell;
  std::string error;
  ASSERT_TRUE(LoadCellFile(kData + "/cells/ur10e_table.yaml", &cell, &error))
      << error;
  EXPECT_DOUBLE_EQ(cell.joint_margin_rad, 3 * kDeg);
  EXPECT_DOUBLE_EQ(cell.clearance_m, 0.05);
  EXPECT_DOUBLE_EQ(cell.self_clearance_m, 0.01);
  ASSERT_EQ(cell.obstacles.size(), 2u);
  EXPECT_TRUE(cell.obstacles[0].plane);
  EXPECT_EQ(cell.obstacles[1].shape.type, ShapeType::kBox);
  EXPECT_EQ(cell.device.type, DeviceType::kLaserTracker);
  EXPECT_DOUBLE_EQ(cell.device.min_range_m, 1.0);
  ASSERT_EQ(cell.targets.size(), 1u);
  EXPECT_DOUBLE_EQ(cell.targets[0].acceptance_rad, 30 * kDeg);
  // Without self_clearance_m it is clearance_m.
  EXPECT_DOUBLE_EQ(ParseCellOrDie("clearance_m: 0.04\n").self_clearance_m,
                   0.04);
}

TEST(CellFileTest, EveryBadInputNamesLineAndField) {
  const std::string device =
      "device: {type: laser_tracker, xyz_m: [2, 0, 1]}\n"
      "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n";
  struct Case {
    std::string text, want;
  };
  const std::vector<Case> cases = {
      {"clearence_m: 0.05\n", "cell.yaml:1:1: clearence_m: unknown field"},
      {"clearance_m: -1\n",
       "cell.yaml:1:14: clearance_m: must be >= 0, got -1"},
      {"joint_margin_deg: abc\n",
       "cell.yaml:1:19: joint_margin_deg: expected a number, got 'abc'"},
      {"obstacles:\n  - {name: t, type: plane, normal: [0, 0, 0]}\n",
       "cell.yaml:2:36: obstacles[0].normal: a zero vector"},
      {"obstacles:\n  - {name: t, type: slab}\n",
       "cell.yaml:2:21: obstacles[0].type: expected plane, box, cylinder, "
       "sphere or mesh, got 'slab'"},
      {"obstacles:\n  - {name: w, type: box, size_m: [1, 0, 1]}\n",
       "cell.yaml:2:34: obstacles[0].size_m: every edge must be > 0"},
      {"obstacles:\n  - {name: w, type: box, size_m: [1, 1]}\n",
       "cell.yaml:2:34: obstacles[0].size_m: expected [x, y, z]"},
      {"obstacles:\n  - {name: w, type: sphere}\n",
       "cell.yaml:2:5: obstacles[0].radius_m: missing"},
      {"obstacles:\n  - {name: w, type: sphere, radius_m: 1}\n"
       "  - {name: w, type: sphere, radius_m: 1}\n",
       "cell.yaml:3:12: obstacles[1].name: duplicate name 'w' (also at line "
       "2)"},
      // A duplicate target name: this file's line and field (not the
      // markers the targets become), also against a default name.
      {"device: {type: laser_tracker, xyz_m: [2, 0, 1]}\n"
       "targets:\n"
       "  - {name: front, xyz_m: [0, 0, 0], normal: [0, 0, 1], "
       "acceptance_deg: 30}\n"
       "  - {name: front, xyz_m: [0, 0, 1], normal: [0, 0, 1], "
       "acceptance_deg: 30}\n",
       "cell.yaml:4:12: targets[1].name: duplicate name 'front' (also at line "
       "3)"},
      {"device: {type: laser_tracker, xyz_m: [2, 0, 1]}\n"
       "targets:\n"
       "  - {xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}\n"
       "  - {name: target1, xyz_m: [0, 0, 1], normal: [0, 0, 1], "
       "acceptance_deg: 30}\n",
       "cell.yaml:4:12: targets[1].name: duplicate name 'target1' (also at "
       "line 3)"},
      {"obstacles:\n  - {name: w, type: cylinder, radius_m: 1, length_m: 1, "
       "rpy_rad: [0, 0, 0], quaternion_xyzw: [0, 0, 0, 1]}\n",
       "quaternion_xyzw: give rpy_rad or quaternion_xyzw, not both"},
      {"obstacles:\n  - {name: w, type: box, size_m: [1, 1, 1], "
       "quaternion_xyzw: [0, 0, 0, 0]}\n",
       "obstacles[0].quaternion_xyzw: zero"},
      {"device: {type: laser_tracker, xyz_m: [2, 0, 1]}\n",
       "targets: missing: a device needs the targets it measures"},
      {"targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n",
       "device: missing: targets need the device that measures them"},
      {"device: {type: tracker, xyz_m: [2, 0, 1]}\n",
       "cell.yaml:1:16: device.type: expected laser_tracker, mocap or camera, "
       "got 'tracker'"},
      {"device: {type: laser_tracker, xyz_m: [2, 0, 1], range_m: [3, 1]}\n",
       "cell.yaml:1:58: device.range_m: expected 0 <= min < max"},
      {"device: {type: laser_tracker, xyz_m: [2, 0, 1]}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 0], acceptance_deg: 30}]\n",
       "cell.yaml:2:38: targets[0].normal: a zero vector"},
      {"device: {type: laser_tracker, xyz_m: [2, 0, 1]}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 0}]\n",
       "cell.yaml:2:65: targets[0].acceptance_deg: must be in (0, 90], got 0"},
      {"device: {type: laser_tracker, xyz_m: [2, 0, 1]}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: "
       "90.5}]\n",
       "targets[0].acceptance_deg: must be in (0, 90], got 90.5"},
      {"device: {type: laser_tracker, xyz_m: [2, 0, 1]}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1]}]\n",
       "cell.yaml:2:11: targets[0].acceptance_deg: missing"},
      {"obstacles:\n  - {name: wall, type: box, size_m: [1, 1, 1], xyz_m: [2, "
       "0, 1]}\n" +
           device,
       "cell.yaml:3:9: device.xyz_m: the device lies inside obstacle 'wall'"},
      {"obstacles:\n  - {name: floor, type: plane, normal: [0, 0, 1], "
       "offset_m: 1.5}\n" +
           device,
       "device.xyz_m: the device lies inside obstacle 'floor'"},
      {"device: {type: mocap, min_cameras: 3, cameras: [{xyz_m: [2, 0, 1], "
       "look_at_m: [0, 0, 0], fov_deg: 60}]}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n",
       "device.min_cameras: expected a whole number in [1, 1] (the cameras), "
       "got 3"},
      {"device: {type: mocap, cameras: [{xyz_m: [2, 0, 1], look_at_m: [2, 0, "
       "1], fov_deg: 60}]}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n",
       "device.cameras[0].look_at_m: the camera looks at its own position"},
      {"device: {type: camera, xyz_m: [2, 0, 1], look_at_m: [0, 0, 0]}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n",
       "device.fov_deg: missing (or intrinsics): the camera's field of view"},
      {"device: {type: camera, xyz_m: [2, 0, 1], look_at_m: [0, 0, 0], "
       "fov_deg: 180}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n",
       "device.fov_deg: must be in (0, 180), got 180"},
      {"device: {type: camera, xyz_m: [2, 0, 1], look_at_m: [0, 0, 0], "
       "intrinsics: {fx: 1000, fy: 1000, cx: 640, width: 1280, height: 960}}\n"
       "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], acceptance_deg: 30}]\n",
       "device.intrinsics.cy: missing"},
      {"skip_pairs: [[a]]\n",
       "cell.yaml:1:14: skip_pairs[0]: expected [link, "
       "link]"},
      {"srdf: /nonexistent/robot.srdf\n",
       "cell.yaml:1:7: srdf: /nonexistent/robot.srdf: cannot open the file"},
      {"obstacles:\n  - {name: m, type: mesh, file: /nonexistent/m.stl}\n",
       "cell.yaml:2:33: obstacles[0].file: /nonexistent/m.stl: Unable to open "
       "file"},
      {"joint_margin_override_deg: {a: 1, a: 2}\n",
       "cell.yaml:1:35: joint_margin_override_deg.a: given twice"},
      // A key given twice is an error, not one of the two silently lost
      // (yaml-cpp's map[key] reads the first).
      {"clearance_m: 0.05\nclearance_m: 0.01\n",
       "cell.yaml:2:1: clearance_m: given twice"},
      {"obstacles:\n  - {name: t, type: plane, normal: [0, 0, 1]}\n"
       "obstacles:\n  - {name: w, type: sphere, radius_m: 1}\n",
       "cell.yaml:3:1: obstacles: given twice"},
      {"obstacles:\n  - {name: w, type: sphere, radius_m: 1, radius_m: 2}\n",
       "cell.yaml:2:42: obstacles[0].radius_m: given twice"},
      {"obstacles: {name: t}\n", "cell.yaml:1:12: obstacles: expected a list"},
      {"[1, 2]\n", "cell.yaml:1:1: expected a mapping of cell fields"},
      {"clearance_m: [0.05\n", "cell.yaml:2:1: not valid YAML"},
  };
  for (const Case& c : cases) {
    const std::string error = CellError(c.text);
    EXPECT_NE(error.find(c.want), std::string::npos)
        << "input:\n"
        << c.text << "got:  " << error << "\nwant: " << c.want;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
  // A mocap system of 64 cameras is read; 65 are refused (the checks keep
  // a bit per camera in 64).
  for (int n : {64, 65}) {
    std::string text = "device:\n  type: mocap\n  cameras:\n";
    for (int k = 0; k < n; ++k) {
      text += "    - {xyz_m: [2, " + std::to_string(0.01 * k) +
              ", 1], look_at_m: [0, 0, 0], fov_deg: 60}\n";
    }
    text +=
        "targets: [{xyz_m: [0, 0, 0], normal: [0, 0, 1], "
        "acceptance_deg: 30}]\n";
    Cell cell;
    std::string error;
    EXPECT_EQ(ParseCellFile(text, "cell.yaml", "", &cell, &error), n == 64)
        << n;
    if (n == 65) {
      EXPECT_EQ(error,
                "cell.yaml:4:5: device.cameras: at most 64 cameras, got 65");
    }
  }
}

TEST(CellFileTest, MeshesFromStlObjAndDae) {
  // A unit cube, centred, written three ways; the DAE in millimetres with
  // z up, as CAD exports write it.
  const std::string dir = ::testing::TempDir();
  const std::vector<Eigen::Vector3d> corners = {
      {-0.5, -0.5, -0.5}, {0.5, -0.5, -0.5}, {0.5, 0.5, -0.5},
      {-0.5, 0.5, -0.5},  {-0.5, -0.5, 0.5}, {0.5, -0.5, 0.5},
      {0.5, 0.5, 0.5},    {-0.5, 0.5, 0.5}};
  const int faces[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                            {0, 1, 5}, {0, 5, 4}, {2, 3, 7}, {2, 7, 6},
                            {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
  std::ostringstream stl, obj, dae_positions, dae_indices;
  stl << "solid cube\n";
  for (const auto& f : faces) {
    stl << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& v = corners[f[k]];
      stl << "   vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
    }
    stl << "  endloop\n endfacet\n";
  }
  stl << "endsolid cube\n";
  for (const Eigen::Vector3d& v : corners) {
    obj << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    dae_positions << 1000 * v.x() << " " << 1000 * v.y() << " " << 1000 * v.z()
                  << " ";
  }
  for (const auto& f : faces) {
    obj << "f " << f[0] + 1 << " " << f[1] + 1 << " " << f[2] + 1 << "\n";
    dae_indices << f[0] << " " << f[1] << " " << f[2] << " ";
  }
  const std::string dae =
      "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
      "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" "
      "version=\"1.4.1\">\n"
      " <asset><unit name=\"millimeter\" meter=\"0.001\"/>"
      "<up_axis>Z_UP</up_axis></asset>\n"
      " <library_geometries><geometry id=\"cube\"><mesh>\n"
      "  <source id=\"p\"><float_array id=\"pa\" count=\"24\">" +
      dae_positions.str() +
      "</float_array><technique_common><accessor source=\"#pa\" "
      "count=\"8\" stride=\"3\"><param name=\"X\" type=\"float\"/><param "
      "name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/>"
      "</accessor></technique_common></source>\n"
      "  <vertices id=\"v\"><input semantic=\"POSITION\" source=\"#p\"/>"
      "</vertices>\n"
      "  <triangles count=\"12\"><input semantic=\"VERTEX\" source=\"#v\" "
      "offset=\"0\"/><p>" +
      dae_indices.str() +
      "</p></triangles>\n"
      " </mesh></geometry></library_geometries>\n"
      " <library_visual_scenes><visual_scene id=\"s\"><node id=\"n\">"
      "<instance_geometry url=\"#cube\"/></node></visual_scene>"
      "</library_visual_scenes>\n"
      " <scene><instance_visual_scene url=\"#s\"/></scene>\n"
      "</COLLADA>\n";
  WriteText(dir + "/activecal_cube.stl", stl.str());
  WriteText(dir + "/activecal_cube.obj", obj.str());
  WriteText(dir + "/activecal_cube.dae", dae);
  for (const std::string name :
       {"activecal_cube.stl", "activecal_cube.obj", "activecal_cube.dae"}) {
    const Cell cell = ParseCellOrDie(
        "obstacles:\n  - {name: cube, type: mesh, file: " + name +
            ", scale: [0.2, 0.4, 0.6], xyz_m: [1, 0, 0]}\n",
        dir);
    ASSERT_EQ(cell.obstacles.size(), 1u) << name;
    const CollisionShape& s = cell.obstacles[0].shape;
    EXPECT_EQ(s.triangles.size(), 12u) << name;
    Eigen::Vector3d lo = s.vertices[0], hi = s.vertices[0];
    for (const Eigen::Vector3d& v : s.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    EXPECT_TRUE((hi - lo).isApprox(Eigen::Vector3d(0.2, 0.4, 0.6), 1e-6))
        << name << ": " << (hi - lo).transpose();
    // Inside and outside, by the ray parity.
    EXPECT_TRUE(PointInsideObstacle(cell.obstacles[0], {1.05, 0.1, 0.2}));
    EXPECT_FALSE(PointInsideObstacle(cell.obstacles[0], {1.15, 0.1, 0.2}));
  }
  // A file assimp cannot read: its reason.
  WriteText(dir + "/activecal_bad.stl", "solid x\n facet garbage\n");
  const std::string error = CellError(
      "obstacles:\n  - {name: m, type: mesh, file: activecal_bad.stl}\n", dir);
  EXPECT_NE(error.find("obstacles[0].file: " + dir + "/activecal_bad.stl: "),
            std::string::npos)
      << error;
  EXPECT_GT(error.size(), error.find("activecal_bad.stl: ") + 20) << error;
}

TEST(CellFileTest, RobotFileCollisionErrors) {
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(
      ParseRobotDescription(kCapsuleRobot, "planar.yaml", &robot, &error))
      << error;
  RobotCollisionModel collision;
  std::string text = kCapsuleRobot;
  text.replace(text.find("{link: L3"), 9, "{link: L9");
  EXPECT_FALSE(ParseRobotFileCollision(text, "planar.yaml", robot.model,
                                       &collision, &error));
  EXPECT_NE(error.find("planar.yaml:11:12: collision[2].link: no link named "
                       "'L9' (expected one of: base, L1, L2, L3)"),
            std::string::npos)
      << error;
  text = kCapsuleRobot;
  text.replace(text.find("radius_m: 0.03"), 14, "radius_m: 0");
  EXPECT_FALSE(ParseRobotFileCollision(text, "planar.yaml", robot.model,
                                       &collision, &error));
  EXPECT_NE(error.find("planar.yaml:11:"), std::string::npos) << error;
  EXPECT_NE(error.find("collision[2].radius_m: must be > 0"), std::string::npos)
      << error;
  // The robot file itself accepts the section.
  RobotDescription data;
  EXPECT_TRUE(LoadRobotFile(kData + "/puma560.yaml", &data, &error)) << error;
  RobotCollisionModel puma;
  EXPECT_TRUE(LoadRobotCollision(kData + "/puma560.yaml", {}, data.model, &puma,
                                 &error))
      << error;
  EXPECT_EQ(puma.num_shapes(), 8);
}

TEST(CellFileTest, UrdfCollisionOfTheShippedRobots) {
  for (const auto& [file, tip, shapes] :
       std::vector<std::tuple<std::string, std::string, int>>{
           {"ur10.urdf", "tool0", 12},
           {"ur10e.urdf", "tool0", 12},
           {"kuka_iiwa14.urdf", "", 10}}) {
    RobotLoadOptions o;
    o.chain.tip_link = tip;
    RobotDescription robot;
    std::string error;
    ASSERT_TRUE(LoadRobot(kData + "/" + file, o, &robot, &error)) << error;
    RobotCollisionModel c;
    ASSERT_TRUE(LoadRobotCollision(kData + "/" + file, o.chain, robot.model, &c,
                                   &error))
        << error;
    EXPECT_EQ(c.num_shapes(), shapes) << file;
    for (double v : c.velocity_limits) EXPECT_GT(v, 0) << file;
    if (file != "kuka_iiwa14.urdf") {
      // ur_description's config/<robot>/joint_limits.yaml: 120 deg/s at the
      // shoulder, 180 deg/s at the elbow and the wrists (the tour's times).
      EXPECT_EQ(c.velocity_limits,
                (std::vector<double>{2.0943951023931953, 2.0943951023931953,
                                     M_PI, M_PI, M_PI, M_PI}))
          << file;
    }
    // The straight arm is free of itself.
    Cell cell;
    cell.self_clearance_m = 0.01;
    CellChecker checker;
    ASSERT_TRUE(checker.Init(robot.model, c, cell, &error)) << error;
    auto w = checker.NewWorkspace();
    const Eigen::VectorXd q = Eigen::VectorXd::Zero(robot.model.num_joints());
    EXPECT_TRUE(checker.Check(q.data(), w.get()).feasible()) << file;
  }
  // A URDF mesh, relative to the URDF's folder, with its scale.
  const std::string dir = ::testing::TempDir();
  WriteText(dir + "/activecal_tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  std::string urdf = kStickUrdf;
  urdf.replace(urdf.find("<sphere radius=\"0.02\"/>"), 23,
               "<mesh filename=\"activecal_tri.obj\" scale=\"0.1 0.2 0.3\"/>");
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(ParseUrdfRobot(urdf, "stick.urdf", {}, &robot, &error));
  RobotCollisionModel c;
  ASSERT_TRUE(
      ParseUrdfCollision(urdf, "stick.urdf", dir, {}, robot.model, &c, &error))
      << error;
  const CollisionShape& mesh = c.bodies[c.BodyIndex("slider")].shapes[0];
  EXPECT_EQ(mesh.type, ShapeType::kMesh);
  EXPECT_TRUE(mesh.vertices[2].isApprox(Eigen::Vector3d(0, 0.2, 0)));
  urdf.replace(urdf.find("activecal_tri.obj"), 17, "package://nope/m.stl");
  EXPECT_FALSE(
      ParseUrdfCollision(urdf, "stick.urdf", dir, {}, robot.model, &c, &error));
  EXPECT_NE(
      error.find("stick.urdf: link 'slider': mesh 'package://nope/m.stl': "
                 "not found in ROS_PACKAGE_PATH"),
      std::string::npos)
      << error;
}

// ---------------------------------------------------------------------
// The pool filter, its CSV, the measurable pool, the tour, the hook.

Eigen::MatrixXd UrSobol(const RobotModel& model, int64_t n) {
  Eigen::MatrixXd joints;
  std::string error;
  EXPECT_TRUE(
      SampleJointValues(model, JointSampling::kSobol, n, 3, &joints, &error));
  return joints;
}

TEST(CellPoolTest, FilterIsThreadCountIndependentAndItsCsvReadsBack) {
  Ur10e u;
  std::string error;
  ASSERT_TRUE(LoadUr10e(kData + "/cells/ur10e_table.yaml", &u, &error))
      << error;
  const Eigen::MatrixXd joints = UrSobol(u.robot.model, 3000);
  PoolFilterSummary one, three;
  PoolFilterOptions o;
  o.num_threads = 1;
  ASSERT_TRUE(FilterPool(*u.setup.checker, joints, o, &one));
  o.num_threads = 3;
  ASSERT_TRUE(FilterPool(*u.setup.checker, joints, o, &three));
  EXPECT_EQ(one.feasible, three.feasible);
  ASSERT_EQ(one.verdicts.size(), three.verdicts.size());
  for (size_t i = 0; i < one.verdicts.size(); ++i) {
    EXPECT_EQ(one.verdicts[i].reason, three.verdicts[i].reason);
    EXPECT_EQ(one.verdicts[i].a, three.verdicts[i].a);
    EXPECT_EQ(one.verdicts[i].b, three.verdicts[i].b);
  }
  // The counts add up; each reason occurs in this cell.
  int64_t total = one.num_feasible();
  for (int64_t n : one.rejected) total += n;
  EXPECT_EQ(total, 3000);
  EXPECT_GT(one.num_feasible(), 0);
  for (RejectionReason r :
       {RejectionReason::kJointMargin, RejectionReason::kFacingAway,
        RejectionReason::kSelfCollision, RejectionReason::kObstacle}) {
    EXPECT_GT(one.rejected[static_cast<int>(r)], 0) << RejectionReasonLabel(r);
  }
  EXPECT_EQ(one.rejected_by_obstacle[0] + one.rejected_by_obstacle[1],
            one.rejected[static_cast<int>(RejectionReason::kObstacle)]);
  EXPECT_NE(one.BriefReport(*u.setup.checker).find("obstacle table "),
            std::string::npos);
  // The rejected CSV: a poses CSV (the readers ignore the three columns)
  // whose reasons are the verdicts'.
  std::vector<int64_t> labels(3000);
  for (int i = 0; i < 3000; ++i) labels[i] = 1000 + i;
  const std::string csv =
      RejectedCsvText(*u.setup.checker, joints, labels, one);
  PoseList read;
  ASSERT_TRUE(
      ParsePosesCsv(csv, "rejected.csv", u.robot.model, true, &read, &error))
      << error;
  ASSERT_EQ(read.joints.rows(), 3000 - one.num_feasible());
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  EXPECT_NE(line.find(",q6_deg,reason,obstacle,detail"), std::string::npos);
  int k = 0;
  while (std::getline(lines, line)) {
    const int64_t row = read.pose_indices[k] - 1000;
    const PoseVerdict& v = one.verdicts[row];
    ASSERT_FALSE(v.feasible());
    EXPECT_TRUE(read.joints.row(k).isApprox(joints.row(row), 1e-15));
    std::vector<std::string> fields;
    std::stringstream split(line);
    std::string field;
    while (std::getline(split, field, ',')) fields.push_back(field);
    if (line.back() == ',') fields.push_back("");
    ASSERT_EQ(fields.size(), 16u) << line;
    RejectionReason reason;
    ASSERT_TRUE(StringToRejectionReason(fields[13], &reason)) << line;
    EXPECT_EQ(reason, v.reason);
    EXPECT_EQ(fields[14], v.reason == RejectionReason::kObstacle
                              ? u.setup.cell.obstacles[v.a].name
                              : "");
    EXPECT_EQ(fields[15], u.setup.checker->Detail(v));
    ++k;
  }
  EXPECT_EQ(k, read.joints.rows());
}

TEST(CellPoolTest, EachReasonIsTheFirstCheckThatFails) {
  // Every check recomputed on its own, without the checker's shortcuts
  // (bounding balls, early exits): the margins from the limits, range and
  // facing from the tip frame, the collisions from the exact distances of
  // every pair. A pose's reason is the first check in the documented order
  // (margin, range, facing, self-collision, obstacles in the file's order,
  // line of sight) that fails, and a feasible pose fails none.
  Ur10e u;
  std::string error;
  ASSERT_TRUE(LoadUr10e(kData + "/cells/ur10e_table.yaml", &u, &error))
      << error;
  const CellChecker& c = *u.setup.checker;
  const Cell& cell = u.setup.cell;
  const RobotModel& m = u.robot.model;
  const Eigen::MatrixXd joints = UrSobol(m, 3000);
  PoolFilterSummary s;
  ASSERT_TRUE(FilterPool(c, joints, {}, &s));
  auto w = c.NewWorkspace();
  std::array<int, kNumRejectionReasons> seen{};
  for (int64_t i = 0; i < joints.rows(); ++i) {
    const Eigen::VectorXd q = joints.row(i).transpose();
    std::vector<RejectionReason> fails;
    int first_joint = -1;
    for (int j = m.num_joints() - 1; j >= 0; --j) {
      if (q[j] < m.links[j].joint_min + c.joint_margin(j) - 1e-12 ||
          q[j] > m.links[j].joint_max - c.joint_margin(j) + 1e-12) {
        first_joint = j;
      }
    }
    if (first_joint >= 0) fails.push_back(RejectionReason::kJointMargin);
    const FixedTransform tip = c.TipFrame(q.data());
    const Eigen::Vector3d p =
        tip.rotation * cell.targets[0].xyz_m + tip.translation;
    const Eigen::Vector3d to_device = cell.device.position - p;
    if (to_device.norm() < cell.device.min_range_m ||
        to_device.norm() > cell.device.max_range_m) {
      fails.push_back(RejectionReason::kOutOfRange);
    }
    const double angle = std::acos(std::clamp(
        (tip.rotation * cell.targets[0].normal).dot(to_device.normalized()),
        -1.0, 1.0));
    if (angle > cell.targets[0].acceptance_rad + 1e-9) {
      fails.push_back(RejectionReason::kFacingAway);
    }
    double self = 1e9;
    std::vector<double> to_obstacle(cell.obstacles.size(), 1e9);
    for (const PairDistance& d : c.Distances(q.data(), w.get())) {
      if (!d.obstacle) {
        self = std::min(self, d.distance_m);
        continue;
      }
      for (size_t o = 0; o < cell.obstacles.size(); ++o) {
        if (cell.obstacles[o].name == d.second) {
          to_obstacle[o] = std::min(to_obstacle[o], d.distance_m);
        }
      }
    }
    if (self < cell.self_clearance_m) {
      fails.push_back(RejectionReason::kSelfCollision);
    }
    int first_obstacle = -1;
    for (int o = static_cast<int>(cell.obstacles.size()) - 1; o >= 0; --o) {
      if (to_obstacle[o] < cell.clearance_m) first_obstacle = o;
    }
    if (first_obstacle >= 0) fails.push_back(RejectionReason::kObstacle);
    const PoseVerdict& v = s.verdicts[i];
    ++seen[static_cast<int>(v.reason)];
    if (fails.empty()) {
      // Feasible, or only the line of sight (not recomputed here) failed.
      EXPECT_TRUE(v.feasible() || v.reason == RejectionReason::kLineOfSight)
          << i << ": " << c.Describe(v);
      continue;
    }
    ASSERT_EQ(v.reason, fails[0]) << "pose " << i << ": " << c.Describe(v);
    if (v.reason == RejectionReason::kJointMargin) {
      EXPECT_EQ(v.a, first_joint) << i;
    }
    if (v.reason == RejectionReason::kObstacle) {
      EXPECT_EQ(v.a, first_obstacle) << i;
    }
  }
  // The pool exercises every reason but the camera's.
  for (RejectionReason r :
       {RejectionReason::kNone, RejectionReason::kJointMargin,
        RejectionReason::kOutOfRange, RejectionReason::kFacingAway,
        RejectionReason::kSelfCollision, RejectionReason::kObstacle,
        RejectionReason::kLineOfSight}) {
    EXPECT_GT(seen[static_cast<int>(r)], 0) << RejectionReasonLabel(r);
  }
}

TEST(CellPoolTest, MeasurablePoolIsFeasibleDeterministicAndCheaper) {
  Ur10e u;
  std::string error;
  ASSERT_TRUE(LoadUr10e(kData + "/cells/ur10e_table.yaml", &u, &error))
      << error;
  MeasurablePoolOptions o;
  o.num_poses = 60;
  o.seed = 5;
  o.num_threads = 1;
  MeasurablePoolSummary one, three;
  ASSERT_TRUE(SampleMeasurablePool(*u.setup.checker, o, &one)) << one.message;
  o.num_threads = 3;
  ASSERT_TRUE(SampleMeasurablePool(*u.setup.checker, o, &three));
  EXPECT_EQ(one.termination_type, TerminationType::kConvergence);
  ASSERT_EQ(one.joints.rows(), 60);
  EXPECT_EQ(one.joints, three.joints);
  EXPECT_EQ(one.draws, three.draws);
  EXPECT_EQ(one.ik_solves, three.ik_solves);
  // Every pose passes the checks, and far fewer draws are needed than by
  // rejection (about 1 in 40 Sobol poses passes in this cell).
  PoolFilterSummary check;
  ASSERT_TRUE(FilterPool(*u.setup.checker, one.joints, {}, &check));
  EXPECT_EQ(check.num_feasible(), 60);
  EXPECT_LT(one.DrawsPerPose(), 5.0);
  // Another seed, other poses.
  o.seed = 6;
  MeasurablePoolSummary other;
  ASSERT_TRUE(SampleMeasurablePool(*u.setup.checker, o, &other));
  EXPECT_NE(other.joints, one.joints);
  // A cell without a device has nothing to aim at.
  Ur10e bare;
  ASSERT_TRUE(LoadUr10e(DeviceFreeUrCell(), &bare, &error));
  EXPECT_FALSE(SampleMeasurablePool(*bare.setup.checker, o, &other));
  EXPECT_EQ(other.termination_type, TerminationType::kUserFailure);
}

TEST(CellPoolTest, WithACellTheLatticeSitsAtTheMarginsNotOnTheStops) {
  // The issue's iiwa: a 3-level lattice puts a joint on a stop in every
  // pose but one, which a 3 deg margin rejects. Inside the margins the
  // lattice's end levels sit exactly at them, which the check passes.
  RobotDescription robot;
  RobotLoadOptions o;
  o.chain.tip_link = "flange";
  std::string error;
  ASSERT_TRUE(LoadRobot(kData + "/kuka_iiwa14.urdf", o, &robot, &error))
      << error;
  const std::string path = TempPath("iiwa_margin.yaml");
  WriteText(path, "joint_margin_deg: 3\nself_clearance_m: 0.0\n");
  CellSetupOptions c;
  c.cell_path = path;
  c.robot_path = kData + "/kuka_iiwa14.urdf";
  c.chain = o.chain;
  CellSetup setup;
  ASSERT_TRUE(SetUpCell(c, &robot, &setup, &error)) << error;
  const RobotModel& model = robot.model;
  const RobotModel inside = WithinJointMargins(*setup.checker, model);
  const double m = 3 * kDeg;
  for (int j = 0; j < model.num_joints(); ++j) {
    EXPECT_DOUBLE_EQ(inside.links[j].joint_min, model.links[j].joint_min + m);
    EXPECT_DOUBLE_EQ(inside.links[j].joint_max, model.links[j].joint_max - m);
  }
  JointLattice on_stops, at_margins;
  ASSERT_TRUE(JointLattice::Create(model, 3, &on_stops, &error)) << error;
  ASSERT_TRUE(JointLattice::Create(inside, 3, &at_margins, &error)) << error;
  PoolFilterSummary before, after;
  ASSERT_TRUE(
      FilterPool(*setup.checker, on_stops.AllJointValues(), {}, &before));
  ASSERT_TRUE(
      FilterPool(*setup.checker, at_margins.AllJointValues(), {}, &after));
  EXPECT_EQ(before.num_poses, 2187);
  EXPECT_EQ(before.rejected[static_cast<int>(RejectionReason::kJointMargin)],
            2186);
  EXPECT_EQ(after.rejected[static_cast<int>(RejectionReason::kJointMargin)], 0);
  // Nothing else rejects here but self-collisions of folded poses.
  EXPECT_EQ(
      after.num_feasible() +
          after.rejected[static_cast<int>(RejectionReason::kSelfCollision)],
      2187);
  const Eigen::MatrixXd q = at_margins.AllJointValues();
  double least = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < q.rows(); ++i) {
    for (int j = 0; j < model.num_joints(); ++j) {
      least = std::min({least, q(i, j) - model.links[j].joint_min,
                        model.links[j].joint_max - q(i, j)});
    }
  }
  EXPECT_NEAR(least, m, 1e-12);
}

TEST(CellTourTest, PermutationNoLongerThanTheInputAndEveryMoveFree) {
  Ur10e u;
  std::string error;
  ASSERT_TRUE(LoadUr10e(kData + "/cells/ur10e_table.yaml", &u, &error))
      << error;
  MeasurablePoolOptions mo;
  mo.num_poses = 14;
  mo.seed = 2;
  MeasurablePoolSummary poses;
  ASSERT_TRUE(SampleMeasurablePool(*u.setup.checker, mo, &poses));
  TourOptions o;
  o.velocity_limits = u.setup.collision.velocity_limits;
  o.resolution_rad = 2 * kDeg;
  TourSummary tour;
  ASSERT_TRUE(OrderTour(u.setup.checker.get(), poses.joints, o, &tour));
  std::vector<int> sorted = tour.order;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 0; k < 14; ++k) EXPECT_EQ(sorted[k], k);
  // The times are the velocity-weighted ones.
  double before = 0, after = 0;
  for (int k = 0; k + 1 < 14; ++k) {
    before += MoveTime(poses.joints.row(k).transpose(),
                       poses.joints.row(k + 1).transpose(), tour.velocities);
    after += MoveTime(poses.joints.row(tour.order[k]).transpose(),
                      poses.joints.row(tour.order[k + 1]).transpose(),
                      tour.velocities);
  }
  EXPECT_NEAR(tour.time_before_s, before, 1e-9);
  EXPECT_NEAR(tour.time_after_s, after, 1e-9);
  auto w = u.setup.checker->NewWorkspace();
  if (tour.blocked_before == 0) {
    EXPECT_LE(tour.time_after_s, before + 1e-9);
  }
  // Every move of the tour, rechecked: free unless reported blocked.
  for (int k = 0; k + 1 < 14; ++k) {
    const bool free = MoveIsFree(
        *u.setup.checker, poses.joints.row(tour.order[k]).transpose(),
        poses.joints.row(tour.order[k + 1]).transpose(), o, w.get(), nullptr);
    const bool reported =
        std::count(tour.blocked_moves.begin(), tour.blocked_moves.end(), k) > 0;
    EXPECT_EQ(free, !reported) << "move " << k;
  }
  // The velocity limits weigh the joints: a slow joint makes its moves
  // long.
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(6);
  Eigen::VectorXd b = a;
  b[0] = 1.0;
  b[5] = 1.5;
  EXPECT_DOUBLE_EQ(MoveTime(a, b, {2, 2, 2, 2, 2, 3}), 0.5);
  EXPECT_DOUBLE_EQ(MoveTime(a, b, {0.5, 2, 2, 2, 2, 3}), 2.0);
}

TEST(CellTourTest, ABlockedMoveIsAvoidedByReordering) {
  // A post on the stick's sweep at angle 0, radius 0.62: the slider (a
  // ball of 0.02 at 0.45 + q2 along the arm) passes it when pulled in,
  // hits it when out.
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(kStickUrdf,
                          "obstacles:\n  - {name: post, type: sphere, "
                          "radius_m: 0.03, xyz_m: [0.62, 0, 0.5]}\n",
                          &f, &error))
      << error;
  Eigen::MatrixXd poses(3, 2);
  poses << 0.8, 0.19,  // A: out, on one side
      -0.8, 0.19,      // B: out, on the other: A -> B hits the post
      0.9, 0.0;        // C: in
  auto w = f.checker.NewWorkspace();
  PoseVerdict v;
  EXPECT_FALSE(MoveIsFree(f.checker, poses.row(0).transpose(),
                          poses.row(1).transpose(), TourOptions(), w.get(),
                          &v));
  EXPECT_EQ(f.checker.Describe(v), "obstacle post (slider)");
  // By time alone C, A, B (0.19 + 1.6 s at 1 rad/s) beats A, C, B (0.19 +
  // 1.7 s), but A -> B is blocked: the tour goes round through C.
  TourSummary tour;
  ASSERT_TRUE(OrderTour(&f.checker, poses, TourOptions(), &tour));
  EXPECT_EQ(tour.blocked_before, 1);
  EXPECT_TRUE(tour.blocked_moves.empty());
  EXPECT_EQ(tour.order[1], 2);
  EXPECT_NEAR(tour.time_after_s, 0.19 + 1.7, 1e-12);
  EXPECT_NEAR(tour.time_before_s, 1.6 + 1.7, 1e-12);
  // Without the checks the shortest order takes the blocked move.
  TourOptions unchecked;
  unchecked.check_moves = false;
  ASSERT_TRUE(OrderTour(&f.checker, poses, unchecked, &tour));
  EXPECT_NEAR(tour.time_after_s, 0.19 + 1.6, 1e-12);
}

TEST(CellHookTest, BuildSelectionPoolKeepsTheFilteredRows) {
  Ur10e u;
  std::string error;
  ASSERT_TRUE(LoadUr10e(kData + "/cells/ur10e_table.yaml", &u, &error))
      << error;
  MeasurablePoolOptions mo;
  mo.num_poses = 150;
  MeasurablePoolSummary measurable;
  ASSERT_TRUE(SampleMeasurablePool(*u.setup.checker, mo, &measurable));
  // Half of them, interleaved with poses the cell rejects.
  const Eigen::MatrixXd sobol = UrSobol(u.robot.model, 150);
  Eigen::MatrixXd joints(300, 6);
  for (int i = 0; i < 150; ++i) {
    joints.row(2 * i) = sobol.row(i);
    joints.row(2 * i + 1) = measurable.joints.row(i);
  }
  PoolFilterSummary feasibility;
  SelectionPoolOptions options;
  options.parameter_set = ParameterSet::kFull;
  options.filter = [&](const Eigen::MatrixXd& all, std::vector<int64_t>* kept,
                       std::string* note) {
    if (!FilterPool(*u.setup.checker, all, {}, &feasibility)) return false;
    *kept = feasibility.feasible;
    *note = "rejected: " + feasibility.CountsText(*u.setup.checker);
    return true;
  };
  RobotModel model = u.robot.model;
  CandidatePool pool;
  SelectionPoolSummary summary;
  ASSERT_TRUE(BuildSelectionPool(&model, joints, options, &pool, &summary))
      << summary.message;
  EXPECT_TRUE(summary.filtered);
  EXPECT_EQ(pool.size(), static_cast<int64_t>(summary.kept.size()));
  EXPECT_GE(pool.size(), 150);
  for (int i = 0; i < 150; ++i) {
    EXPECT_TRUE(std::binary_search(summary.kept.begin(), summary.kept.end(),
                                   2 * i + 1));
  }
  // A filter that keeps nothing: the note is in the message.
  options.filter = [](const Eigen::MatrixXd&, std::vector<int64_t>* kept,
                      std::string* note) {
    kept->clear();
    *note = "0 of 300 poses feasible; rejected: joint margin 300";
    return true;
  };
  model = u.robot.model;
  EXPECT_FALSE(BuildSelectionPool(&model, joints, options, &pool, &summary));
  EXPECT_EQ(summary.message,
            "no pose of the pool is left: 0 of 300 poses feasible; rejected: "
            "joint margin 300");
}

TEST(CellSetupTest, TargetsBecomeTheMarkers) {
  Ur10e u;
  std::string error;
  const std::string path = TempPath("two_targets.yaml");
  WriteText(path,
            "device: {type: laser_tracker, xyz_m: [2.2, 0.4, 0.9]}\n"
            "targets:\n"
            "  - {name: front, xyz_m: [0, 0, 0.06], normal: [0, 0, 1], "
            "acceptance_deg: 30}\n"
            "  - {name: side, xyz_m: [0.05, 0, 0.03], normal: [1, 0, 0], "
            "acceptance_deg: 45}\n");
  ASSERT_TRUE(LoadUr10e(path, &u, &error)) << error;
  const RobotModel& m = u.robot.model;
  ASSERT_EQ(m.num_markers(), 2);
  EXPECT_EQ(m.markers[1].name, "side");
  EXPECT_DOUBLE_EQ(m.nominal[m.block_offset(m.marker_block(1))], 0.05);
}

TEST(CellSetupTest, LinkPairsNeverAsFarApartAsTheClearanceAreNoted) {
  // The issue's cell sets only clearance_m: 0.05, which self_clearance_m
  // then takes. The UR10e's forearm and wrist 2 are 2.1-2.2 cm apart at
  // every pose (wrist 1 turns the wrist about the forearm housing's axis),
  // so every pose would be a self-collision: a note says so.
  Ur10e u;
  std::string error;
  const std::string path = TempPath("ur_clearance.yaml");
  WriteText(path, "clearance_m: 0.05\n");
  ASSERT_TRUE(LoadUr10e(path, &u, &error)) << error;
  const std::vector<PairDistance> close =
      SelfPairsAlwaysTooClose(*u.setup.checker);
  std::set<std::string> names;
  for (const PairDistance& d : close) {
    names.insert(d.first + "|" + d.second);
    EXPECT_LT(d.distance_m, 0.05);
  }
  EXPECT_EQ(names, (std::set<std::string>{"base_link_inertia|upper_arm_link",
                                          "forearm_link|wrist_2_link",
                                          "wrist_1_link|wrist_3_link"}));
  std::string notes;
  for (const std::string& n : u.setup.notes) notes += n + "\n";
  EXPECT_NE(notes.find("self_clearance_m 0.05: links base_link_inertia and "
                       "upper_arm_link are never that far apart (at most "
                       "0.021"),
            std::string::npos)
      << notes;
  EXPECT_NE(notes.find(", forearm_link and wrist_2_link (0.02"),
            std::string::npos)
      << notes;
  EXPECT_NE(notes.find("lower self_clearance_m or add the pairs to skip_pairs"),
            std::string::npos)
      << notes;
  // Every pose that reaches the collision checks is rejected indeed.
  PoolFilterSummary s;
  ASSERT_TRUE(
      FilterPool(*u.setup.checker, UrSobol(u.robot.model, 500), {}, &s));
  EXPECT_EQ(s.num_feasible(), 0);
  // The example cell (self_clearance_m: 0.01) has no such pair.
  Ur10e example;
  ASSERT_TRUE(LoadUr10e(kData + "/cells/ur10e_table.yaml", &example, &error))
      << error;
  EXPECT_TRUE(SelfPairsAlwaysTooClose(*example.setup.checker).empty());
  for (const std::string& n : example.setup.notes) {
    EXPECT_EQ(n.find("never that far apart"), std::string::npos) << n;
  }
}

TEST(CellSetupTest, TheTargetsSeenAreRecorded) {
  // Two targets on the stick, the device far along +x: A faces it at q1 =
  // 0, B is 40 deg round from A.
  std::string text = StickCell("", 0,
                               "device: {type: laser_tracker, xyz_m: "
                               "[1000, 0, 0.5]}\n");
  text +=
      "  - {name: B, xyz_m: [0, 0, 0], normal: [0.766044443118978, "
      "0.642787609686539, 0], acceptance_deg: 30}\n";
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(kStickUrdf, text, &f, &error)) << error;
  EXPECT_EQ(CheckStick(f, 0.0, 0.1).targets_seen, 1u);
  EXPECT_EQ(CheckStick(f, -0.3, 0.1).targets_seen, 3u);
  EXPECT_EQ(CheckStick(f, -0.6, 0.1).targets_seen, 2u);
  EXPECT_EQ(CheckStick(f, 0.6, 0.1).reason, RejectionReason::kFacingAway);
  Eigen::MatrixXd joints(3, 2);
  joints << 0.0, 0.1, -0.3, 0.1, 0.6, 0.1;
  PoolFilterSummary s;
  ASSERT_TRUE(FilterPool(f.checker, joints, {}, &s));
  EXPECT_EQ(s.feasible, (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(s.targets_seen, (std::vector<uint32_t>{1u, 3u}));
}

// Two reflectors back to back on the UR10e's flange (never both seen) as
// the markers, and the pool of the poses the tracker sees one of.
struct BackToBack {
  Ur10e u;
  PoolFilterSummary feasibility;
  Eigen::MatrixXd joints;  // the feasible poses
};

void LoadBackToBack(BackToBack* b) {
  const std::string path = TempPath("back_to_back.yaml");
  WriteText(path,
            "device: {type: laser_tracker, xyz_m: [2.2, 0.4, 0.9], "
            "range_m: [0.3, 6.0]}\n"
            "targets:\n"
            "  - {name: front, xyz_m: [0.01, 0, 0.06], normal: [0, 0, 1], "
            "acceptance_deg: 45}\n"
            "  - {name: back, xyz_m: [0, 0.02, -0.01], normal: [0, 0, -1], "
            "acceptance_deg: 45}\n");
  std::string error;
  ASSERT_TRUE(LoadUr10e(path, &b->u, &error)) << error;
  ASSERT_EQ(b->u.robot.model.num_markers(), 2);
  const Eigen::MatrixXd all = UrSobol(b->u.robot.model, 1500);
  ASSERT_TRUE(FilterPool(*b->u.setup.checker, all, {}, &b->feasibility));
  b->joints = b->feasibility.FeasibleJoints(all);
}

// Model `from`'s free columns in model `to`'s (-1: `to` has no such).
std::vector<int> ColumnsByName(const RobotModel& from, const RobotModel& to) {
  const std::vector<std::string> a = from.FreeParameterNames();
  const std::vector<std::string> b = to.FreeParameterNames();
  std::vector<int> map(a.size(), -1);
  for (size_t i = 0; i < a.size(); ++i) {
    const auto it = std::find(b.begin(), b.end(), a[i]);
    if (it != b.end()) map[i] = static_cast<int>(it - b.begin());
  }
  return map;
}

TEST(CellTargetsTest, ADesignPoseHasTheRowsOfTheMarkersSeenOnly) {
  BackToBack b;
  ASSERT_NO_FATAL_FAILURE(LoadBackToBack(&b));
  // The parameters the pool identifies (the full set, reduced), as
  // activecal_select finds them.
  RobotModel two = b.u.robot.model;
  {
    SelectionPoolOptions options;
    options.parameter_set = ParameterSet::kFull;
    options.auto_fix = true;
    PoolFilterSummary again;
    SetCellPoolFilter(*b.u.setup.checker, two, {}, &again, &options);
    CandidatePool pool;
    SelectionPoolSummary summary;
    ASSERT_TRUE(BuildSelectionPool(&two, b.joints, options, &pool, &summary))
        << summary.message;
    ASSERT_GT(two.num_free(), 20);
  }
  // The reduction sees the markers seen (with marker 0's rows alone it
  // would drop the back reflector's offsets, which its poses identify).
  {
    const std::vector<std::string> names = two.FreeParameterNames();
    for (const char* name : {"front.x", "back.x", "back.y", "back.z"}) {
      EXPECT_NE(std::find(names.begin(), names.end(), name), names.end())
          << name;
    }
  }
  int front_only = -1, back_only = -1;
  for (size_t i = 0; i < b.feasibility.targets_seen.size(); ++i) {
    const uint32_t seen = b.feasibility.targets_seen[i];
    EXPECT_NE(seen, 3u) << "back to back, both seen at feasible pose " << i;
    if (seen == 1u && front_only < 0) front_only = static_cast<int>(i);
    if (seen == 2u && back_only < 0) back_only = static_cast<int>(i);
  }
  ASSERT_GE(front_only, 0);
  ASSERT_GE(back_only, 0);

  CandidatePoolOptions o;
  o.marker_masks = b.feasibility.targets_seen;
  CandidatePool pool;
  CandidatePoolSummary summary;
  ASSERT_TRUE(
      BuildCandidatePool(two, two.nominal, b.joints, o, &pool, &summary))
      << summary.message;
  ASSERT_EQ(pool.block_rows(), 6);
  ASSERT_EQ(pool.size(), b.joints.rows());

  // One-marker models: the front reflector alone, the back one alone.
  RobotModel front = two;
  front.markers.resize(1);
  front.nominal = two.nominal.head(front.num_parameters());
  RobotModel back = front;
  back.markers[0] = two.markers[1];
  back.nominal.tail(kMarkerBlockSize) = two.nominal.segment(
      two.block_offset(two.marker_block(1)), kMarkerBlockSize);
  for (const auto& [one, pose, marker] :
       {std::make_tuple(&front, front_only, 0),
        std::make_tuple(&back, back_only, 1)}) {
    SCOPED_TRACE(one->markers[0].name);
    CandidatePool single;
    CandidatePoolSummary single_summary;
    ASSERT_TRUE(BuildCandidatePool(*one, one->nominal,
                                   b.joints.middleRows(pose, 1), {}, &single,
                                   &single_summary))
        << single_summary.message;
    const RowMatrixXd block = pool.CopyBlock(pose);
    const RowMatrixXd x = single.CopyBlock(0);
    // The unseen marker's rows are zero; the seen one's are the one-marker
    // model's, column for column (a marker's own columns by name).
    EXPECT_EQ(block.middleRows(3 * (1 - marker), 3).norm(), 0.0);
    const std::vector<int> map = ColumnsByName(*one, two);
    RowMatrixXd expected = RowMatrixXd::Zero(3, two.num_free());
    for (size_t c = 0; c < map.size(); ++c) {
      ASSERT_GE(map[c], 0);
      expected.col(map[c]) = x.col(c);
    }
    EXPECT_LT((block.middleRows(3 * marker, 3) - expected).norm(),
              1e-12 * expected.norm())
        << "\n"
        << block << "\n"
        << expected;
    // Its information is exactly the seen marker's.
    const Eigen::MatrixXd m = block.transpose() * block;
    const Eigen::MatrixXd m_one = expected.transpose() * expected;
    EXPECT_LT((m - m_one).norm(), 1e-12 * m_one.norm());
  }

  // A design's log det over the masked pool is the one recomputed from the
  // seen markers' measurements alone (and differs from one that measures
  // both at every pose).
  GreedyOptions g;
  g.num_poses = 40;
  SelectionSummary design;
  ASSERT_TRUE(GreedyDesign(pool, {}, g, &design)) << design.message;
  std::vector<Measurement> seen_rows, every_row;
  for (int64_t i : design.design) {
    for (int k = 0; k < 2; ++k) {
      Measurement m;
      m.joints = b.joints.row(i).transpose();
      m.marker = k;
      every_row.push_back(m);
      if (b.feasibility.targets_seen[i] & (1u << k)) seen_rows.push_back(m);
    }
  }
  Eigen::MatrixXd j_seen, j_every;
  std::string error;
  ASSERT_TRUE(
      StackedJacobian(two, two.nominal, seen_rows, 1.0, &j_seen, &error))
      << error;
  ASSERT_TRUE(
      StackedJacobian(two, two.nominal, every_row, 1.0, &j_every, &error))
      << error;
  EXPECT_EQ(j_seen.rows(), 3 * 40);
  const double recomputed = LogDetSpd(j_seen.transpose() * j_seen);
  EXPECT_NEAR(design.log_det, recomputed, 1e-8 * std::abs(recomputed));
  EXPECT_GT(LogDetSpd(j_every.transpose() * j_every), recomputed + 1.0);
}

TEST(CellTargetsTest, SelectionPoolTakesTheMasksOfTheCellFilter) {
  BackToBack b;
  ASSERT_NO_FATAL_FAILURE(LoadBackToBack(&b));
  const RobotModel& two = b.u.robot.model;
  EXPECT_TRUE(CellTargetsAreMarkers(*b.u.setup.checker, two));
  const Eigen::MatrixXd all = UrSobol(two, 1500);
  PoolFilterSummary feasibility;
  SelectionPoolOptions options;
  options.parameter_set = ParameterSet::kFull;
  options.auto_fix = true;
  SetCellPoolFilter(*b.u.setup.checker, two, {}, &feasibility, &options);
  ASSERT_EQ(options.kept_marker_masks, &feasibility.targets_seen);
  RobotModel model = two;
  CandidatePool pool;
  SelectionPoolSummary summary;
  ASSERT_TRUE(BuildSelectionPool(&model, all, options, &pool, &summary))
      << summary.message;
  ASSERT_EQ(pool.block_rows(), 6);
  for (int64_t i = 0; i < pool.size(); ++i) {
    const RowMatrixXd block = pool.CopyBlock(i);
    for (int k = 0; k < 2; ++k) {
      const bool seen = feasibility.targets_seen[i] & (1u << k);
      EXPECT_EQ(block.middleRows(3 * k, 3).norm() > 0, seen) << i << " " << k;
    }
  }
  // A pose that sees no marker is refused.
  CandidatePoolOptions o;
  o.marker_masks.assign(b.joints.rows(), 1u);
  o.marker_masks[3] = 0;
  CandidatePoolSummary s;
  EXPECT_FALSE(BuildCandidatePool(two, two.nominal, b.joints, o, &pool, &s));
  EXPECT_EQ(s.message, "pool pose 3: no marker seen");
  // One target: the pool stays marker 0's (today's pools).
  Ur10e one;
  std::string error;
  ASSERT_TRUE(LoadUr10e(kData + "/cells/ur10e_table.yaml", &one, &error));
  EXPECT_FALSE(CellTargetsAreMarkers(*one.setup.checker, one.robot.model));
}

// ---------------------------------------------------------------------
// Why a cell admits too few poses: the counts, the pair to blame, the
// measurable pool's cap on draws.

// The stick over a floor 3 cm below its links (arm box and slider sphere
// both 0.48 m high at their lowest): every pose too close at clearance
// 0.05 m.
std::string StickOverFloor(double floor_z) {
  char obstacles[160];
  std::snprintf(obstacles, sizeof(obstacles),
                "clearance_m: 0.05\nobstacles:\n  - {name: floor, type: "
                "plane, normal: [0, 0, 1], offset_m: %.17g}\n",
                floor_z);
  return StickCell(obstacles);
}

TEST(RejectionCountsTest, CountsPerReasonObstacleAndPairInFirstSeenOrder) {
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickOverFloor(0.45), &f, &error))
      << error;
  auto verdict = [](RejectionReason r, int a, int b) {
    PoseVerdict v;
    v.reason = r;
    v.a = static_cast<int16_t>(a);
    v.b = static_cast<int16_t>(b);
    return v;
  };
  const PoseVerdict facing = verdict(RejectionReason::kFacingAway, -1, -1);
  const PoseVerdict floor_0 = verdict(RejectionReason::kObstacle, 0, 0);
  const PoseVerdict floor_1 = verdict(RejectionReason::kObstacle, 0, 1);
  const PoseVerdict self = verdict(RejectionReason::kSelfCollision, 0, 1);
  const std::vector<std::pair<PoseVerdict, double>> poses = {
      {facing, 0.0},  {floor_1, 0.1}, {PoseVerdict(), 0.2}, {floor_0, 0.3},
      {floor_1, 0.4}, {self, 0.5},    {floor_1, 0.6},       {facing, 0.7}};
  RejectionCounts all, first, second;
  for (size_t k = 0; k < poses.size(); ++k) {
    const double q[2] = {poses[k].second, 0.1};
    all.Add(poses[k].first, q, 2);
    (k < 4 ? first : second).Add(poses[k].first, q, 2);
  }
  EXPECT_EQ(all.num_checked, 8);
  EXPECT_EQ(all.num_feasible, 1);
  EXPECT_EQ(all.num_rejected(), 7);
  EXPECT_EQ(all.rejected[static_cast<int>(RejectionReason::kFacingAway)], 2);
  EXPECT_EQ(all.rejected[static_cast<int>(RejectionReason::kObstacle)], 4);
  EXPECT_EQ(all.num_collisions(), 5);
  ASSERT_EQ(all.rejected_by_obstacle.size(), 1u);
  EXPECT_EQ(all.rejected_by_obstacle[0], 4);
  ASSERT_EQ(all.collisions.size(), 3u);
  EXPECT_EQ(all.collisions[0].b, 1);  // floor_1 first seen
  EXPECT_EQ(all.collisions[0].count, 3);
  EXPECT_EQ(all.collisions[0].first_joints, (std::vector<double>{0.1, 0.1}));
  EXPECT_EQ(all.collisions[1].count, 1);
  EXPECT_EQ(all.collisions[2].reason, RejectionReason::kSelfCollision);
  EXPECT_EQ(all.MostFrequentCollision(), &all.collisions[0]);
  // Merged in order, the halves give the same counts and example poses.
  first.Merge(second);
  EXPECT_EQ(first.num_checked, all.num_checked);
  EXPECT_EQ(first.rejected, all.rejected);
  EXPECT_EQ(first.rejected_by_obstacle, all.rejected_by_obstacle);
  ASSERT_EQ(first.collisions.size(), all.collisions.size());
  for (size_t k = 0; k < all.collisions.size(); ++k) {
    EXPECT_EQ(first.collisions[k].count, all.collisions[k].count);
    EXPECT_EQ(first.collisions[k].first_joints, all.collisions[k].first_joints);
  }
  EXPECT_EQ(first.CountsText(f.checker), all.CountsText(f.checker));
  EXPECT_EQ(all.CountsText(f.checker),
            "joint margin 0, self-collision 1, obstacle floor 4, out of range "
            "0, target facing away 2, line of sight blocked 0");
  // Not every pose, nor every one past the earlier checks (one feasible):
  // the most frequent pair.
  const std::string body = f.checker.robot().bodies[1].name;
  EXPECT_EQ(all.CollisionDiagnosis(f.checker).rfind(
                "most often (3 of 8 poses): link '" + body +
                    "' collides with obstacle 'floor' (0.03 m apart, "
                    "clearance_m 0.05); is 'floor' clear of the robot's base",
                0),
            0u)
      << all.CollisionDiagnosis(f.checker);
  // Without collisions, nothing to blame.
  RejectionCounts none;
  const double q0[2] = {0.0, 0.1};
  none.Add(facing, q0, 2);
  EXPECT_EQ(none.CollisionDiagnosis(f.checker), "");
}

// No pose left: FeasibleNote names the most frequent reason; the pair to
// blame only when a collision is that reason (it named a collision when
// facing away rejected most poses: #24, found by the new-user trial).
TEST(RejectionCountsTest, FeasibleNoteNamesTheMostFrequentReason) {
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickOverFloor(0.45), &f, &error))
      << error;
  // Two poses facing the device (they hit the floor), four facing away.
  Eigen::MatrixXd joints(6, 2);
  joints << 0.0, 0.1, 0.1, 0.1, 0.93, 0.1, 0.91, 0.1, -0.93, 0.1, -0.91, 0.1;
  PoolFilterSummary s;
  ASSERT_TRUE(FilterPool(f.checker, joints, {}, &s));
  ASSERT_EQ(s.num_feasible(), 0);
  ASSERT_EQ(s.rejected[static_cast<int>(RejectionReason::kFacingAway)], 4);
  ASSERT_EQ(s.rejected[static_cast<int>(RejectionReason::kObstacle)], 2);
  const std::string note = FeasibleNote(f.checker, s);
  // Facing away named first; the floor after it, as it rejected every pose
  // that reached its check.
  EXPECT_NE(note.find("; most often (4 of 6 poses): target facing away; "
                      "every pose that reached the obstacle checks (2 of 6): "
                      "link '"),
            std::string::npos)
      << note;
  // Collisions the most frequent: the pair to blame, as before.
  Eigen::MatrixXd more(5, 2);
  more << 0.0, 0.1, 0.1, 0.1, -0.1, 0.1, 0.93, 0.1, -0.93, 0.1;
  ASSERT_TRUE(FilterPool(f.checker, more, {}, &s));
  ASSERT_EQ(s.rejected[static_cast<int>(RejectionReason::kObstacle)], 3);
  EXPECT_NE(FeasibleNote(f.checker, s).find("collides with obstacle 'floor'"),
            std::string::npos)
      << FeasibleNote(f.checker, s);
}

TEST(RejectionCountsTest, EveryPoseAndEveryPosePastTheEarlierChecks) {
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickOverFloor(0.45), &f, &error))
      << error;
  // Inside +-0.3 rad the target faces the device: every pose reaches the
  // collision checks and one pair rejects it.
  Eigen::MatrixXd joints(7, 2);
  for (int i = 0; i < 7; ++i) joints.row(i) << -0.3 + 0.1 * i, 0.1;
  PoolFilterSummary s;
  ASSERT_TRUE(FilterPool(f.checker, joints, {}, &s));
  ASSERT_EQ(s.num_feasible(), 0);
  EXPECT_EQ(s.counts.num_checked, 7);
  EXPECT_EQ(s.counts.rejected, s.rejected);
  const std::string link = f.checker.Detail(s.verdicts[0]);
  const std::string every = "every pose: link '" + link +
                            "' collides with obstacle 'floor' (0.03 m apart, "
                            "clearance_m 0.05); ";
  EXPECT_EQ(s.counts.CollisionDiagnosis(f.checker).rfind(every, 0), 0u)
      << s.counts.CollisionDiagnosis(f.checker);
  // FeasibleNote (the line of "no pose of the pool is left") carries it.
  EXPECT_NE(FeasibleNote(f.checker, s).find("; " + every), std::string::npos)
      << FeasibleNote(f.checker, s);
  // Two poses facing away first: every pose past those checks.
  Eigen::MatrixXd wider(9, 2);
  wider.topRows(7) = joints;
  wider.row(7) << 1.0 - 4 * kDeg, 0.1;
  wider.row(8) << -1.0 + 4 * kDeg, 0.1;
  ASSERT_TRUE(FilterPool(f.checker, wider, {}, &s));
  EXPECT_EQ(s.rejected[static_cast<int>(RejectionReason::kFacingAway)], 2);
  EXPECT_EQ(s.counts.CollisionDiagnosis(f.checker).rfind(
                "every pose that reached the obstacle checks (7 of 9): "
                "link '" +
                    link + "'",
                0),
            0u)
      << s.counts.CollisionDiagnosis(f.checker);
  // The floor 1 cm lower: 0.04 m apart, still too close; 3 cm lower
  // (0.06 m): no collision, the note without a diagnosis.
  Fixture lower;
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickOverFloor(0.44), &lower, &error));
  ASSERT_TRUE(FilterPool(lower.checker, joints, {}, &s));
  EXPECT_NE(s.counts.CollisionDiagnosis(lower.checker)
                .find("(0.04 m apart, clearance_m 0.05)"),
            std::string::npos);
  Fixture clear;
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickOverFloor(0.42), &clear, &error));
  ASSERT_TRUE(FilterPool(clear.checker, joints, {}, &s));
  EXPECT_EQ(s.num_feasible(), 7);
  EXPECT_EQ(FeasibleNote(clear.checker, s).find("collides"), std::string::npos);
}

TEST(RejectionCountsTest, SelfPairNamesBothLinks) {
  Fixture f;
  std::string error;
  ASSERT_TRUE(MakeChecker(kStickUrdf, StickOverFloor(0.0), &f, &error))
      << error;
  RejectionCounts c;
  PoseVerdict v;
  v.reason = RejectionReason::kSelfCollision;
  v.a = 0;
  v.b = 1;
  const double q[2] = {0.0, 0.1};
  c.Add(v, q, 2);
  const auto& bodies = f.checker.robot().bodies;
  EXPECT_EQ(c.CollisionDiagnosis(f.checker).rfind(
                "every pose: links '" + bodies[0].name + "' and '" +
                    bodies[1].name + "' collide (",
                0),
            0u)
      << c.CollisionDiagnosis(f.checker);
  EXPECT_NE(c.CollisionDiagnosis(f.checker).find(
                "lower self_clearance_m or add the pair to skip_pairs"),
            std::string::npos);
}

TEST(CellPoolTest, MeasurablePoolGivesUpOrStopsAtItsCap) {
  // A UR10e whose table top is 20 cm above its base: the shoulder is in
  // the table at every pose.
  const std::string path = TempPath("high_table.yaml");
  WriteText(path,
            "joint_margin_deg: 3\nclearance_m: 0.05\nself_clearance_m: 0.01\n"
            "obstacles:\n"
            "  - {name: table, type: plane, normal: [0, 0, 1], offset_m: "
            "0.2}\n"
            "device: {type: laser_tracker, xyz_m: [2.2, 0.4, 0.9], range_m: "
            "[1.0, 6.0]}\n"
            "targets:\n  - {name: smr, xyz_m: [0, 0, 0.06], normal: [0, 0, "
            "1], acceptance_deg: 30}\n");
  Ur10e u;
  std::string error;
  ASSERT_TRUE(LoadUr10e(path, &u, &error)) << error;
  MeasurablePoolOptions o;
  o.num_poses = 50;
  EXPECT_EQ(MaxDraws(o), 500);  // kDefaultDrawsPerPose x num_poses
  o.give_up_draws = 70;
  MeasurablePoolSummary one, two;
  o.num_threads = 1;
  ASSERT_TRUE(SampleMeasurablePool(*u.setup.checker, o, &one));
  o.num_threads = 2;
  ASSERT_TRUE(SampleMeasurablePool(*u.setup.checker, o, &two));
  EXPECT_EQ(one.termination_type, TerminationType::kNoConvergence);
  EXPECT_TRUE(one.gave_up);
  EXPECT_EQ(one.draws, 70);  // exactly at the threshold, for any threads
  EXPECT_EQ(two.draws, 70);
  EXPECT_EQ(one.joints.rows(), 0);
  EXPECT_EQ(one.counts.rejected, two.counts.rejected);
  EXPECT_EQ(one.counts.rejected, one.rejected);
  EXPECT_EQ(one.counts.num_checked, one.solutions_checked);
  EXPECT_GT(one.rejected[static_cast<int>(RejectionReason::kObstacle)], 0);
  const std::string text = one.FailureText(*u.setup.checker);
  EXPECT_EQ(text, two.FailureText(*u.setup.checker));
  EXPECT_EQ(text.rfind("found no measurable pose in 70 draws", 0), 0u) << text;
  EXPECT_NE(text.find("collides with obstacle 'table'"), std::string::npos)
      << text;
  // Without giving up the cap ends it: max_draws draws, not one more.
  o.give_up_draws = 0;
  o.max_draws = 90;
  ASSERT_TRUE(SampleMeasurablePool(*u.setup.checker, o, &one));
  EXPECT_FALSE(one.gave_up);
  EXPECT_EQ(one.draws, 90);
  EXPECT_EQ(one.max_draws, 90);
  EXPECT_NE(one.message.find("in 90 draws (max_draws)"), std::string::npos)
      << one.message;
  // A cell that gives poses is not stopped by the threshold.
  Ur10e ok;
  ASSERT_TRUE(LoadUr10e(kData + "/cells/ur10e_table.yaml", &ok, &error));
  o.max_draws = 0;
  o.give_up_draws = 10;
  o.num_poses = 20;
  ASSERT_TRUE(SampleMeasurablePool(*ok.setup.checker, o, &one));
  EXPECT_EQ(one.termination_type, TerminationType::kConvergence);
  EXPECT_EQ(one.joints.rows(), 20);
  o.give_up_draws = -1;
  EXPECT_FALSE(SampleMeasurablePool(*ok.setup.checker, o, &one));
  EXPECT_EQ(one.termination_type, TerminationType::kUserFailure);
}

}  // namespace
}  // namespace activecal
