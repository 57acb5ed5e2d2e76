// One entry for every robot description activecal reads: a URDF file
// (".urdf", a serial chain of it, urdf_robot.h) or an activecal robot YAML
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

// True for a path that names a URDF file (ends in ".urdf", any case).
bool IsUrdfPath(const std::string& path);

bool LoadRobot(const std::string& path, const RobotLoadOptions& options,
               RobotDescription* robot, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_ROBOT_LOADER_H_
