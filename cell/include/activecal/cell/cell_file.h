// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The cell a robot is calibrated in (YAML, docs/formats.md "Cell file"):
// the joint margins planned poses keep, the clearance to obstacles and
// between links, the obstacles, the measuring device and the targets it
// measures on the robot. Everything is given in the robot's base frame
// (the frame the base block B leads to: a URDF's base_link, a DH robot's
// frame 0), in metres and radians unless a key says _deg.
//
//   joint_margin_deg: 3
//   clearance_m: 0.05
//   obstacles:
//     - {name: table, type: plane, normal: [0, 0, 1], offset_m: 0.0}
//     - {name: wall, type: box, size_m: [0.1, 4, 3], xyz_m: [-0.75, 0, 1]}
//   device: {type: laser_tracker, xyz_m: [2.2, 0.4, 0.9], range_m: [1, 6]}
//   targets:
//     - {xyz_m: [0, 0, 0.06], normal: [0, 0, 1], acceptance_deg: 30}
//
//   Cell cell;
//   std::string error;
//   if (!LoadCellFile("cell.yaml", &cell, &error)) {
//     std::cerr << error << "\n";  // "cell.yaml:7:40: obstacles[1].size_m:
//   }                              //  expected [x, y, z]"
//
// Meshes are read when the file is (paths relative to the cell file).

#ifndef ACTIVECAL_CELL_CELL_FILE_H_
#define ACTIVECAL_CELL_CELL_FILE_H_

#include <Eigen/Core>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "activecal/cell/shape.h"

namespace activecal {

// An obstacle: a half-space (plane) or a solid shape, fixed in the base
// frame.
struct Obstacle {
  std::string name;
  bool plane = false;
  // plane: solid where normal . x < offset_m (normal: unit).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset_m = 0.0;
  // Otherwise: the shape, shape.pose its placement in the base frame.
  CollisionShape shape;
};

enum class DeviceType { kLaserTracker, kMocap, kCamera };

// "laser_tracker", "mocap", "camera".
const char* DeviceTypeName(DeviceType type);

// A camera (of a mocap system, or the camera device). Its frame: z the
// optical axis (forward), x right, y down in the image (OpenCV's).
struct CellCamera {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  // A circular field of view: half its full angle (rad); used when there
  // are no intrinsics.
  double half_fov_rad = M_PI / 2;
  // Pinhole intrinsics (pixels): a point is seen when it projects inside
  // [0, width] x [0, height] in front of the camera.
  bool has_intrinsics = false;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double width = 0, height = 0;
  double min_range_m = 0.0;
  double max_range_m = std::numeric_limits<double>::infinity();
};

// The most cameras a mocap device may have (the checks keep a bit per
// camera).
inline constexpr int kMaxCellCameras = 64;

struct CellDevice {
  DeviceType type = DeviceType::kLaserTracker;
  // laser_tracker: the tracker head (m) and its range.
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double min_range_m = 0.0;
  double max_range_m = std::numeric_limits<double>::infinity();
  // mocap: the cameras (at most kMaxCellCameras), of which at least
  // min_cameras must see a target; camera: one.
  std::vector<CellCamera> cameras;
  int min_cameras = 1;
  // camera: the largest angle between a target's normal and the direction
  // to the camera (rad), on top of the target's own acceptance.
  double max_viewing_angle_rad = M_PI / 2;
};

// A reflector or marker on the end effector, in the tip link's frame.
struct CellTarget {
  std::string name;  // "target1", ... unless given
  Eigen::Vector3d xyz_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit
  // The largest angle between the normal and the direction to the device
  // at which the target is still measured, in (0, pi/2].
  double acceptance_rad = M_PI / 2;
};

struct Cell {
  std::string source;  // the file, for messages
  // Planned poses stay this far inside every joint range: revolute joints
  // by joint_margin_rad, prismatic by joint_margin_m, unless a joint (by
  // name) has its own value in joint_margin_override (rad or m).
  double joint_margin_rad = 0.0;
  double joint_margin_m = 0.0;
  std::map<std::string, double> joint_margin_override;
  // Where each override and each skip pair was given ("<file>:<line>:<col>:
  // <field>"), for messages about names the robot does not have.
  std::map<std::string, std::string> joint_margin_override_where;
  // Where joint_margin_deg and joint_margin_m were given (empty: not).
  std::string joint_margin_deg_where, joint_margin_m_where;
  // The least distance between the robot and an obstacle, and between two
  // links that are not adjacent (self_clearance_m: that of clearance_m
  // unless set).
  double clearance_m = 0.0;
  double self_clearance_m = 0.0;
  std::vector<Obstacle> obstacles;
  bool has_device = false;
  CellDevice device;
  // Where the file gives the device ("<file>:<line>:<col>"; empty for a
  // cell made in code), for messages about it (DeviceEyes).
  std::string device_where;
  // A point the device sees from (the tracker, or one camera).
  struct Eye {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    std::string field;  // "device.xyz_m", "device.cameras[1].xyz_m"
    std::string where;  // "<file>:<line>:<col>: <field>", or <field>
  };
  std::vector<CellTarget> targets;
  // Pairs not checked against each other: two robot links (by link name),
  // or a robot link and an obstacle (by the obstacle's name).
  std::vector<std::pair<std::string, std::string>> skip_pairs;
  std::vector<std::string> skip_pair_where;  // empty for the SRDF's pairs
  // An SRDF file whose <disable_collisions> pairs are skipped too (read
  // when the cell file is; its pairs are added to skip_pairs).
  std::string srdf_file;
  // The stretch of each line of sight next to its target that is not
  // checked (m): the target's own mount.
  double line_of_sight_margin_m = 0.02;
};

// Where `cell`'s device sees from: the tracker, or each camera (none
// without a device), for the checks that it lies outside every obstacle
// (the reader) and outside the robot's fixed links (SetUpCell). Computed
// from cell.device, so a cell made in code is checked as a read one is.
std::vector<Cell::Eye> DeviceEyes(const Cell& cell);

// Reads and checks a cell file: every field, the meshes, the SRDF file, a
// device (or camera) outside every obstacle, non-zero normals, acceptance
// angles in (0, 90] deg. False with "<path>:<line>:<column>: <field>:
// <what>" (a mesh: "<field>: <mesh path>: <assimp's reason>").
bool LoadCellFile(const std::string& path, Cell* cell, std::string* error);
// The same from text; relative mesh and SRDF paths are taken from
// `directory` (empty: the working directory).
bool ParseCellFile(const std::string& text, const std::string& source,
                   const std::string& directory, Cell* cell,
                   std::string* error);

// The <disable_collisions link1=".." link2=".."/> pairs of an SRDF file.
bool ReadSrdfDisabledPairs(
    const std::string& path,
    std::vector<std::pair<std::string, std::string>>* pairs,
    std::string* error);

// True when `point` (base frame) lies inside the obstacle (a plane's solid
// side, a shape's interior; a mesh: by the parity of the crossings of a
// ray, for a closed mesh).
bool PointInsideObstacle(const Obstacle& obstacle,
                         const Eigen::Vector3d& point);

}  // namespace activecal

#endif  // ACTIVECAL_CELL_CELL_FILE_H_
