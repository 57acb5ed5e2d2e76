// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Metrology frames (YAML): where the robot's base sits in the measuring
// device's frame and where the measured points (markers) sit on the end
// effector. They are not robot geometry, so a calibrated URDF does not hold
// them; activecal_identify --frames_out writes them and every program reads
// them with --frames beside a URDF robot.
//
//   # frames.yaml
//   angle_unit: rad                 # or deg, for every rpy below
//   base: {xyz: [0.4, 0, 0.1], rpy: [0, 0, 1.5708]}
//   markers:
//     - {name: tool, xyz: [0, 0, 0.12], rpy: [0, 0, 0]}
//     - {name: smr2, xyz: [0.05, 0, 0.1]}
//
// base: the robot base frame in the device's frame (translation in m, then
// R = Rz(yaw) Ry(pitch) Rx(roll)); markers: each point (and target
// orientation, for 6D measurements) in the tip frame. Both optional.

#ifndef ACTIVECAL_IO_FRAMES_FILE_H_
#define ACTIVECAL_IO_FRAMES_FILE_H_

#include <string>

#include "activecal/io/robot_file.h"

namespace activecal {

// Applies the frames of `text` to robot->model: the base values (the base
// must be a 6-DOF frame, convention kFrame) and the markers (their number,
// names and values; the free flags of a new marker are those of the first).
// The nominal vector and the true values (when given) follow. On failure
// returns false with "<source>:<line>:<column>: <field>: <what>".
bool ParseFramesFile(const std::string& text, const std::string& source,
                     RobotDescription* robot, std::string* error);
bool LoadFramesFile(const std::string& path, RobotDescription* robot,
                    std::string* error);

// The frames file text of `model` with the full parameter vector `values`.
std::string FramesFileText(const RobotModel& model,
                           const Eigen::VectorXd& values,
                           const std::string& comment = "");

}  // namespace activecal

#endif  // ACTIVECAL_IO_FRAMES_FILE_H_
