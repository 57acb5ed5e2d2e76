// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The kinematics file of Universal Robots' ROS description
// (ur_description's config/<type>/default_kinematics.yaml, which the UR ROS
// driver loads with kinematics_params_file:=FILE, and ur_calibration
// writes from a robot's own calibration):
//
//   kinematics:
//     shoulder:  {x: .., y: .., z: .., roll: .., pitch: .., yaw: ..}
//     upper_arm: ...
//     forearm:   ...
//     wrist_1:   ...
//     wrist_2:   ...
//     wrist_3:   ...
//     hash: calib_...
//
// Each entry is the <origin> of one joint (shoulder_pan_joint,
// shoulder_lift_joint, elbow_joint, wrist_1_joint, wrist_2_joint,
// wrist_3_joint): x, y, z in metres and roll, pitch, yaw in radians as URDF
// writes them (R = Rz(yaw) Ry(pitch) Rx(roll), fixed axes), every joint
// turning about its frame's z. ur_description's ur_macro.xacro builds the
// chain base_link -> tool0 as
//
//   Rz(pi)                                   base_link -> base_link_inertia
//   * prod_i Trans(x, y, z) Rpy(roll, pitch, yaw) Rz(q_i)     the six joints
//   * Rpy(0, -pi/2, -pi/2)                        wrist_3_link -> flange
//   * Rpy(pi/2, 0, pi/2)                          flange -> tool0
//
// which UrTool0Pose computes.

#ifndef ACTIVECAL_IO_UR_KINEMATICS_H_
#define ACTIVECAL_IO_UR_KINEMATICS_H_

#include <Eigen/Core>
#include <array>
#include <string>

namespace activecal {

// "shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3".
extern const char* const kUrKinematicsEntries[6];
// The joints they are the origins of: "shoulder_pan_joint", ...,
// "wrist_3_joint".
extern const char* const kUrJointNames[6];

struct UrJointOrigin {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();  // m
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();  // rad, URDF convention
};

struct UrKinematics {
  std::array<UrJointOrigin, 6> joints;
  std::string hash;  // the "hash:" entry, as written
};

// The file's text: `comment` lines first ("# " added), every number in its
// shortest form that reads back to the same double.
std::string UrKinematicsText(const UrKinematics& kinematics,
                             const std::string& comment);

// Reads the text back (the six entries with their six numbers each, and
// the hash). False with "<source>:<line>:<column>: <field>: <what>".
bool ParseUrKinematics(const std::string& text, const std::string& source,
                       UrKinematics* kinematics, std::string* error);

// tool0 in base_link at joint readings q (6, rad), built as the macro
// above does.
void UrTool0Pose(const UrKinematics& kinematics, const Eigen::VectorXd& q,
                 Eigen::Matrix3d* R, Eigen::Vector3d* t);

}  // namespace activecal

#endif  // ACTIVECAL_IO_UR_KINEMATICS_H_
