// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The metrology frames (frames_file.h: the base registration and the
// markers) for ROS 2's tf2, in the two forms ROS takes static transforms:
//
//   a static_transform_publisher script (sh), one publisher per transform:
//     #!/bin/sh
//     ros2 run tf2_ros static_transform_publisher --x 0.4 --y 0 --z 0.1
//       --qx 0 --qy 0 --qz 0.7071067811865476 --qw 0.7071067811865476
//       --frame-id device --child-frame-id base_link &     (one line)
//     ...
//     wait
//
//   a tf2_msgs/msg/TFMessage in YAML (what `ros2 topic echo /tf_static`
//   prints; `ros2 topic pub --once --qos-durability transient_local
//   /tf_static tf2_msgs/msg/TFMessage "$(cat FILE)"` publishes it):
//     transforms:
//       - header:
//           stamp: {sec: 0, nanosec: 0}
//           frame_id: "device"
//         child_frame_id: "base_link"
//         transform:
//           translation: {x: 0.4, y: 0.0, z: 0.1}
//           rotation: {x: 0.0, y: 0.0, z: 0.7071067811865476, w: ...}
//
// The transforms: device frame -> the robot's base link (the base
// registration, when the base is a 6-DOF frame; another base is part of
// the robot's geometry and its URDF), and tip link -> each marker (named
// after the marker: its measured point and target orientation in the tip
// frame). The tip link's own pose comes from the robot's URDF
// (robot_state_publisher). Translations in metres; rotations as the unit
// quaternion of the model's rotation matrix (Eigen's conversion, w >= 0),
// never through roll-pitch-yaw. Numbers are written in the shortest form
// that reads back to the same double (in the YAML always with a '.', so
// that YAML 1.1 readers such as PyYAML take them as floats).

#ifndef ACTIVECAL_IO_ROS_FRAMES_H_
#define ACTIVECAL_IO_ROS_FRAMES_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

// One static transform: the child frame's pose in the parent frame.
struct RosTransform {
  std::string frame_id;        // the parent frame
  std::string child_frame_id;  // the child frame
  // The child's origin in the parent frame (m).
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  // The child's axes in the parent frame: a point x of the child frame is
  // rotation * x + translation in the parent frame. Unit, w >= 0.
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();

  // The 4 x 4 homogeneous transform.
  Eigen::Matrix4d Matrix() const;
};

// The transform of rotation matrix R (orthonormal) and translation t:
// R's quaternion, normalised, with w >= 0.
RosTransform RosTransformFromMatrix(const std::string& frame_id,
                                    const std::string& child_frame_id,
                                    const Eigen::Matrix3d& R,
                                    const Eigen::Vector3d& t);

struct RosFramesOptions {
  // The measuring device's frame (the parent of the robot's base).
  std::string device_frame = "device";
  // The robot's base link and tip link: for a URDF robot, the ends of the
  // calibrated chain (base_link, tip_link); for a URDF written by
  // UrdfFromModel, "base_link" and "tip".
  std::string base_frame = "base_link";
  std::string tip_frame = "tip";
};

// The transforms of `model` at `values` (full vector): the base when it is
// a 6-DOF frame (convention kFrame), then every marker. False with a
// message when a frame name is not a valid tf2 frame id (letters, digits,
// '_', '-', '.', '/', not starting with '/') or the names make a frame the
// child of two parents or of itself (a marker named after the device, base
// or tip frame, two markers of one name).
bool MetrologyRosTransforms(const RobotModel& model,
                            const Eigen::VectorXd& values,
                            const RosFramesOptions& options,
                            std::vector<RosTransform>* transforms,
                            std::string* error);

// The sh script of one `ros2 run tf2_ros static_transform_publisher` per
// transform (in the background; the script waits for them). `comment`:
// lines written as "# " comments at the top.
std::string StaticTransformPublisherScript(
    const std::vector<RosTransform>& transforms,
    const std::string& comment = "");

// The tf2_msgs/msg/TFMessage YAML of the transforms (stamps 0).
std::string Tf2StaticTransformsYaml(const std::vector<RosTransform>& transforms,
                                    const std::string& comment = "");

// Reads static_transform_publisher command lines back: one per line, each
// `ros2 run tf2_ros static_transform_publisher` or `rosrun tf2_ros
// static_transform_publisher` followed by the ROS 2 flags (--x --y --z, then
// --qx --qy --qz --qw or --roll --pitch --yaw (R = Rz(yaw) Ry(pitch)
// Rx(roll)), --frame-id, --child-frame-id; translation and rotation default
// to zero and identity) or by the positional form "x y z qx qy qz qw frame
// child" / "x y z yaw pitch roll frame child"; an ending '&' or '\' line
// continuation allowed. Blank lines, '#' comments and `wait` are skipped.
// A quaternion is normalised when its squared norm is within 0.01 of 1 (as
// tf2 accepts it), refused otherwise. On failure: "<source>:<line>: <what>".
bool ParseStaticTransformPublisherScript(const std::string& text,
                                         const std::string& source,
                                         std::vector<RosTransform>* transforms,
                                         std::string* error);

// Reads a TFMessage YAML back (the form Tf2StaticTransformsYaml writes, any
// YAML layout; header.stamp is optional and ignored; the quaternion as
// above). On failure: "<source>:<line>:<column>: <field>: <what>".
bool ParseTf2StaticTransformsYaml(const std::string& text,
                                  const std::string& source,
                                  std::vector<RosTransform>* transforms,
                                  std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_ROS_FRAMES_H_
