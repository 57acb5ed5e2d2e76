// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_select --iso9283_cube's work (calibration/iso9283_cube_poses.h):
// a cube or orientation that does not parse gives the message and no table;
// a cube out of reach the message naming the pose (and the table); a
// reachable cube both CSV texts (header and five rows, read back by the
// library's readers) with poses whose forward kinematics reach the points
// at 10 % of the diagonals from the cube's corners (computed here) with the
// asked orientation; a cell's checker refuses a cube inside its table.

#include "activecal/calibration/iso9283_cube_poses.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "activecal/cell/cell_setup.h"
#include "activecal/core/kinematics.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/targets_csv.h"

namespace activecal {
namespace {

RobotDescription LoadUrdf(const std::string& name) {
  RobotLoadOptions options;
  options.chain.tip_link = "tool0";
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(LoadRobot(std::string(ACTIVECAL_DATA_DIR) + "/" + name, options,
                        &robot, &error))
      << error;
  return robot;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  return cells;
}

int Column(const std::vector<std::string>& header, const std::string& name) {
  for (size_t k = 0; k < header.size(); ++k) {
    if (header[k] == name) return static_cast<int>(k);
  }
  return -1;
}

// Neither CSV text (poses, targets) was made.
void ExpectNoCsvText(const Iso9283CubePoses& poses) {
  EXPECT_TRUE(poses.poses_csv.empty()) << poses.poses_csv;
  EXPECT_TRUE(poses.targets_csv.empty()) << poses.targets_csv;
}

TEST(Iso9283CubePosesTest, BadCubeGivesTheMessageAndNoTable) {
  const RobotModel model = LoadUrdf("ur10.urdf").model;
  Iso9283CubePoses poses;
  poses.table = "left over";
  EXPECT_FALSE(
      MakeIso9283CubePoses(model, {"0.6,0.2,0.5", "", nullptr}, &poses));
  EXPECT_FALSE(poses.ok);
  EXPECT_EQ(poses.message,
            "--iso9283_cube: expected cx,cy,cz,edge_m or "
            "cx,cy,cz,edge_m,qw,qx,qy,qz (m, base frame), got 3 values");
  EXPECT_TRUE(poses.table.empty()) << poses.table;
  ExpectNoCsvText(poses);

  EXPECT_FALSE(
      MakeIso9283CubePoses(model, {"0.6,0.2,0.5,0", "", nullptr}, &poses));
  EXPECT_EQ(poses.message, "--iso9283_cube: the edge (value 4) must be > 0 m");
  EXPECT_TRUE(poses.table.empty());

  // A good cube with an orientation that does not parse.
  EXPECT_FALSE(MakeIso9283CubePoses(
      model, {"0.6,0.2,0.5,0.3", "0,1,0", nullptr}, &poses));
  EXPECT_EQ(poses.message,
            "--iso9283_orientation: expected qw,qx,qy,qz, got 3 values");
  EXPECT_TRUE(poses.table.empty());
  EXPECT_TRUE(poses.poses_csv.empty());
}

TEST(Iso9283CubePosesTest, OutOfReachNamesThePose) {
  const RobotModel model = LoadUrdf("ur10.urdf").model;
  Iso9283CubePoses poses;
  EXPECT_FALSE(MakeIso9283CubePoses(
      model, {"5.6,0.2,0.5,0.3", "0,1,0,0", nullptr}, &poses));
  EXPECT_FALSE(poses.ok);
  EXPECT_EQ(poses.message.rfind(
                "--iso9283_cube: P1 at (5600.0, 200.0, 500.0) mm (base "
                "frame): unreachable",
                0),
            0u)
      << poses.message;
  EXPECT_EQ(poses.message.find('\n'), std::string::npos) << poses.message;
  // The table is kept (the poses not solved in it); no CSV text.
  EXPECT_NE(poses.table.find("P1"), std::string::npos) << poses.table;
  ExpectNoCsvText(poses);
}

TEST(Iso9283CubePosesTest, ReachableCubeGivesBothCsvTexts) {
  const RobotModel model = LoadUrdf("ur10.urdf").model;
  Iso9283CubePoses poses;
  ASSERT_TRUE(MakeIso9283CubePoses(
      model, {"0.6,0.2,0.5,0.3", "0,1,0,0", nullptr}, &poses))
      << poses.message;
  EXPECT_TRUE(poses.ok);
  EXPECT_TRUE(poses.message.empty()) << poses.message;
  EXPECT_GE(Lines(poses.table).size(), 5u) << poses.table;
  for (const char* label : {"P1", "P2", "P3", "P4", "P5"}) {
    EXPECT_NE(poses.table.find(label), std::string::npos) << label;
  }

  // The poses CSV: a header and five rows, the labels and the joints.
  const std::vector<std::string> lines = Lines(poses.poses_csv);
  ASSERT_EQ(lines.size(), 6u) << poses.poses_csv;
  const std::vector<std::string> header = Cells(lines[0]);
  const int pose_column = Column(header, "pose");
  ASSERT_GE(pose_column, 0) << lines[0];
  for (const char* name :
       {"commanded_x_m", "commanded_y_m", "commanded_z_m", "commanded_qw",
        "commanded_qx", "commanded_qy", "commanded_qz"}) {
    EXPECT_GE(Column(header, name), 0) << name << " in " << lines[0];
  }
  for (int k = 0; k < 5; ++k) {
    const std::vector<std::string> row = Cells(lines[k + 1]);
    EXPECT_EQ(row.size(), header.size()) << lines[k + 1];
    ASSERT_GT(static_cast<int>(row.size()), pose_column);
    EXPECT_EQ(row[pose_column], "P" + std::to_string(k + 1));
  }
  PoseList read;
  std::string error;
  ASSERT_TRUE(
      ParsePosesCsv(poses.poses_csv, "cube.csv", model, true, &read, &error))
      << error;
  ASSERT_EQ(read.joints.rows(), 5);
  EXPECT_EQ(read.joints, poses.summary.joints);

  // The targets CSV: five targets with the joints as starts.
  ASSERT_EQ(Lines(poses.targets_csv).size(), 6u) << poses.targets_csv;
  EXPECT_GE(Column(Cells(Lines(poses.targets_csv)[0]), "pose"), 0)
      << poses.targets_csv;
  TargetList targets;
  ASSERT_TRUE(ParseTargetsCsv(poses.targets_csv, "cube_targets.csv", model,
                              &targets, &error))
      << error;
  ASSERT_EQ(targets.points.rows(), 5);
  ASSERT_EQ(targets.start_joints.rows(), 5);
  EXPECT_EQ(targets.start_joints, poses.summary.joints);

  // The poses reach the cube's points, computed here from its corners: P1
  // the centre, P2..P5 at 10 % of the diagonal from C1, C2, C7, C8 toward
  // the opposite corner; the tool turned 180 deg about the base's x.
  const Eigen::Vector3d c(0.6, 0.2, 0.5);
  const double h = 0.15;
  const Eigen::Vector3d c1 = c + h * Eigen::Vector3d(-1, -1, -1);
  const Eigen::Vector3d c2 = c + h * Eigen::Vector3d(1, -1, -1);
  const Eigen::Vector3d c7 = c + h * Eigen::Vector3d(1, 1, 1);
  const Eigen::Vector3d c8 = c + h * Eigen::Vector3d(-1, 1, 1);
  const Eigen::Vector3d want[5] = {c, c1 + 0.1 * (c7 - c1),
                                   c2 + 0.1 * (c8 - c2), c7 + 0.1 * (c1 - c7),
                                   c8 + 0.1 * (c2 - c8)};
  const Eigen::Vector3d corner[5] = {c, c1, c2, c7, c8};
  const Eigen::Matrix3d tool = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const std::vector<const double*> blocks =
      BlockPointers(model, model.nominal.data());
  Eigen::Matrix3d rb, r;
  Eigen::Vector3d tb, t;
  LinkTransform(model.base, blocks[0], 0.0, &rb, &tb);
  for (int k = 0; k < 5; ++k) {
    const Eigen::VectorXd q = poses.summary.joints.row(k).transpose();
    EXPECT_TRUE(model.CheckJointValues(q, nullptr)) << "P" << k + 1;
    TargetFrame(model, model.nominal, q, &r, &t);
    const Eigen::Vector3d p = rb.transpose() * (t - tb);
    EXPECT_LT((p - want[k]).norm(), 1e-9) << "P" << k + 1 << ": " << p;
    if (k > 0) {
      EXPECT_NEAR((p - corner[k]).norm(), 0.1 * std::sqrt(3.0) * 2 * h, 1e-9)
          << "P" << k + 1;
    }
    const Eigen::AngleAxisd d(rb.transpose() * r * tool.transpose());
    EXPECT_LT(std::abs(d.angle()), 1e-9) << "P" << k + 1;
  }
}

TEST(Iso9283CubePosesTest, CellCheckerRefusesACubeInTheTable) {
  RobotDescription robot = LoadUrdf("ur10e.urdf");
  CellSetupOptions cell_options;
  cell_options.cell_path =
      std::string(ACTIVECAL_DATA_DIR) + "/cells/ur10e_table.yaml";
  cell_options.robot_path = std::string(ACTIVECAL_DATA_DIR) + "/ur10e.urdf";
  cell_options.chain.tip_link = "tool0";
  CellSetup cell;
  std::string error;
  ASSERT_TRUE(SetUpCell(cell_options, &robot, &cell, &error)) << error;
  ASSERT_NE(cell.checker, nullptr);
  const RobotModel& model = robot.model;
  // Without the checker the cube under the table top is solved; with it
  // P1 is refused, named.
  Iso9283CubePoses poses;
  ASSERT_TRUE(MakeIso9283CubePoses(
      model, {"0.6,0.2,-0.3,0.2", "0,1,0,0", nullptr}, &poses))
      << poses.message;
  EXPECT_FALSE(MakeIso9283CubePoses(
      model, {"0.6,0.2,-0.3,0.2", "0,1,0,0", cell.checker.get()}, &poses));
  EXPECT_EQ(poses.message.rfind("--iso9283_cube: P1 at (600.0, 200.0, "
                                "-300.0) mm (base frame): ",
                                0),
            0u)
      << poses.message;
  EXPECT_TRUE(poses.poses_csv.empty());
  EXPECT_TRUE(poses.targets_csv.empty());
  EXPECT_FALSE(poses.table.empty());
}

}  // namespace
}  // namespace activecal
