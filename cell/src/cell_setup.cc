// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/cell_setup.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "activecal/core/random.h"
#include "activecal/core/text_table.h"
#include "activecal/io/frames_file.h"
#include "activecal/io/robot_loader.h"

namespace activecal {
namespace {

// Configurations SetUpCell samples for SelfPairsAlwaysTooClose.
constexpr int kSelfPairSamples = 64;

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
    text += "  - {name: " + Quoted(t.name) + ", xyz: [" +
            FormatNumber("%.17g", t.xyz_m.x()) + ", " +
            FormatNumber("%.17g", t.xyz_m.y()) + ", " +
            FormatNumber("%.17g", t.xyz_m.z()) + "]}\n";
  }
  return ParseFramesFile(text, cell.source + " (targets as markers)", robot,
                         error);
}

RobotModel WithinJointMargins(const CellChecker& checker,
                              const RobotModel& model) {
  RobotModel narrowed = model;
  for (int j = 0; j < narrowed.num_joints(); ++j) {
    Link& l = narrowed.links[j];
    const double m = checker.joint_margin(j);
    if (std::isfinite(l.joint_min)) l.joint_min += m;
    if (std::isfinite(l.joint_max)) l.joint_max -= m;
  }
  return narrowed;
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

std::vector<PairDistance> SelfPairsAlwaysTooClose(const CellChecker& checker,
                                                  int samples) {
  const RobotModel& model = checker.model();
  // (link, link) -> the largest distance seen, while below the clearance
  // at every sample so far.
  std::map<std::pair<std::string, std::string>, double> close;
  Random random(1);
  auto workspace = checker.NewWorkspace();
  Eigen::VectorXd q(model.num_joints());
  for (int k = 0; k < samples && (k == 0 || !close.empty()); ++k) {
    for (int j = 0; j < model.num_joints(); ++j) {
      const Link& l = model.links[j];
      const double m = checker.joint_margin(j);
      const double lo = std::isfinite(l.joint_min) ? l.joint_min + m : -M_PI;
      const double hi = std::isfinite(l.joint_max) ? l.joint_max - m : M_PI;
      q[j] = lo + (hi - lo) * random.Uniform();
    }
    std::map<std::pair<std::string, std::string>, double> still;
    for (const PairDistance& d : checker.Distances(q.data(), workspace.get())) {
      if (d.obstacle || !(d.distance_m < checker.cell().self_clearance_m)) {
        continue;
      }
      const auto key = std::make_pair(d.first, d.second);
      const auto it = close.find(key);
      if (k == 0) {
        still[key] = d.distance_m;
      } else if (it != close.end()) {
        still[key] = std::max(it->second, d.distance_m);
      }
    }
    close = std::move(still);
  }
  std::vector<PairDistance> out;
  for (const auto& [pair, distance] : close) {
    out.push_back({pair.first, pair.second, false, distance});
  }
  return out;
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
  setup->collision_source =
      setup->collision.num_shapes() > 0 ? options.robot_path : std::string();
  if (setup->collision.num_shapes() == 0 &&
      !options.collision_fallback_path.empty()) {
    RobotCollisionModel fallback;
    if (!LoadRobotCollision(options.collision_fallback_path, options.chain,
                            robot->model, &fallback, error)) {
      return false;
    }
    if (fallback.num_shapes() > 0) {
      // Keep the robot's own velocity limits where its file gives them.
      for (size_t j = 0; j < fallback.velocity_limits.size() &&
                         j < setup->collision.velocity_limits.size();
           ++j) {
        if (setup->collision.velocity_limits[j] > 0) {
          fallback.velocity_limits[j] = setup->collision.velocity_limits[j];
        }
      }
      setup->collision = std::move(fallback);
      setup->collision_source = options.collision_fallback_path;
      setup->notes.push_back(
          (options.robot_path.empty() ? std::string("the robot")
                                      : options.robot_path) +
          " has no collision geometry: that of " +
          options.collision_fallback_path + " (the same chain) is used");
    }
  }
  if (setup->collision.num_shapes() == 0) {
    setup->notes.push_back(
        "the robot has no collision geometry (<collision> in its URDF, "
        "collision: in its robot file): self-collision, obstacles and the "
        "robot's shadow on lines of sight are not checked");
  }
  // The device must see from outside the robot's fixed links too (frame 0:
  // they never move out of its way).
  const std::vector<Cell::Eye> eyes = DeviceEyes(setup->cell);
  for (const CollisionBody& body : setup->collision.bodies) {
    if (body.frame != 0) continue;
    for (const CollisionShape& shape : body.shapes) {
      for (const Cell::Eye& eye : eyes) {
        const Eigen::Vector3d in_body =
            body.in_frame.rotation.transpose() *
            (eye.position - body.in_frame.translation);
        const Eigen::Vector3d in_shape = shape.pose.rotation.transpose() *
                                         (in_body - shape.pose.translation);
        if (PointInShape(shape, in_shape)) {
          if (error) {
            *error = eye.where +
                     ": the device lies inside the robot's fixed "
                     "link '" +
                     body.name + "' (its collision geometry in " +
                     setup->collision_source + ")";
          }
          return false;
        }
      }
    }
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
  const std::vector<PairDistance> close =
      SelfPairsAlwaysTooClose(*setup->checker, kSelfPairSamples);
  if (!close.empty()) {
    std::string pairs;
    for (size_t k = 0; k < close.size(); ++k) {
      char at_most[32];
      std::snprintf(at_most, sizeof(at_most), "%.4g", close[k].distance_m);
      pairs += (k == 0 ? "links " : ", ") + close[k].first + " and " +
               close[k].second +
               (k == 0 ? " are never that far apart (at most " : " (") +
               at_most + " m" +
               (k == 0 ? " at " + std::to_string(kSelfPairSamples) +
                             " sampled poses)"
                       : ")");
    }
    char head[64];
    std::snprintf(head, sizeof(head),
                  "self_clearance_m %.4g: ", setup->cell.self_clearance_m);
    setup->notes.push_back(
        head + pairs +
        ": every pose that reaches the collision checks is rejected as a "
        "self-collision; lower self_clearance_m or add the pairs to "
        "skip_pairs");
  }
  return true;
}

}  // namespace activecal
