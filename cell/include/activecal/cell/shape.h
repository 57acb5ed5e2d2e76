// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Collision shapes of the cell: the robot's links and the obstacles, as
// FCL (the Flexible Collision Library) checks them.
//
// Every shape has its own frame, placed by `pose` in its parent frame (a
// robot link's frame, or the robot's base frame for an obstacle):
//
//   box       size_m: the full edge lengths along the shape's x, y, z,
//             centred on its origin
//   cylinder  radius_m, length_m: the axis is the shape's z, centred
//   capsule   radius_m, length_m: the segment from (0, 0, -length/2) to
//             (0, 0, length/2) swept by a ball of radius_m
//   sphere    radius_m, centred
//   mesh      triangles over `vertices` (m, already scaled, in the shape's
//             frame), read from an STL, OBJ or DAE file with assimp
//
// These are the URDF's conventions for box, cylinder and sphere. Units:
// metres.

#ifndef ACTIVECAL_CELL_SHAPE_H_
#define ACTIVECAL_CELL_SHAPE_H_

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

enum class ShapeType { kBox, kCylinder, kCapsule, kSphere, kMesh };

// "box", "cylinder", "capsule", "sphere", "mesh".
const char* ShapeTypeName(ShapeType type);

struct CollisionShape {
  ShapeType type = ShapeType::kBox;
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();  // box
  double radius_m = 0.0;  // cylinder, capsule, sphere
  double length_m = 0.0;  // cylinder, capsule
  // Mesh only.
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::string mesh_file;  // where it was read from, for messages
  // The shape's frame in its parent frame.
  FixedTransform pose;

  // The centre (in the shape's frame) and radius of a ball holding the
  // whole shape: the cheap test before an exact distance.
  void BoundingBall(Eigen::Vector3d* centre, double* radius) const;
};

// True when `point` (in the shape's own frame, m) lies inside the shape
// grown by `grow_m` (strictly: with grow_m = 0 a point on the surface is
// outside). A mesh: by the parity of the crossings of a ray (a closed
// mesh; grow_m is not applied).
bool PointInShape(const CollisionShape& shape, const Eigen::Vector3d& point,
                  double grow_m = 0.0);

// A capsule from point `from` to point `to` (m, in the parent frame) of
// radius `radius_m`; a zero-length one is a ball.
CollisionShape CapsuleBetween(const Eigen::Vector3d& from,
                              const Eigen::Vector3d& to, double radius_m);

// Reads a triangle mesh (STL, OBJ, DAE: anything assimp reads) into
// shape->vertices and shape->triangles, every vertex multiplied by `scale`
// per axis. The nodes' transforms of the file are applied (a DAE's unit,
// e.g. millimetres, is honoured); a DAE's up axis is not (as ROS reads
// meshes: the file's z stays z). False with "<path>: <assimp's reason>"
// when the file cannot be read or holds no triangles.
bool LoadMeshShape(const std::string& path, const Eigen::Vector3d& scale,
                   CollisionShape* shape, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CELL_SHAPE_H_
