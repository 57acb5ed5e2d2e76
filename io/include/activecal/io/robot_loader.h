// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// One entry for every robot description activecal reads: a URDF file
// (".urdf", a serial chain of it, urdf_robot.h; or a xacro file, ".xacro"
// or ".urdf.xacro", expanded by running `xacro` when it is installed) or an
// activecal robot YAML
// file (robot_file.h), optionally with a metrology frames file
// (frames_file.h).
//
//   RobotLoadOptions options;
//   options.chain.tip_link = "tool0";
//   options.frames_path = "frames.yaml";
//   RobotDescription robot;
//   std::string error;
//   if (!LoadRobot("ur10.urdf", options, &robot, &error)) { ... }

#ifndef ACTIVECAL_IO_ROBOT_LOADER_H_
#define ACTIVECAL_IO_ROBOT_LOADER_H_

#include <string>

#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

struct RobotLoadOptions {
  // URDF only: the chain's ends.
  UrdfChainOptions chain;
  // If not empty, a frames file applied after loading.
  std::string frames_path;
};

// True for a path that names a URDF file (ends in ".urdf" or ".xacro", any
// case).
bool IsUrdfPath(const std::string& path);
// True for a xacro file (ends in ".xacro", any case: robot.urdf.xacro).
bool IsXacroPath(const std::string& path);

// The URDF text of `path`: a .urdf file as it is; a xacro file expanded by
// `xacro` found on PATH (run as `xacro FILE`, its output into a temporary
// file). False with one line: "FILE is a xacro file: run `xacro FILE >
// robot.urdf` (xacro is not installed)", or "FILE: xacro failed (exit
// status N): <its first error line>".
bool ReadUrdfText(const std::string& path, std::string* xml,
                  std::string* error);

bool LoadRobot(const std::string& path, const RobotLoadOptions& options,
               RobotDescription* robot, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_ROBOT_LOADER_H_
