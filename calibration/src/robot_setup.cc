// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/robot_setup.h"

#include "activecal/core/puma560.h"
#include "activecal/io/frames_file.h"
#include "activecal/io/robot_loader.h"

namespace activecal {

bool SetUpRobot(const RobotSetupOptions& options, RobotDescription* robot,
                std::string* note, std::string* error) {
  *robot = RobotDescription();
  note->clear();
  if (options.robot_path.empty()) {
    if (!options.chain.base_link.empty() || !options.chain.tip_link.empty() ||
        !options.frames_path.empty()) {
      *error =
          "--base_link, --tip_link and --frames need a --robot file (the "
          "built-in PUMA has neither a URDF chain nor a 6-DOF base)";
      return false;
    }
    robot->model = Puma560PaperModel();
    robot->true_parameters = Puma560TrueParameters();
    return true;
  }
  RobotLoadOptions load;
  load.chain = options.chain;
  if (!LoadRobot(options.robot_path, load, robot, error)) {
    *error = "--robot: " + *error;
    return false;
  }
  if (!options.frames_path.empty() &&
      !LoadFramesFile(options.frames_path, robot, error)) {
    *error = "--frames: " + *error;
    return false;
  }
  if (IsUrdfPath(options.robot_path)) {
    // The CSV files name joints q1..qn in chain order: say which is which.
    const RobotModel& model = robot->model;
    *note = "robot '" + model.name +
            "': " + std::to_string(model.num_joints()) + " joints: ";
    for (int j = 0; j < model.num_joints(); ++j) {
      *note +=
          (j ? ", q" : "q") + std::to_string(j + 1) + " " + model.links[j].name;
    }
    *note += "\n";
  }
  return true;
}

}  // namespace activecal
