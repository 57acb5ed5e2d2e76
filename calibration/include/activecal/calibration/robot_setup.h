// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The robot a program works on (every program's --robot, --base_link,
// --tip_link and --frames): a robot file (YAML, or a URDF chain), its
// metrology frames, or the built-in PUMA 560 of the paper with its true
// values when no file is named.
//
//   RobotSetupOptions options;
//   options.robot_path = "ur10e.urdf";
//   options.chain.tip_link = "tool0";
//   RobotDescription robot;
//   if (!SetUpRobot(options, &robot, &note, &error)) ...
//   std::cout << note;

#ifndef ACTIVECAL_CALIBRATION_ROBOT_SETUP_H_
#define ACTIVECAL_CALIBRATION_ROBOT_SETUP_H_

#include <string>

#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

struct RobotSetupOptions {
  // The robot file (LoadRobot); empty: Puma560PaperModel with
  // Puma560TrueParameters.
  std::string robot_path;
  // A URDF robot's chain (empty ends: the root, the only leaf).
  UrdfChainOptions chain;
  // A metrology frames file applied after loading (LoadFramesFile); empty:
  // none.
  std::string frames_path;
};

// The robot of `options` into *robot. For a URDF robot *note says which
// joint is which ("robot '<name>': <n> joints: q1 <link>, q2 <link>, ...\n":
// the CSV files name joints q1..qn in chain order); empty otherwise. False
// with *error naming the options: "--base_link, --tip_link and --frames
// need a --robot file (...)" (a chain or frames without a file), "--robot:
// <file:line: ...>", "--frames: <file:line: ...>".
bool SetUpRobot(const RobotSetupOptions& options, RobotDescription* robot,
                std::string* note, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_ROBOT_SETUP_H_
