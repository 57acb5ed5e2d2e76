#include "activecal/io/robot_loader.h"

#include <algorithm>
#include <cctype>

#include "activecal/io/frames_file.h"

namespace activecal {

bool IsUrdfPath(const std::string& path) {
  if (path.size() < 5) return false;
  std::string tail = path.substr(path.size() - 5);
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return tail == ".urdf";
}

bool LoadRobot(const std::string& path, const RobotLoadOptions& options,
               RobotDescription* robot, std::string* error) {
  RobotDescription loaded;
  if (IsUrdfPath(path)) {
    if (!LoadUrdfRobot(path, options.chain, &loaded, error)) return false;
  } else {
    if (!options.chain.base_link.empty() || !options.chain.tip_link.empty()) {
      if (error) {
        *error = path +
                 ": --base_link and --tip_link choose a chain of a URDF "
                 "file; this is not one (no .urdf ending)";
      }
      return false;
    }
    if (!LoadRobotFile(path, &loaded, error)) return false;
  }
  if (!options.frames_path.empty() &&
      !LoadFramesFile(options.frames_path, &loaded, error)) {
    return false;
  }
  *robot = std::move(loaded);
  return true;
}

}  // namespace activecal
