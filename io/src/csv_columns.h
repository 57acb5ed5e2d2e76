// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Internal to the io library: the column logic of the measurements CSV
// (csv_files.cc) for another file of the same columns, the targets CSV
// (targets_csv.cc), so that both accept the same columns.

#ifndef ACTIVECAL_IO_SRC_CSV_COLUMNS_H_
#define ACTIVECAL_IO_SRC_CSV_COLUMNS_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {
namespace internal {

// Rows of a point for the marker, optionally its orientation, optionally
// the joints, as the measurements CSV writes them: the point x_m,y_m,z_m
// or x_mm,y_mm,z_mm; the orientation as a rotation vector
// (rx_rad,ry_rad,rz_rad), a unit quaternion (qw,qx,qy,qz) or roll, pitch,
// yaw (_rad or _deg); the joints as q<j>_rad / q<j>_deg / q<j>_m / q<j>_mm
// or by joint name (elbow_joint_rad, ...), every joint or none; and an
// optional pose_index label. Every cell of a column read is filled.
struct PointTable {
  std::vector<int> lines;             // the file line of each row
  std::vector<int64_t> pose_indices;  // pose_index, or 0, 1, 2, ...
  Eigen::MatrixXd points;             // n x 3 (m)
  // n x 3 rotation vectors (rad), 0 rows without orientation columns.
  Eigen::MatrixXd rotation_vectors;
  bool rotation_given_as_vector = false;  // rx_rad,ry_rad,rz_rad
  // n x num_joints (SI; not checked against the limits), or 0 rows.
  Eigen::MatrixXd joints;
  // Columns not read, in header order.
  std::vector<std::string> unread;
};

// Parses `text`; with columns_strict, a column not read is an error. On
// failure false with "<source>:<line>: <what>" in *error.
bool ParsePointTable(const std::string& text, const std::string& source,
                     const RobotModel& model, bool columns_strict,
                     PointTable* table, std::string* error);

// "<source>: ignored 2 columns activecal does not read: a, b", the note of
// the measurements reader.
std::string UnreadColumnsNote(const std::string& source,
                              const std::vector<std::string>& unread);

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_IO_SRC_CSV_COLUMNS_H_
