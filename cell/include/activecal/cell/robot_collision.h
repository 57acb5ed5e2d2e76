// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The robot's collision geometry: rigid bodies of collision shapes, each
// fixed to a frame of the RobotModel, and the joints' velocity limits.
//
// From a URDF (LoadUrdfCollision): the <collision> elements (box, cylinder,
// sphere, mesh with scale) of every link below base_link: the links of the
// chain, the links fixed to them (folded into the model's joints by the
// URDF reader) and the links after the tip. A link off the chain hangs from
// the nearest chain link through the joints between them, moving ones held
// at zero (a gripper's fingers). Origins are read as urdfdom's quaternions.
// Mesh files: a path relative to the URDF's directory, file://, or
// package://<package>/... found through ROS_PACKAGE_PATH.
//
// From a robot file (ParseRobotFileCollision, the robot YAML's
// `collision:` list, docs/formats.md): capsules per link,
//
//   collision:
//     - {link: L2, from_m: [0, 0, 0], to_m: [0.43, 0, 0], radius_m: 0.08}
//
// given in the frame after that link's transform (`link: base`: the
// robot's base frame, after the base block B).
//
// Frames: 0 is the robot's base frame (the base block B is not applied: the
// cell is given in this frame), j = 1..n the frame after the model's link
// j (a URDF joint's child link).

#ifndef ACTIVECAL_CELL_ROBOT_COLLISION_H_
#define ACTIVECAL_CELL_ROBOT_COLLISION_H_

#include <string>
#include <vector>

#include "activecal/cell/shape.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

struct CollisionBody {
  // The URDF link, or the robot file's link name ("base" for frame 0).
  std::string name;
  int frame = 0;
  // The body's frame in that model frame.
  FixedTransform in_frame;
  // Each shape's pose is in the body's frame. May be empty (a link
  // without collision elements).
  std::vector<CollisionShape> shapes;
};

struct RobotCollisionModel {
  std::vector<CollisionBody> bodies;
  // Per joint of the model: the velocity limit (rad/s or m/s) from the
  // URDF's <limit velocity>; 0 where none is given (robot files).
  std::vector<double> velocity_limits;

  int num_shapes() const;
  // The body named `name`, or -1.
  int BodyIndex(const std::string& name) const;
};

bool LoadUrdfCollision(const std::string& path, const UrdfChainOptions& chain,
                       const RobotModel& model, RobotCollisionModel* robot,
                       std::string* error);
// From URDF text; relative mesh paths are taken from `directory`.
bool ParseUrdfCollision(const std::string& xml, const std::string& source,
                        const std::string& directory,
                        const UrdfChainOptions& chain, const RobotModel& model,
                        RobotCollisionModel* robot, std::string* error);

// The `collision:` list of a robot file (absent: no shapes). Errors read
// "<source>:<line>:<column>: collision[2].radius_m: ...".
bool ParseRobotFileCollision(const std::string& text, const std::string& source,
                             const RobotModel& model,
                             RobotCollisionModel* robot, std::string* error);

// A URDF file (".urdf") or a robot file, as robot_loader.h tells them apart.
bool LoadRobotCollision(const std::string& path, const UrdfChainOptions& chain,
                        const RobotModel& model, RobotCollisionModel* robot,
                        std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CELL_ROBOT_COLLISION_H_
