// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Serial chains of URDF robot descriptions as RobotModels, parsed with
// urdfdom.
//
//   RobotDescription robot;
//   UrdfChainOptions chain;
//   chain.tip_link = "tool0";  // several leaves: say which
//   std::string error;
//   if (!LoadUrdfRobot("data/ur10.urdf", chain, &robot, &error)) {
//     std::cerr << error << "\n";  // "data/ur10.urdf: the chain has several
//   }                              //  leaves (base, tool0): ..."
//
// The chain runs from base_link (default: the URDF root) to tip_link
// (default: the only leaf). Every revolute, continuous or prismatic joint on
// it becomes a link of convention kUrdf, in chain order, named after the
// joint: its origin is the joint's origin with the fixed joints before it
// (back to the previous moving joint or base_link) folded in, its axis the
// joint's axis, its range the URDF limits (continuous: unbounded); every
// rotation is read from urdfdom's quaternion, never through roll-pitch-yaw
// (urdfdom's getRPY snaps pitches near +-90 deg). The fixed
// joints after the last moving joint form the model's tip transform, so the
// markers are given in tip_link's frame. The base is a 6-DOF frame
// (convention kFrame) at the identity: the registration of base_link in the
// measuring device's frame. One marker, "tool", at the tip frame's origin.
// Nothing is free; choose a parameter set (parameter_sets.h).
//
// Floating and planar joints, and mimic joints, cannot be part of a
// calibrated chain: they are errors naming the joint.

#ifndef ACTIVECAL_IO_URDF_ROBOT_H_
#define ACTIVECAL_IO_URDF_ROBOT_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/io/robot_file.h"

namespace activecal {

struct UrdfChainOptions {
  std::string base_link;  // empty: the URDF root link
  std::string tip_link;   // empty: the only leaf below base_link
};

// A joint of the URDF file on the chosen chain, as the file has it (for
// writing a calibrated URDF back): its origin, a point x of the joint frame
// being rotation * x + xyz in the parent link's frame (the rotation from
// urdfdom's quaternion, not through roll-pitch-yaw).
struct UrdfChainJoint {
  std::string name;
  bool moving = false;  // revolute, continuous or prismatic
  std::string parent_link, child_link;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

// Parses URDF text; `source` names it in messages ("<source>: ...").
bool ParseUrdfRobot(const std::string& xml, const std::string& source,
                    const UrdfChainOptions& options, RobotDescription* robot,
                    std::string* error);
bool LoadUrdfRobot(const std::string& path, const UrdfChainOptions& options,
                   RobotDescription* robot, std::string* error);

// The joints of the chain from base_link to tip_link, in order, fixed ones
// included.
bool UrdfChainJoints(const std::string& xml, const std::string& source,
                     const UrdfChainOptions& options,
                     std::vector<UrdfChainJoint>* joints, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_URDF_ROBOT_H_
