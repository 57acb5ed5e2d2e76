// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The ISO 9283:1998 section 6.8 test poses of a cube in the workspace,
// solved to joints (activecal_select --iso9283_cube):
//
//   Iso9283CubeOptions options;
//   options.centre_m = {0.6, 0.0, 0.5};  // robot's base frame
//   options.edge_m = 0.4;
//   Iso9283CubeSummary summary;
//   DesignIso9283Cube(model, model.nominal, options, &summary);
//   summary.joints.row(k): pose P(k+1)
//
// The cube: centre c, edge e, axes the columns u, v, w of `cube_rotation`
// (base frame), half edge h = e / 2. Its corners, numbered here
//   C1 = c + h(-u - v - w)   C2 = c + h(+u - v - w)
//   C7 = c + h(+u + v + w)   C8 = c + h(-u + v + w)
// span the measuring plane C1-C2-C7-C8 of ISO 9283 6.8.3, the diagonal
// plane through the opposite edges C1-C2 and C7-C8 (a rectangle e by
// sqrt(2) e). Its diagonals C1-C7 and C2-C8 are space diagonals of the
// cube, length L = sqrt(3) e. The test points:
//   P1 = c                          (the intersection of the diagonals)
//   P2 = C1 + f (C7 - C1)           P3 = C2 + f (C8 - C2)
//   P4 = C7 + f (C1 - C7)           P5 = C8 + f (C2 - C8)
// with f = corner_fraction = 0.1: P2-P5 on the diagonals at 10 % of L from
// the corners (ISO allows 10 +- 2 %). All five with one orientation of the
// measured target frame (`tool_rotation`, base frame; by default the
// orientation the frame has at the middle of the joint ranges).
//
// Solved with the inverse kinematics of the model (kinematics/, pose match)
// as a path: P1 from the middle of the joint ranges, each next from the
// previous solution; `check` (e.g. CellCompensationCheck) refuses a
// configuration the cell cannot run.

#ifndef ACTIVECAL_CALIBRATION_ISO9283_CUBE_H_
#define ACTIVECAL_CALIBRATION_ISO9283_CUBE_H_

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"
#include "activecal/io/targets_csv.h"
#include "activecal/kinematics/compensation.h"

namespace activecal {

struct Iso9283CubeOptions {
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();  // base frame
  double edge_m = 0.0;                                 // > 0
  Eigen::Matrix3d cube_rotation = Eigen::Matrix3d::Identity();
  bool has_tool_rotation = false;
  Eigen::Matrix3d tool_rotation = Eigen::Matrix3d::Identity();
  double corner_fraction = 0.1;  // in [0.08, 0.12]
  int marker = 0;
  // The configuration the cell cannot run: false with the reason.
  std::function<bool(const Eigen::VectorXd& joints, std::string* reason)> check;
};

struct Iso9283CubeSummary {
  bool ok = false;
  std::string message;                    // why not, when !ok
  std::vector<std::string> labels;        // P1 .. P5
  std::vector<Eigen::Vector3d> points_m;  // base frame
  Eigen::Matrix3d tool_rotation = Eigen::Matrix3d::Identity();  // base frame
  // C1, C2, C7, C8 (base frame).
  std::vector<Eigen::Vector3d> corners_m;
  Eigen::MatrixXd joints;  // 5 x num_joints, SI
  // The targets in the device's frame (the IK's), with the joints as
  // their start configurations.
  TargetList targets;
  CompensationSummary solve;  // per pose status and errors
  // One line per pose: label, point (mm, base frame), status, errors.
  std::string TableText() const;
};

// The five points of the cube (P1 .. P5) and its corners C1, C2, C7, C8,
// base frame (no solving): the geometry above.
void Iso9283CubePoints(const Iso9283CubeOptions& options,
                       std::vector<Eigen::Vector3d>* points,
                       std::vector<Eigen::Vector3d>* corners);

// False (summary->ok false, message) for a bad option (edge <= 0, not a
// rotation, a fraction outside [0.08, 0.12]) or a pose not solved (its
// label, status and why).
bool DesignIso9283Cube(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const Iso9283CubeOptions& options,
                       Iso9283CubeSummary* summary);

// Parses the cube of activecal_select --iso9283_cube,
// "cx,cy,cz,edge_m" (m, base frame) or "cx,cy,cz,edge_m,qw,qx,qy,qz" (the
// cube's axes as a unit quaternion), and the tool orientation of
// --iso9283_orientation, "qw,qx,qy,qz" (empty: the default above). False
// with one line naming the value that is wrong.
bool ParseIso9283Cube(const std::string& cube, const std::string& orientation,
                      Iso9283CubeOptions* options, std::string* error);

// The poses CSV of the five poses (PosesCsvText, pose_index 1..5) with the
// columns of ISO 9283 cycles (csv_files.h CommandedPose): `pose` P1..P5 and
// the commanded pose in the base frame, commanded_x_m,commanded_y_m,
// commanded_z_m,commanded_qw,commanded_qx,commanded_qy,commanded_qz (a
// measurements file of the cycles keeps them beside each row); and the targets
// CSV (TargetsCsvText: the points and orientations in the device's frame, the
// joints as starts) with the same column.
std::string Iso9283CubePosesCsvText(const RobotModel& model,
                                    const Iso9283CubeSummary& summary);
std::string Iso9283CubeTargetsCsvText(const RobotModel& model,
                                      const Iso9283CubeSummary& summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_ISO9283_CUBE_H_
