// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/shape.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>

#include "activecal/core/enum_name_list.h"

namespace activecal {

constexpr const char* kShapeTypeNames[] = {"box", "cylinder", "capsule",
                                           "sphere", "mesh"};

const char* ShapeTypeName(ShapeType type) {
  return EnumToString(kShapeTypeNames, type);
}

void CollisionShape::BoundingBall(Eigen::Vector3d* centre,
                                  double* radius) const {
  centre->setZero();
  switch (type) {
    case ShapeType::kBox:
      *radius = 0.5 * size_m.norm();
      return;
    case ShapeType::kCylinder:
      *radius = std::hypot(radius_m, 0.5 * length_m);
      return;
    case ShapeType::kCapsule:
      *radius = radius_m + 0.5 * length_m;
      return;
    case ShapeType::kSphere:
      *radius = radius_m;
      return;
    case ShapeType::kMesh: {
      if (vertices.empty()) {
        *radius = 0.0;
        return;
      }
      Eigen::Vector3d lo = vertices[0], hi = vertices[0];
      for (const Eigen::Vector3d& v : vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
      *centre = 0.5 * (lo + hi);
      double r = 0.0;
      for (const Eigen::Vector3d& v : vertices) {
        r = std::max(r, (v - *centre).norm());
      }
      *radius = r;
      return;
    }
  }
  *radius = 0.0;
}

namespace {

// Moller-Trumbore: does the ray o + s d (s > 0) cross the triangle?
bool RayCrossesTriangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                        const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-15) return false;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0 || u + v > 1) return false;
  return e2.dot(q) / det > 0;
}

}  // namespace

bool PointInShape(const CollisionShape& s, const Eigen::Vector3d& p,
                  double grow_m) {
  switch (s.type) {
    case ShapeType::kBox: {
      const Eigen::Vector3d excess = p.cwiseAbs() - 0.5 * s.size_m;
      if (excess.maxCoeff() < 0) return true;
      return grow_m > 0 && excess.cwiseMax(0.0).norm() < grow_m;
    }
    case ShapeType::kCylinder: {
      const double radial = p.head<2>().norm() - s.radius_m;
      const double axial = std::abs(p.z()) - 0.5 * s.length_m;
      if (radial < 0 && axial < 0) return true;
      return grow_m > 0 &&
             std::hypot(std::max(0.0, radial), std::max(0.0, axial)) < grow_m;
    }
    case ShapeType::kCapsule: {
      const double z = std::clamp(p.z(), -0.5 * s.length_m, 0.5 * s.length_m);
      return (p - Eigen::Vector3d(0, 0, z)).norm() < s.radius_m + grow_m;
    }
    case ShapeType::kSphere:
      return p.norm() < s.radius_m + grow_m;
    case ShapeType::kMesh: {
      // An odd number of crossings of a ray in a direction unlikely to
      // graze an edge.
      const Eigen::Vector3d d = Eigen::Vector3d(0.5773, 0.5774, 0.5775);
      int crossings = 0;
      for (const auto& t : s.triangles) {
        crossings += RayCrossesTriangle(p, d, s.vertices[t[0]],
                                        s.vertices[t[1]], s.vertices[t[2]]);
      }
      return crossings % 2 == 1;
    }
  }
  return false;
}

CollisionShape CapsuleBetween(const Eigen::Vector3d& from,
                              const Eigen::Vector3d& to, double radius_m) {
  CollisionShape s;
  s.radius_m = radius_m;
  const Eigen::Vector3d d = to - from;
  s.length_m = d.norm();
  s.type = s.length_m > 0 ? ShapeType::kCapsule : ShapeType::kSphere;
  s.pose.translation = 0.5 * (from + to);
  if (s.length_m > 0) {
    // A rotation taking z to d / |d|: z' = d, x' any unit vector normal
    // to it.
    const Eigen::Vector3d z = d / s.length_m;
    const Eigen::Vector3d helper = std::abs(z.x()) < 0.9
                                       ? Eigen::Vector3d::UnitX()
                                       : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d x = helper.cross(z).normalized();
    s.pose.rotation.col(0) = x;
    s.pose.rotation.col(1) = z.cross(x);
    s.pose.rotation.col(2) = z;
  }
  return s;
}

namespace {

// Appends the triangles of `node` and its children, with the transforms
// from the root down.
void CollectTriangles(const aiScene* scene, const aiNode* node,
                      const aiMatrix4x4& parent, const Eigen::Vector3d& scale,
                      CollisionShape* shape) {
  const aiMatrix4x4 transform = parent * node->mTransformation;
  for (unsigned m = 0; m < node->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[m]];
    const int base = static_cast<int>(shape->vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D p = transform * mesh->mVertices[v];
      shape->vertices.emplace_back(scale.x() * p.x, scale.y() * p.y,
                                   scale.z() * p.z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      shape->triangles.push_back({base + static_cast<int>(face.mIndices[0]),
                                  base + static_cast<int>(face.mIndices[1]),
                                  base + static_cast<int>(face.mIndices[2])});
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) {
    CollectTriangles(scene, node->mChildren[c], transform, scale, shape);
  }
}

}  // namespace

bool LoadMeshShape(const std::string& path, const Eigen::Vector3d& scale,
                   CollisionShape* shape, std::string* error) {
  Assimp::Importer importer;
  // ROS keeps a DAE's z up; assimp would turn a Z_UP file to y up.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                aiProcess_SortByPType);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    if (error) *error = path + ": " + importer.GetErrorString();
    return false;
  }
  shape->type = ShapeType::kMesh;
  shape->mesh_file = path;
  shape->vertices.clear();
  shape->triangles.clear();
  CollectTriangles(scene, scene->mRootNode, aiMatrix4x4(), scale, shape);
  if (shape->triangles.empty()) {
    if (error) *error = path + ": the file holds no triangles";
    return false;
  }
  for (const Eigen::Vector3d& v : shape->vertices) {
    if (!v.allFinite()) {
      if (error) *error = path + ": a vertex is not finite";
      return false;
    }
  }
  return true;
}

}  // namespace activecal
