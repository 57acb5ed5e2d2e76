#include "activecal/cell/cell_setup.h"

#include <cstdio>

#include "activecal/io/frames_file.h"
#include "activecal/io/robot_loader.h"

namespace activecal {
namespace {

std::string Number(double x) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", x);
  return buffer;
}

// A YAML double-quoted string.
std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

bool UseTargetsAsMarkers(const Cell& cell, RobotDescription* robot,
                         std::string* error) {
  if (cell.targets.empty()) return true;
  // Through the frames file's reader, which rebuilds the marker blocks,
  // the nominal vector and the true values.
  std::string text = "markers:\n";
  for (const CellTarget& t : cell.targets) {
    text += "  - {name: " + Quoted(t.name) + ", xyz: [" + Number(t.xyz_m.x()) +
            ", " + Number(t.xyz_m.y()) + ", " + Number(t.xyz_m.z()) + "]}\n";
  }
  return ParseFramesFile(text, cell.source + " (targets as markers)", robot,
                         error);
}

std::vector<double> RobotVelocityLimits(const std::string& robot_path,
                                        const UrdfChainOptions& chain,
                                        const RobotModel& model) {
  RobotCollisionModel collision;
  if (!robot_path.empty() && IsUrdfPath(robot_path) &&
      LoadUrdfCollision(robot_path, chain, model, &collision, nullptr)) {
    return collision.velocity_limits;
  }
  return std::vector<double>(model.num_joints(), 0.0);
}

bool SetUpCell(const CellSetupOptions& options, RobotDescription* robot,
               CellSetup* setup, std::string* error) {
  setup->notes.clear();
  if (!LoadCellFile(options.cell_path, &setup->cell, error)) return false;
  if (options.robot_path.empty()) {
    setup->collision = RobotCollisionModel();
    setup->collision.velocity_limits.assign(robot->model.num_joints(), 0.0);
  } else if (!LoadRobotCollision(options.robot_path, options.chain,
                                 robot->model, &setup->collision, error)) {
    return false;
  }
  if (setup->collision.num_shapes() == 0) {
    setup->notes.push_back(
        "the robot has no collision geometry (<collision> in its URDF, "
        "collision: in its robot file): self-collision, obstacles and the "
        "robot's shadow on lines of sight are not checked");
  }
  if (options.targets_as_markers &&
      !UseTargetsAsMarkers(setup->cell, robot, error)) {
    return false;
  }
  setup->checker = std::make_unique<CellChecker>();
  std::string why;
  if (!setup->checker->Init(robot->model, setup->collision, setup->cell,
                            &why)) {
    if (error) *error = why;
    return false;
  }
  return true;
}

}  // namespace activecal
