// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The calibrated robot as URDF, checked before it is written: what
// activecal_identify --urdf_out and the Python module's Estimate.write_urdf
// write.
//
// A URDF robot gets its own file with only the calibrated joints' origins
// changed (urdf_export.h: CalibratedUrdfText); any other robot is written
// as a new URDF (UrdfFromModel: links base_link ... tip). The text is then
// reloaded and must predict every measured point of `check` within
// tolerance_m of the calibrated model (CheckUrdfAgainstModel), or the call
// fails: a URDF that does not reproduce the calibration is never written.
//
//   CalibratedUrdfOptions options;
//   options.source_path = "ur10e.urdf";   // "" for a YAML robot
//   options.chain.tip_link = "tool0";
//   options.output_path = "calibrated.urdf";
//   CalibratedUrdf urdf;
//   if (!MakeCalibratedUrdf(model, parameters, measurements, options, &urdf,
//                           &error)) ...
//   // urdf.text to write; urdf.worst_m the largest difference found.

#ifndef ACTIVECAL_CALIBRATION_CALIBRATION_EXPORT_H_
#define ACTIVECAL_CALIBRATION_CALIBRATION_EXPORT_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

// The largest distance allowed between the reloaded URDF's and the
// calibrated model's measured points (m).
inline constexpr double kUrdfReloadToleranceM = 1e-9;

struct CalibratedUrdfOptions {
  // The URDF file the robot was loaded from, with its chain; empty: the
  // robot is not a URDF robot (written by UrdfFromModel).
  std::string source_path;
  UrdfChainOptions chain;
  // Where the text will be written (names the reloaded file in messages).
  std::string output_path;
  double tolerance_m = kUrdfReloadToleranceM;
};

struct CalibratedUrdf {
  std::string text;
  // What the URDF cannot hold (a joint gain, a half-bounded range); also
  // filled when the check fails.
  std::vector<std::string> warnings;
  double worst_m = 0;  // the reload check's largest difference (m)
};

// The text of the calibrated URDF of `model` at `parameters` (full
// vector), reloaded and checked against `check`. False with *error (the
// caller prefixes its option: "--urdf_out: ..."): the source cannot be
// read or edited, "the written URDF does not reload: ...", or "the written
// URDF predicts the measurements up to D m away from the calibrated model
// (more than 1e-9 m)[: <first warning>]".
bool MakeCalibratedUrdf(const RobotModel& model,
                        const Eigen::VectorXd& parameters,
                        const std::vector<Measurement>& check,
                        const CalibratedUrdfOptions& options,
                        CalibratedUrdf* urdf, std::string* error);

// The kinematics file of the UR ROS driver (io/ur_kinematics.h) of a
// calibrated UR: what activecal_identify --ur_calibration_out and Python's
// Estimate.save_ur_calibration write. The robot must be UR-shaped: six
// revolute URDF joints named as ur_description names them
// (shoulder_pan_joint ... wrist_3_joint, all with the same prefix, if
// any), each turning about its frame's z with gain 1, loaded on the chain
// base_link -> tool0. Each entry is the joint's calibrated origin with the
// joint offset folded in, origin * Correction * Rz(offset) (the first
// relative to base_link_inertia = base_link Rz(pi)); the rotations are
// converted to the format's roll, pitch, yaw at the end only
// (RotationToShortRpy: also at pitch +-90 deg). The base registration and
// the markers are metrology and stay out (they go to a frames file).
//
// Checked before it is returned: the text is read back, the chain rebuilt
// from its numbers as ur_description's ur_macro.xacro builds it
// (UrTool0Pose) and compared with the calibrated model's chain (base_link
// to its tip) at the joints of `check` and at fixed poses; the largest
// differences must be at most kUrCalibrationTolerance (m and rad).
inline constexpr double kUrCalibrationTolerance = 1e-9;

struct UrCalibration {
  std::string text;
  double worst_m = 0;    // the check's largest position difference (m)
  double worst_rad = 0;  // ... and rotation difference (rad)
};

// False with one line in *error (the caller prefixes its option): "the
// robot is not a UR: ..." naming why, or "the written UR kinematics do not
// reproduce the calibrated model: ... (more than 1e-9 m / rad): ...".
// `comment`: lines written at the top of the file.
bool MakeUrCalibration(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const std::vector<Measurement>& check,
                       const std::string& comment, UrCalibration* out,
                       std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_CALIBRATION_EXPORT_H_
