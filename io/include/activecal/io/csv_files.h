// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The CSV files of the calibration workflow (docs/formats.md):
//
//   poses        what to run on the robot: pose_index, then each joint in SI
//                units (q1_rad, or q3_m for a prismatic joint) and in the
//                unit a robot pendant shows (q1_deg, q3_mm). Reading needs
//                one of the two per joint; when both are there they must
//                agree.
//   measurements what the device reported: type (position, pose, distance;
//                without the column: pose when the file has orientation
//                columns, position otherwise), the joints (q1_rad / q1_deg /
//                q3_m / q3_mm, or by URDF joint name: elbow_joint_rad), and
//                the measured values: the point (x_m,y_m,z_m or
//                x_mm,y_mm,z_mm), the orientation of a pose (rotation
//                vector rx_rad,ry_rad,rz_rad; unit quaternion qw,qx,qy,qz;
//                or roll_rad,pitch_rad,yaw_rad / _deg with R = Rz(yaw)
//                Ry(pitch) Rx(roll)), the second pose's joints (q1_rad_2 ...)
//                and distance_m / distance_mm (distance); standard
//                deviations sigma_m (or sigma_x_m,sigma_y_m,sigma_z_m, or a
//                95% expanded uncertainty u95_m = 2 sigma; _mm forms too)
//                and sigma_rad / sigma_deg (pose). One representation per
//                quantity per file. Fields a row's type does not use are
//                left empty. An optional "marker" column names the model's
//                marker a row measured (its name, or its number 1, 2, ...;
//                empty or no column: the first). The wide form of motion
//                capture, x1_m,y1_m,z1_m,x2_m,..., gives one position per
//                marker k (the model's marker k, 1-based) and row; a
//                marker's empty cells mean it was not seen. Columns
//                activecal does not know (a device's temperature,
//                timestamps, ...) are ignored and listed in a note.
//
// Lines starting with '#' are comments. The text may be as spreadsheets
// and device software write it: CRLF line ends, a UTF-8 byte order mark,
// quoted fields ("P1, north"), rows of separators only and columns with no
// name that stay empty; the separator is ',' (';', tabs and UTF-16 are
// named as errors). Every reader names the file, the line and the column of
// a problem: "poses.csv:7: q3_rad: expected a number, got 'abc'".

#ifndef ACTIVECAL_IO_CSV_FILES_H_
#define ACTIVECAL_IO_CSV_FILES_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/column_map.h"

namespace activecal {

// The SI column name of joint j (0-based): "q1_rad" or "q1_m".
std::string JointColumn(const RobotModel& model, int j);

struct PoseList {
  Eigen::MatrixXd joints;             // one pose per row, SI units
  std::vector<int64_t> pose_indices;  // from pose_index, or 0, 1, 2, ...
};

// The largest pose label the readers take (labels are integers in
// [0, kMaxPoseIndex], written in full).
inline constexpr int64_t kMaxPoseIndex = 9000000000000000;

// Labels a file can hold: each in [0, kMaxPoseIndex] and, with `unique`
// (the labels of a pool, which name its poses), no two the same. False
// with one line naming the first bad entry: "pose_indices[2] = -1: ...".
// Check labels with it before PosesCsvText (and TargetsCsvText) writes
// them: every reader refuses a file with others.
bool CheckPoseIndices(const std::vector<int64_t>& labels, bool unique,
                      std::string* error);

std::string PosesCsvText(const RobotModel& model, const PoseList& poses);
// Checks each pose against the joint limits; with reject_duplicates (a
// pool), two identical poses or two rows of the same pose_index are an
// error naming both lines.
bool ParsePosesCsv(const std::string& text, const std::string& source,
                   const RobotModel& model, bool reject_duplicates,
                   PoseList* poses, std::string* error);
bool ReadPosesCsv(const std::string& path, const RobotModel& model,
                  bool reject_duplicates, PoseList* poses, std::string* error);

// How a pose's orientation is written. Roll, pitch, yaw are fixed-axis
// angles, R = Rz(yaw) Ry(pitch) Rx(roll) (the URDF/ROS convention).
enum class OrientationFormat {
  kRotationVector,  // rx_rad, ry_rad, rz_rad: axis times angle
  kQuaternion,      // qw, qx, qy, qz: unit quaternion, qw >= 0
  kRpyRad,          // roll_rad, pitch_rad, yaw_rad
  kRpyDeg,          // roll_deg, pitch_deg, yaw_deg
};

// The columns MeasurementsCsvText writes. The default is SI throughout and
// reads back bit for bit; the others round-trip to rounding (1e-15
// relative).
struct MeasurementsCsvFormat {
  bool millimetres = false;    // x_mm.., distance_mm, sigma_mm
  bool joint_degrees = false;  // q1_deg / q3_mm instead of q1_rad / q3_m
  bool joint_names = false;    // <joint name>_rad instead of q<j>_rad
  OrientationFormat orientation = OrientationFormat::kRotationVector;
};

// Writes one row per measurement; the sigma columns (sigma_m, or
// sigma_x_m,sigma_y_m,sigma_z_m for rows whose axes differ, and sigma_rad)
// when any measurement carries them.
std::string MeasurementsCsvText(const RobotModel& model,
                                const std::vector<Measurement>& measurements,
                                const MeasurementsCsvFormat& format = {});

// How a measurements file is read.
struct MeasurementsCsvOptions {
  // Joint readings beyond the model's joint ranges are accepted when they
  // lie within the tolerance below, with one warning per file (real
  // readings do: a torso reads 0.35018 m against a 0.35 m limit); beyond
  // the tolerance they are an error (a wrong file or wrong units). With
  // strict_limits every reading beyond a range is an error. The tolerances
  // may be tightened, not widened: CheckMeasurement (and so Identify,
  // EvaluateModel) holds readings to kMeasuredJointTolerance*.
  bool strict_limits = false;
  double limit_tolerance_rad = kMeasuredJointToleranceRad;  // revolute
  double limit_tolerance_m = kMeasuredJointToleranceM;      // prismatic
  // Columns activecal does not know: listed in a note (false) or an error.
  bool columns_strict = false;
  // A device's export read as it comes (column_map.h): the file's text is
  // rewritten through the map before it is read. Without one, the file is
  // in activecal's own form.
  std::optional<ColumnMap> column_map;

  // Tolerances in [0, kMeasuredJointToleranceRad] and
  // [0, kMeasuredJointToleranceM].
  bool IsValid(std::string* error) const;
};

// What reading a file had to say besides the measurements: each entry one
// line, naming the file.
struct MeasurementsCsvReport {
  // Joint readings beyond the ranges, within the tolerance: at most one
  // line per file, naming the rows, joints and excess in the file's units.
  std::vector<std::string> warnings;
  // Ignored columns; marker positions not seen (empty cells) that were
  // skipped.
  std::vector<std::string> notes;
  // Rows of the file each measurement came from (1-based line numbers).
  std::vector<int> lines;
};

// Parses a measurements file; `report` may be null. On failure returns
// false with "<source>:<line>: <column>: <what is wrong>" in *error.
bool ParseMeasurementsCsv(const std::string& text, const std::string& source,
                          const RobotModel& model,
                          const MeasurementsCsvOptions& options,
                          std::vector<Measurement>* measurements,
                          MeasurementsCsvReport* report, std::string* error);
bool ReadMeasurementsCsv(const std::string& path, const RobotModel& model,
                         const MeasurementsCsvOptions& options,
                         std::vector<Measurement>* measurements,
                         MeasurementsCsvReport* report, std::string* error);
// The same with the default options, the report dropped.
bool ParseMeasurementsCsv(const std::string& text, const std::string& source,
                          const RobotModel& model,
                          std::vector<Measurement>* measurements,
                          std::string* error);
bool ReadMeasurementsCsv(const std::string& path, const RobotModel& model,
                         std::vector<Measurement>* measurements,
                         std::string* error);

// ISO 9283 cycles (docs/iso9283.md): the commanded pose of each row of a
// measurements file, read from the columns
//   pose                    the label the cycles to one commanded pose share
//                           (P1, P2, ...: any text, not empty)
//   commanded_x_m, commanded_y_m, commanded_z_m (or commanded_x_mm, ...)
//                           the commanded point of the measured target frame
//                           in the robot's base frame
//   commanded_qw, commanded_qx, commanded_qy, commanded_qz (a unit
//   quaternion, as qw..qz of a measured pose) or commanded_r11 ...
//   commanded_r33 (a rotation matrix, row by row)
//                           the commanded orientation of that frame in the
//                           base frame; optional for position measurements
// The measurements reader knows these columns (no note, no strict-columns
// error) and leaves them to this one. One entry per data row, in file
// order, with its line (MeasurementsCsvReport::lines of the measurements).
struct CommandedPose {
  int line = 0;
  std::string pose;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m
  bool has_rotation = false;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

// A commanded rotation matrix is one when |R^T R - I| (largest entry) is
// within this and det R > 0; it is then replaced by the nearest rotation.
inline constexpr double kCommandedRotationTolerance = 1e-6;

// False with "<source>:<line>: <column>: ..." for a missing 'pose' or
// commanded point column, an empty label, a quaternion that is not a unit
// one or a matrix that is not a rotation. options.column_map is applied as
// by ParseMeasurementsCsv.
bool ParseCommandedPosesCsv(const std::string& text, const std::string& source,
                            const RobotModel& model,
                            const MeasurementsCsvOptions& options,
                            std::vector<CommandedPose>* poses,
                            std::string* error);
bool ReadCommandedPosesCsv(const std::string& path, const RobotModel& model,
                           const MeasurementsCsvOptions& options,
                           std::vector<CommandedPose>* poses,
                           std::string* error);

// The same for a poses file that may carry the cycle columns (a 'pose'
// column, as activecal_select --iso9283_cube writes them): true with *poses
// empty when the header (its first line that is neither blank nor a
// comment) has no 'pose' column.
bool ParseCommandedPosesIfAny(const std::string& text,
                              const std::string& source,
                              const RobotModel& model,
                              const MeasurementsCsvOptions& options,
                              std::vector<CommandedPose>* poses,
                              std::string* error);

// `text` (MeasurementsCsvText of measurements i = 0, 1, ...) with the
// cycle columns of commanded[row_of[i]] appended to each data row: pose
// (quoted when it holds a comma or a quote), commanded_x_m, _y_m, _z_m and,
// when any commanded pose has an orientation, commanded_qw..qz (%.17g), so
// that the ISO 9283 reader reads the file back. row_of holds one entry per
// data row of `text` (CHECK-fails otherwise).
std::string WithCommandedPoseColumns(
    const std::string& text, const std::vector<CommandedPose>& commanded,
    const std::vector<int>& row_of);

// The columns the measurements reader (ParseMeasurementsCsv) and the ISO
// 9283 reader (ParseCommandedPosesCsv) read, from the reader's own lists of
// each quantity's forms: the fixed names ("type", "marker", "pose_index",
// "pose", "x_m", ..., "commanded_qw", ..., "commanded_r33", "sigma_deg"),
// in no particular order. A column map (column_map.h) accepts exactly
// these, the joints' and the wide form's.
std::vector<std::string> MeasurementsCsvFixedColumns();
// `name` is one of those columns for `model`: a fixed name, a joint's
// (q<j>_rad / _deg / _m / _mm or <joint name>_rad / ..., with an optional
// "_2") or the wide form's x<k>_m / y<k>_mm / ....
bool IsMeasurementsCsvColumn(const std::string& name, const RobotModel& model);

// Reads a whole file; false with "<path>: cannot open ..." on failure.
bool ReadTextFile(const std::string& path, std::string* text,
                  std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_CSV_FILES_H_
