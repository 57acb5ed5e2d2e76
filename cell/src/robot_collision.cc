// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/robot_collision.h"

#include <urdf_parser/urdf_parser.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "cell_internal.h"
#include "yaml_reader.h"

namespace activecal {
namespace {

using internal::Compose;

bool IsFile(const std::string& path) {
  std::ifstream in(path);
  return static_cast<bool>(in);
}

FixedTransform FromPose(const urdf::Pose& pose) {
  FixedTransform t;
  const Eigen::Quaterniond q(pose.rotation.w, pose.rotation.x, pose.rotation.y,
                             pose.rotation.z);
  t.rotation = q.normalized().toRotationMatrix();
  t.translation << pose.position.x, pose.position.y, pose.position.z;
  return t;
}

// A mesh file name of a URDF as a path on this machine.
bool ResolveMeshPath(const std::string& name, const std::string& directory,
                     std::string* path, std::string* error) {
  const std::string file_scheme = "file://";
  const std::string package_scheme = "package://";
  if (name.rfind(file_scheme, 0) == 0) {
    *path = name.substr(file_scheme.size());
    return true;
  }
  if (name.rfind(package_scheme, 0) == 0) {
    const std::string rest = name.substr(package_scheme.size());
    const char* env = std::getenv("ROS_PACKAGE_PATH");
    std::string roots = env ? env : "";
    std::stringstream split(roots);
    std::string root;
    while (std::getline(split, root, ':')) {
      if (root.empty()) continue;
      const std::string candidate = root + "/" + rest;
      if (IsFile(candidate)) {
        *path = candidate;
        return true;
      }
    }
    if (error) {
      *error = "mesh '" + name + "': not found in ROS_PACKAGE_PATH" +
               (roots.empty() ? " (not set)" : " (" + roots + ")");
    }
    return false;
  }
  *path = name.empty() || name[0] == '/' || directory.empty()
              ? name
              : directory + "/" + name;
  return true;
}

bool CollisionShapes(const urdf::Link& link, const std::string& source,
                     const std::string& directory,
                     std::vector<CollisionShape>* shapes, std::string* error) {
  auto fail = [&](const std::string& what) {
    if (error) *error = source + ": link '" + link.name + "': " + what;
    return false;
  };
  for (const urdf::CollisionSharedPtr& c : link.collision_array) {
    if (!c || !c->geometry) continue;
    CollisionShape s;
    s.pose = FromPose(c->origin);
    switch (c->geometry->type) {
      case urdf::Geometry::BOX: {
        const auto& box = static_cast<const urdf::Box&>(*c->geometry);
        s.type = ShapeType::kBox;
        s.size_m << box.dim.x, box.dim.y, box.dim.z;
        if (!(s.size_m.minCoeff() > 0)) {
          return fail("a collision box needs three sizes > 0");
        }
        break;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& cyl = static_cast<const urdf::Cylinder&>(*c->geometry);
        s.type = ShapeType::kCylinder;
        s.radius_m = cyl.radius;
        s.length_m = cyl.length;
        if (!(s.radius_m > 0 && s.length_m > 0)) {
          return fail("a collision cylinder needs radius and length > 0");
        }
        break;
      }
      case urdf::Geometry::SPHERE: {
        const auto& sph = static_cast<const urdf::Sphere&>(*c->geometry);
        s.type = ShapeType::kSphere;
        s.radius_m = sph.radius;
        if (!(s.radius_m > 0))
          return fail("a collision sphere needs radius > 0");
        break;
      }
      case urdf::Geometry::MESH: {
        const auto& mesh = static_cast<const urdf::Mesh&>(*c->geometry);
        std::string path, why;
        if (!ResolveMeshPath(mesh.filename, directory, &path, &why)) {
          return fail(why);
        }
        const Eigen::Vector3d scale(mesh.scale.x, mesh.scale.y, mesh.scale.z);
        const FixedTransform pose = s.pose;
        if (!LoadMeshShape(path, scale, &s, &why)) return fail(why);
        s.pose = pose;
        break;
      }
      default:
        return fail("a collision geometry of unknown type");
    }
    shapes->push_back(std::move(s));
  }
  return true;
}

bool Moving(const urdf::Joint& j) {
  return j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS ||
         j.type == urdf::Joint::PRISMATIC;
}

}  // namespace

int RobotCollisionModel::num_shapes() const {
  int n = 0;
  for (const CollisionBody& b : bodies) n += static_cast<int>(b.shapes.size());
  return n;
}

int RobotCollisionModel::BodyIndex(const std::string& name) const {
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

bool ParseUrdfCollision(const std::string& xml, const std::string& source,
                        const std::string& directory,
                        const UrdfChainOptions& chain, const RobotModel& model,
                        RobotCollisionModel* robot, std::string* error) {
  *robot = RobotCollisionModel();
  auto fail = [&](const std::string& what) {
    if (error) *error = source + ": " + what;
    return false;
  };
  urdf::ModelInterfaceSharedPtr urdf_model;
  try {
    urdf_model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    return fail(std::string("not a valid URDF: ") + e.what());
  }
  if (!urdf_model || !urdf_model->getRoot()) return fail("not a valid URDF");
  const std::string base_name =
      chain.base_link.empty() ? urdf_model->getRoot()->name : chain.base_link;
  urdf::LinkConstSharedPtr base = urdf_model->getLink(base_name);
  if (!base) return fail("no link named '" + base_name + "'");
  // The tip: as the URDF reader chooses it.
  std::string tip_name = chain.tip_link;
  if (tip_name.empty()) {
    urdf::LinkConstSharedPtr link = base;
    while (link->child_links.size() == 1) link = link->child_links[0];
    if (!link->child_links.empty()) {
      return fail("the tree below '" + base_name +
                  "' has several leaves: name the tip link");
    }
    tip_name = link->name;
  }
  // The chain's links, base to tip, and the frame of each.
  std::vector<urdf::LinkConstSharedPtr> path;
  for (urdf::LinkConstSharedPtr link = urdf_model->getLink(tip_name);;) {
    if (!link) return fail("no link named '" + tip_name + "'");
    path.push_back(link);
    if (link->name == base_name) break;
    if (!link->parent_joint) {
      return fail("link '" + tip_name + "' is not below '" + base_name + "'");
    }
    link = urdf_model->getLink(link->parent_joint->parent_link_name);
  }
  std::reverse(path.begin(), path.end());
  // Each link's model frame and its transform in that frame.
  std::map<std::string, std::pair<int, FixedTransform>> placed;
  placed[base_name] = {0, FixedTransform()};
  int frame = 0;
  FixedTransform in_frame;
  robot->velocity_limits.assign(model.num_joints(), 0.0);
  for (size_t k = 1; k < path.size(); ++k) {
    const urdf::Joint& j = *path[k]->parent_joint;
    if (Moving(j)) {
      if (frame >= model.num_joints() || model.links[frame].name != j.name) {
        return fail("joint '" + j.name +
                    "' does not match the robot model's chain");
      }
      if (j.limits && j.limits->velocity > 0) {
        robot->velocity_limits[frame] = j.limits->velocity;
      }
      ++frame;
      in_frame = FixedTransform();
    } else {
      in_frame =
          Compose(in_frame, FromPose(j.parent_to_joint_origin_transform));
    }
    placed[path[k]->name] = {frame, in_frame};
  }
  if (frame != model.num_joints()) {
    return fail("the chain's moving joints do not match the robot model's");
  }
  // Every other link below base_link hangs from its nearest placed
  // ancestor; joints off the chain at zero.
  std::vector<urdf::LinkConstSharedPtr> order = {base};
  for (size_t i = 0; i < order.size(); ++i) {
    const urdf::LinkConstSharedPtr link = order[i];
    for (const urdf::LinkSharedPtr& child : link->child_links) {
      if (!placed.count(child->name)) {
        const auto& parent = placed.at(link->name);
        placed[child->name] = {
            parent.first,
            Compose(
                parent.second,
                FromPose(
                    child->parent_joint->parent_to_joint_origin_transform))};
      }
      order.push_back(child);
    }
  }
  for (const urdf::LinkConstSharedPtr& link : order) {
    CollisionBody body;
    body.name = link->name;
    body.frame = placed.at(link->name).first;
    body.in_frame = placed.at(link->name).second;
    if (!CollisionShapes(*link, source, directory, &body.shapes, error)) {
      return false;
    }
    robot->bodies.push_back(std::move(body));
  }
  return true;
}

bool LoadUrdfCollision(const std::string& path, const UrdfChainOptions& chain,
                       const RobotModel& model, RobotCollisionModel* robot,
                       std::string* error) {
  std::string xml;
  if (!ReadTextFile(path, &xml, error)) return false;
  return ParseUrdfCollision(xml, path, internal::DirectoryOf(path), chain,
                            model, robot, error);
}

namespace {

class CollisionSectionParser : public internal::YamlReader {
 public:
  using YamlReader::YamlReader;

  bool Parse(const std::string& text, const RobotModel& model,
             RobotCollisionModel* robot) {
    YAML::Node root;
    if (!LoadMap(text, "of robot fields at the top", &root)) return false;
    robot->bodies.clear();
    robot->velocity_limits.assign(model.num_joints(), 0.0);
    // One body per frame, named after it.
    robot->bodies.resize(model.num_joints() + 1);
    robot->bodies[0].name = "base";
    for (int j = 0; j < model.num_joints(); ++j) {
      robot->bodies[j + 1].name = model.links[j].name;
      robot->bodies[j + 1].frame = j + 1;
    }
    const YAML::Node list = root["collision"];
    if (!list) return true;
    if (!list.IsSequence()) {
      return Fail(list.Mark(), "collision", "expected a list of capsules");
    }
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node c = list[i];
      const std::string field = "collision[" + std::to_string(i) + "]";
      if (!c.IsMap()) {
        return Fail(c.Mark(), field,
                    "expected {link: .., from_m: [..], to_m: [..], "
                    "radius_m: ..}");
      }
      if (!CheckKeys(c, field, {"link", "from_m", "to_m", "radius_m"})) {
        return false;
      }
      std::string link;
      if (!String(c, "link", field + ".link", &link)) return false;
      int frame = -1;
      if (link == "base" || link == model.base.name) frame = 0;
      for (int j = 0; j < model.num_joints() && frame < 0; ++j) {
        if (model.links[j].name == link) frame = j + 1;
      }
      if (frame < 0) {
        std::string names = "base";
        for (const Link& l : model.links) names += ", " + l.name;
        return Fail(
            c["link"].Mark(), field + ".link",
            "no link named '" + link + "' (expected one of: " + names + ")");
      }
      Eigen::Vector3d from, to;
      for (const char* key : {"from_m", "to_m"}) {
        const YAML::Node v = c[key];
        if (!v) return Fail(c.Mark(), field + "." + key, "missing");
        if (!Vector(v, field + "." + key, key[0] == 'f' ? &from : &to)) {
          return false;
        }
      }
      const YAML::Node r = c["radius_m"];
      if (!r) return Fail(c.Mark(), field + ".radius_m", "missing");
      double radius = 0;
      if (!Number(r, field + ".radius_m", &radius)) return false;
      if (!(radius > 0)) {
        return Fail(r.Mark(), field + ".radius_m", "must be > 0");
      }
      robot->bodies[frame].shapes.push_back(CapsuleBetween(from, to, radius));
    }
    return true;
  }
};

}  // namespace

bool ParseRobotFileCollision(const std::string& text, const std::string& source,
                             const RobotModel& model,
                             RobotCollisionModel* robot, std::string* error) {
  *robot = RobotCollisionModel();
  CollisionSectionParser parser(source);
  if (!parser.Parse(text, model, robot)) {
    if (error) *error = parser.error();
    return false;
  }
  return true;
}

bool LoadRobotCollision(const std::string& path, const UrdfChainOptions& chain,
                        const RobotModel& model, RobotCollisionModel* robot,
                        std::string* error) {
  if (IsUrdfPath(path)) {
    return LoadUrdfCollision(path, chain, model, robot, error);
  }
  std::string text;
  if (!ReadTextFile(path, &text, error)) return false;
  return ParseRobotFileCollision(text, path, model, robot, error);
}

}  // namespace activecal
