// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Calibrated robots back into the URDF world.
//
// CalibratedUrdfText rewrites a URDF so that it carries a calibration of its
// chain: only the <origin> of every calibrated joint changes, to
//
//   origin' = origin * Correction(x, y, z, rx, ry, rz) * Motion(offset)
//
// (the joint offset folded into the origin: a rotation about the axis of a
// revolute joint, a translation along the axis of a prismatic one), so that
// the joint at reading q sits where the calibrated model puts it. Every
// other byte of the file stays as it was. The base registration and the
// markers are metrology, not geometry: they go to a frames file
// (frames_file.h), not into the URDF. A joint gain other than 1 cannot be
// written in URDF; it is reported in *warnings.
//
// UrdfFromModel writes a URDF of any model (DH, modified DH, Hayati, URDF
// joints): links "base_link", "link1" ... "linkN" and "tip", joints named
// after the model's links (XML-escaped) and a fixed joint to "tip" named
// "tip_fixed" (or "tip_fixed_2", ... if a link of the model has that name),
// the base block folded into the first joint's origin unless it is a 6-DOF
// frame (then it is metrology and left out). Revolute joints unbounded at
// both ends are "continuous", others carry their <limit>; a range with one
// unbounded end cannot be held and is reported in *warnings.
//
// Rotations are written as rpy angles that read back to them
// (RotationToRpy: also at pitch +-90 deg); joints of the input file are
// found by their name as the XML parser reads it (entities replaced), and
// CalibratedUrdfText reads the edited text back to check its origins.
//
// Both are checked by reloading: CheckUrdfAgainstModel reads a URDF (with
// the model's base frame and markers applied) and compares the measured
// point of every measurement with the model's prediction.

#ifndef ACTIVECAL_IO_URDF_EXPORT_H_
#define ACTIVECAL_IO_URDF_EXPORT_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

// `xml`: the URDF the model was loaded from with `chain`; `model` and
// `values` (full vector): the calibration. Returns false with a message
// when a joint of the model is not in the file or the file cannot be
// edited.
bool CalibratedUrdfText(const std::string& xml, const std::string& source,
                        const UrdfChainOptions& chain, const RobotModel& model,
                        const Eigen::VectorXd& values, std::string* out,
                        std::vector<std::string>* warnings, std::string* error);

// A URDF of `model` at `values`. Gains other than 1 are reported in
// *warnings.
std::string UrdfFromModel(const RobotModel& model,
                          const Eigen::VectorXd& values,
                          std::vector<std::string>* warnings);

// Loads `urdf` (chain `chain`), applies the base frame and markers of
// `model` at `values` (a 6-DOF base is copied; any other base is part of
// the URDF), and returns in *max_difference_m the largest distance between
// the reloaded and the model's measured points over `measurements`.
bool CheckUrdfAgainstModel(const std::string& urdf, const std::string& source,
                           const UrdfChainOptions& chain,
                           const RobotModel& model,
                           const Eigen::VectorXd& values,
                           const std::vector<Measurement>& measurements,
                           double* max_difference_m, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_URDF_EXPORT_H_
