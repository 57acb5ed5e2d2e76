// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The targets CSV: Cartesian targets for the robot's marker, one per row,
// in the measuring device's (base/tracker) frame (docs/formats.md):
//
//   pose_index,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,q1_rad,...,q6_rad
//   0,0.61,20.3,0.92,0.1,-1.2,0.4,0.1,...,0.3
//
//   pose_index     optional label (default: the row number, from 0)
//   x_m, y_m, z_m  the target point (m), required; or x_mm, y_mm, z_mm
//   rx_rad, ry_rad, rz_rad
//                  optional: the target orientation of the marker frame as
//                  a rotation vector (axis times angle, angle <= pi); or a
//                  unit quaternion qw,qx,qy,qz; or roll_rad,pitch_rad,
//                  yaw_rad / roll_deg,pitch_deg,yaw_deg (R = Rz(yaw)
//                  Ry(pitch) Rx(roll)): the forms of the measurements CSV
//   q<j>_rad / q<j>_m (or q<j>_deg / q<j>_mm), or by joint name
//                  (elbow_joint_rad, ...)
//                  optional, every joint or none: the start configuration
//                  of each target (e.g. the controller's own solution); it
//                  must be inside the joint limits
//
// The columns are read by the measurements CSV's own column logic, so a
// file the measurements reader takes is read alike. Other columns are
// ignored and named in a note (with columns_strict: an error). Lines
// starting with '#' are comments; fields may have spaces around them.
// Every error names the file, the line and the column.

#ifndef ACTIVECAL_IO_TARGETS_CSV_H_
#define ACTIVECAL_IO_TARGETS_CSV_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

struct TargetList {
  std::vector<int64_t> pose_indices;  // from pose_index, or 0, 1, 2, ...
  Eigen::MatrixXd points;             // n x 3 (m)
  // n x 3 rotation vectors (rad), or 0 rows when the file has none.
  Eigen::MatrixXd rotation_vectors;
  // n x num_joints start configurations (SI), or 0 rows when none.
  Eigen::MatrixXd start_joints;
};

struct TargetsCsvOptions {
  // Columns the reader does not know: named in a note (false) or an error.
  bool columns_strict = false;
};

// `notes` (may be null): one line naming the columns ignored, if any.
bool ParseTargetsCsv(const std::string& text, const std::string& source,
                     const RobotModel& model, const TargetsCsvOptions& options,
                     TargetList* targets, std::vector<std::string>* notes,
                     std::string* error);
bool ReadTargetsCsv(const std::string& path, const RobotModel& model,
                    const TargetsCsvOptions& options, TargetList* targets,
                    std::vector<std::string>* notes, std::string* error);
// The same with the default options, the notes dropped.
bool ParseTargetsCsv(const std::string& text, const std::string& source,
                     const RobotModel& model, TargetList* targets,
                     std::string* error);
bool ReadTargetsCsv(const std::string& path, const RobotModel& model,
                    TargetList* targets, std::string* error);

// The file text of `targets` (the columns it has); numbers in their
// shortest form that reads back to the same double.
std::string TargetsCsvText(const RobotModel& model, const TargetList& targets);

}  // namespace activecal

#endif  // ACTIVECAL_IO_TARGETS_CSV_H_
