// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/cell_file.h"

#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/kinematics.h"
#include "activecal/io/csv_files.h"
#include "cell_internal.h"
#include "number_text.h"
#include "yaml_reader.h"

namespace activecal {
namespace {

using internal::kDegree;

std::string JoinPath(const std::string& directory, const std::string& path) {
  if (path.empty() || path[0] == '/' || directory.empty()) return path;
  return directory + "/" + path;
}

class CellParser : public internal::YamlReader {
 public:
  CellParser(std::string source, std::string directory)
      : YamlReader(source),
        source_(std::move(source)),
        directory_(std::move(directory)) {}

  bool Parse(const std::string& text, Cell* cell) {
    YAML::Node root;
    if (!LoadMap(text, "of cell fields", &root)) return false;
    if (!CheckKeys(root, "",
                   {"joint_margin_deg", "joint_margin_m",
                    "joint_margin_override_deg", "joint_margin_override_m",
                    "clearance_m", "self_clearance_m", "line_of_sight_margin_m",
                    "obstacles", "device", "targets", "skip_pairs", "srdf"})) {
      return false;
    }
    double deg = 0.0;
    if (!OptionalNonNegative(root, "joint_margin_deg", &deg)) return false;
    cell->joint_margin_rad = deg * kDegree;
    for (const auto& [key, where] :
         {std::make_pair("joint_margin_deg", &cell->joint_margin_deg_where),
          std::make_pair("joint_margin_m", &cell->joint_margin_m_where)}) {
      if (const YAML::Node node = root[key]) *where = Where(node.Mark(), key);
    }
    if (!OptionalNonNegative(root, "joint_margin_m", &cell->joint_margin_m) ||
        !Overrides(root, "joint_margin_override_deg", kDegree, cell) ||
        !Overrides(root, "joint_margin_override_m", 1.0, cell) ||
        !OptionalNonNegative(root, "clearance_m", &cell->clearance_m)) {
      return false;
    }
    cell->self_clearance_m = cell->clearance_m;
    if (!OptionalNonNegative(root, "self_clearance_m",
                             &cell->self_clearance_m) ||
        !OptionalNonNegative(root, "line_of_sight_margin_m",
                             &cell->line_of_sight_margin_m)) {
      return false;
    }
    if (const YAML::Node obstacles = root["obstacles"]) {
      if (!obstacles.IsSequence()) {
        return Fail(obstacles.Mark(), "obstacles", "expected a list");
      }
      // Name -> the line (1-based) of its first use.
      std::map<std::string, int> names;
      for (size_t i = 0; i < obstacles.size(); ++i) {
        const std::string field = "obstacles[" + std::to_string(i) + "]";
        Obstacle o;
        if (!ParseObstacle(obstacles[i], field, &o)) return false;
        const YAML::Mark mark = obstacles[i]["name"].Mark();
        const auto [it, fresh] = names.emplace(o.name, mark.line + 1);
        if (!fresh) {
          return Fail(mark, field + ".name",
                      "duplicate name '" + o.name + "' (also at line " +
                          std::to_string(it->second) + ")");
        }
        cell->obstacles.push_back(std::move(o));
      }
    }
    if (const YAML::Node device = root["device"]) {
      cell->has_device = true;
      if (!ParseDevice(device, &cell->device)) return false;
    }
    if (const YAML::Node targets = root["targets"]) {
      if (!targets.IsSequence() || targets.size() == 0) {
        return Fail(targets.Mark(), "targets",
                    "expected a non-empty list of targets");
      }
      if (targets.size() > 32) {
        return Fail(
            targets.Mark(), "targets",
            "at most 32 targets, got " + std::to_string(targets.size()));
      }
      std::map<std::string, int> names;
      for (size_t i = 0; i < targets.size(); ++i) {
        CellTarget t;
        t.name = "target" + std::to_string(i + 1);
        const std::string field = "targets[" + std::to_string(i) + "]";
        if (!ParseTarget(targets[i], field, &t)) return false;
        // Before the targets become markers (whose reader would name the
        // markers' list, not this file's line).
        const YAML::Mark mark =
            targets[i]["name"] ? targets[i]["name"].Mark() : targets[i].Mark();
        const auto [it, fresh] = names.emplace(t.name, mark.line + 1);
        if (!fresh) {
          return Fail(mark, field + ".name",
                      "duplicate name '" + t.name + "' (also at line " +
                          std::to_string(it->second) + ")");
        }
        cell->targets.push_back(t);
      }
    }
    if (cell->has_device && cell->targets.empty()) {
      return Fail(root["device"].Mark(), "targets",
                  "missing: a device needs the targets it measures");
    }
    if (!cell->has_device && !cell->targets.empty()) {
      return Fail(root["targets"].Mark(), "device",
                  "missing: targets need the device that measures them");
    }
    if (const YAML::Node pairs = root["skip_pairs"]) {
      if (!pairs.IsSequence()) {
        return Fail(pairs.Mark(), "skip_pairs",
                    "expected a list of [link, link] pairs");
      }
      for (size_t i = 0; i < pairs.size(); ++i) {
        const YAML::Node p = pairs[i];
        const std::string field = "skip_pairs[" + std::to_string(i) + "]";
        if (!p.IsSequence() || p.size() != 2 || !p[0].IsScalar() ||
            !p[1].IsScalar()) {
          return Fail(p.Mark(), field, "expected [link, link]");
        }
        cell->skip_pairs.emplace_back(p[0].Scalar(), p[1].Scalar());
        cell->skip_pair_where.push_back(Where(p.Mark(), field));
      }
    }
    if (const YAML::Node srdf = root["srdf"]) {
      if (!srdf.IsScalar()) return Fail(srdf.Mark(), "srdf", "expected a path");
      cell->srdf_file = JoinPath(directory_, srdf.Scalar());
      std::string why;
      if (!ReadSrdfDisabledPairs(cell->srdf_file, &cell->skip_pairs, &why)) {
        return Fail(srdf.Mark(), "srdf", why);
      }
      cell->skip_pair_where.resize(cell->skip_pairs.size());
    }
    // The device must see from outside every obstacle.
    if (cell->has_device) {
      const YAML::Mark mark = root["device"].Mark();
      cell->device_where = source_ + ":" + std::to_string(mark.line + 1) + ":" +
                           std::to_string(mark.column + 1);
      for (const Cell::Eye& e : DeviceEyes(*cell)) {
        for (const Obstacle& o : cell->obstacles) {
          if (PointInsideObstacle(o, e.position)) {
            return Fail(mark, e.field,
                        "the device lies inside obstacle '" + o.name + "'");
          }
        }
      }
    }
    return true;
  }

 private:
  bool OptionalNonNegative(const YAML::Node& map, const char* key,
                           double* out) {
    const YAML::Node node = map[key];
    if (!node) return true;
    if (!Number(node, key, out)) return false;
    if (*out < 0) {
      return Fail(node.Mark(), key,
                  "must be >= 0, got " + internal::ShortestText(*out));
    }
    return true;
  }

  bool Positive(const YAML::Node& map, const char* key,
                const std::string& field, double* out) {
    const YAML::Node node = map[key];
    const std::string f = field + "." + key;
    if (!node) return Fail(map.Mark(), f, "missing");
    if (!Number(node, f, out)) return false;
    if (!(*out > 0)) {
      return Fail(node.Mark(), f,
                  "must be > 0, got " + internal::ShortestText(*out));
    }
    return true;
  }

  bool Overrides(const YAML::Node& root, const char* key, double scale,
                 Cell* cell) {
    const YAML::Node node = root[key];
    if (!node) return true;
    if (!node.IsMap()) {
      return Fail(node.Mark(), key, "expected {joint name: margin, ...}");
    }
    for (const auto& kv : node) {
      const std::string name = kv.first.Scalar();
      const std::string field = std::string(key) + "." + name;
      double value = 0.0;
      if (!Number(kv.second, field, &value)) return false;
      if (value < 0) {
        return Fail(kv.second.Mark(), field,
                    "must be >= 0, got " + internal::ShortestText(value));
      }
      if (!cell->joint_margin_override.emplace(name, value * scale).second) {
        return Fail(kv.first.Mark(), field, "given twice");
      }
      cell->joint_margin_override_where[name] = Where(kv.first.Mark(), field);
    }
    return true;
  }

  // A unit vector from a non-zero [x, y, z].
  bool Direction(const YAML::Node& map, const char* key,
                 const std::string& field, Eigen::Vector3d* out) {
    const YAML::Node node = map[key];
    const std::string f = field + "." + key;
    if (!node) return Fail(map.Mark(), f, "missing");
    if (!Vector(node, f, out)) return false;
    const double norm = out->norm();
    if (!(norm > 1e-12)) return Fail(node.Mark(), f, "a zero vector");
    *out /= norm;
    return true;
  }

  // False (failing at b) when `map` gives both of the alternative keys a
  // and b; prefix: the field's name before the keys ("" or "<field>.").
  bool NotBoth(const YAML::Node& map, const std::string& prefix, const char* a,
               const char* b) {
    if (!map[a] || !map[b]) return true;
    return Fail(map[b].Mark(), prefix + b,
                std::string("give ") + a + " or " + b + ", not both");
  }

  // rpy_rad or quaternion_xyzw (or neither: the identity).
  bool Orientation(const YAML::Node& map, const std::string& field,
                   Eigen::Matrix3d* rotation) {
    rotation->setIdentity();
    if (!NotBoth(map, field + ".", "rpy_rad", "quaternion_xyzw")) return false;
    const YAML::Node rpy = map["rpy_rad"];
    const YAML::Node quaternion = map["quaternion_xyzw"];
    if (rpy) {
      Eigen::Vector3d a;
      if (!Vector(rpy, field + ".rpy_rad", &a)) return false;
      *rotation = RpyRotation(a[0], a[1], a[2]);
    } else if (quaternion) {
      const std::string f = field + ".quaternion_xyzw";
      if (!quaternion.IsSequence() || quaternion.size() != 4) {
        return Fail(quaternion.Mark(), f, "expected [x, y, z, w]");
      }
      double q[4];
      for (int k = 0; k < 4; ++k) {
        if (!Number(quaternion[k], f + "[" + std::to_string(k) + "]", &q[k])) {
          return false;
        }
      }
      Eigen::Quaterniond qq(q[3], q[0], q[1], q[2]);
      if (!(qq.norm() > 1e-12)) return Fail(quaternion.Mark(), f, "zero");
      *rotation = qq.normalized().toRotationMatrix();
    }
    return true;
  }

  bool Placement(const YAML::Node& map, const std::string& field,
                 FixedTransform* pose) {
    pose->translation.setZero();
    if (const YAML::Node xyz = map["xyz_m"]) {
      if (!Vector(xyz, field + ".xyz_m", &pose->translation)) return false;
    }
    return Orientation(map, field, &pose->rotation);
  }

  bool ParseObstacle(const YAML::Node& node, const std::string& field,
                     Obstacle* o) {
    if (!node.IsMap()) {
      return Fail(node.Mark(), field, "expected {name: .., type: .., ...}");
    }
    if (!String(node, "name", field + ".name", &o->name)) return false;
    std::string type;
    if (!String(node, "type", field + ".type", &type)) return false;
    const std::set<std::string> placed = {"name", "type", "xyz_m", "rpy_rad",
                                          "quaternion_xyzw"};
    auto keys = [&](std::set<std::string> extra) {
      extra.insert(placed.begin(), placed.end());
      return CheckKeys(node, field, extra);
    };
    CollisionShape& s = o->shape;
    if (type == "plane") {
      o->plane = true;
      if (!CheckKeys(node, field, {"name", "type", "normal", "offset_m"}) ||
          !Direction(node, "normal", field, &o->normal)) {
        return false;
      }
      o->offset_m = 0.0;
      if (node["offset_m"] &&
          !Number(node["offset_m"], field + ".offset_m", &o->offset_m)) {
        return false;
      }
      return true;
    }
    if (type == "box") {
      s.type = ShapeType::kBox;
      if (!keys({"size_m"})) return false;
      const YAML::Node size = node["size_m"];
      if (!size) return Fail(node.Mark(), field + ".size_m", "missing");
      if (!Vector(size, field + ".size_m", &s.size_m)) return false;
      if (!(s.size_m.minCoeff() > 0)) {
        return Fail(size.Mark(), field + ".size_m", "every edge must be > 0");
      }
    } else if (type == "cylinder") {
      s.type = ShapeType::kCylinder;
      if (!keys({"radius_m", "length_m"}) ||
          !Positive(node, "radius_m", field, &s.radius_m) ||
          !Positive(node, "length_m", field, &s.length_m)) {
        return false;
      }
    } else if (type == "sphere") {
      s.type = ShapeType::kSphere;
      if (!keys({"radius_m"}) ||
          !Positive(node, "radius_m", field, &s.radius_m)) {
        return false;
      }
    } else if (type == "mesh") {
      if (!keys({"file", "scale"})) return false;
      std::string file;
      if (!String(node, "file", field + ".file", &file)) return false;
      Eigen::Vector3d scale = Eigen::Vector3d::Ones();
      if (const YAML::Node sc = node["scale"]) {
        if (sc.IsScalar()) {
          double k = 0;
          if (!Number(sc, field + ".scale", &k)) return false;
          scale.setConstant(k);
        } else if (!Vector(sc, field + ".scale", &scale)) {
          return false;
        }
        if (!(scale.cwiseAbs().minCoeff() > 0)) {
          return Fail(sc.Mark(), field + ".scale", "must not be zero");
        }
      }
      std::string why;
      if (!LoadMeshShape(JoinPath(directory_, file), scale, &s, &why)) {
        return Fail(node["file"].Mark(), field + ".file", why);
      }
    } else {
      return Fail(
          node["type"].Mark(), field + ".type",
          "expected plane, box, cylinder, sphere or mesh, got '" + type + "'");
    }
    return Placement(node, field, &s.pose);
  }

  bool Range(const YAML::Node& map, const std::string& field, double* lo,
             double* hi) {
    const YAML::Node node = map["range_m"];
    if (!node) return true;
    const std::string f = field.empty() ? "range_m" : field + ".range_m";
    if (!node.IsSequence() || node.size() != 2) {
      return Fail(node.Mark(), f, "expected [min, max]");
    }
    if (!Number(node[0], f + "[0]", lo) || !Number(node[1], f + "[1]", hi)) {
      return false;
    }
    if (*lo < 0 || !(*hi > *lo)) {
      return Fail(node.Mark(), f, "expected 0 <= min < max");
    }
    return true;
  }

  // The keys of one camera, at `node` (mocap: an entry of cameras; the
  // camera device: the device itself).
  bool ParseCamera(const YAML::Node& node, const std::string& field,
                   CellCamera* c) {
    const std::string prefix = field.empty() ? "" : field + ".";
    const YAML::Node xyz = node["xyz_m"];
    if (!xyz) return Fail(node.Mark(), prefix + "xyz_m", "missing");
    if (!Vector(xyz, prefix + "xyz_m", &c->position)) return false;
    if (const YAML::Node look = node["look_at_m"]) {
      if (node["rpy_rad"] || node["quaternion_xyzw"]) {
        return Fail(look.Mark(), prefix + "look_at_m",
                    "give look_at_m or an orientation, not both");
      }
      Eigen::Vector3d at, up = Eigen::Vector3d::UnitZ();
      if (!Vector(look, prefix + "look_at_m", &at)) return false;
      if (const YAML::Node u = node["up"]) {
        if (!Vector(u, prefix + "up", &up)) return false;
      }
      const Eigen::Vector3d z = at - c->position;
      if (!(z.norm() > 1e-9)) {
        return Fail(look.Mark(), prefix + "look_at_m",
                    "the camera looks at its own position");
      }
      const Eigen::Vector3d zn = z.normalized();
      const Eigen::Vector3d down = -(up - up.dot(zn) * zn);
      if (!(down.norm() > 1e-9)) {
        return Fail(look.Mark(), prefix + "up",
                    "parallel to the viewing direction");
      }
      c->rotation.col(2) = zn;
      c->rotation.col(1) = down.normalized();
      c->rotation.col(0) = c->rotation.col(1).cross(zn);
    } else {
      if (node["up"]) {
        return Fail(node["up"].Mark(), prefix + "up", "needs look_at_m");
      }
      if (!Orientation(node, field.empty() ? "device" : field, &c->rotation)) {
        return false;
      }
    }
    if (!NotBoth(node, prefix, "fov_deg", "intrinsics")) return false;
    const YAML::Node fov = node["fov_deg"];
    const YAML::Node intrinsics = node["intrinsics"];
    if (fov) {
      double f = 0;
      if (!Number(fov, prefix + "fov_deg", &f)) return false;
      if (!(f > 0 && f < 180)) {
        return Fail(fov.Mark(), prefix + "fov_deg",
                    "must be in (0, 180), got " + internal::ShortestText(f));
      }
      c->half_fov_rad = 0.5 * f * kDegree;
    } else if (intrinsics) {
      const std::string f = prefix + "intrinsics";
      if (!intrinsics.IsMap()) {
        return Fail(intrinsics.Mark(), f,
                    "expected {fx, fy, cx, cy, width, height}");
      }
      if (!CheckKeys(intrinsics, f,
                     {"fx", "fy", "cx", "cy", "width", "height"}) ||
          !Positive(intrinsics, "fx", f, &c->fx) ||
          !Positive(intrinsics, "fy", f, &c->fy) ||
          !Positive(intrinsics, "width", f, &c->width) ||
          !Positive(intrinsics, "height", f, &c->height)) {
        return false;
      }
      for (const char* key : {"cx", "cy"}) {
        const YAML::Node v = intrinsics[key];
        if (!v) return Fail(intrinsics.Mark(), f + "." + key, "missing");
        if (!Number(v, f + "." + key, key[1] == 'x' ? &c->cx : &c->cy)) {
          return false;
        }
      }
      c->has_intrinsics = true;
    } else {
      return Fail(node.Mark(), prefix + "fov_deg",
                  "missing (or intrinsics): the camera's field of view");
    }
    return Range(node, field, &c->min_range_m, &c->max_range_m);
  }

  bool ParseDevice(const YAML::Node& node, CellDevice* d) {
    if (!node.IsMap()) return Fail(node.Mark(), "device", "expected a mapping");
    std::string type;
    if (!String(node, "type", "device.type", &type)) return false;
    if (type == "laser_tracker") {
      d->type = DeviceType::kLaserTracker;
      if (!CheckKeys(node, "device", {"type", "xyz_m", "range_m"})) {
        return false;
      }
      const YAML::Node xyz = node["xyz_m"];
      if (!xyz) return Fail(node.Mark(), "device.xyz_m", "missing");
      if (!Vector(xyz, "device.xyz_m", &d->position)) return false;
      return Range(node, "device", &d->min_range_m, &d->max_range_m);
    }
    const std::set<std::string> camera_keys = {
        "xyz_m",           "look_at_m", "up",         "rpy_rad",
        "quaternion_xyzw", "fov_deg",   "intrinsics", "range_m"};
    if (type == "mocap") {
      d->type = DeviceType::kMocap;
      if (!CheckKeys(node, "device", {"type", "cameras", "min_cameras"})) {
        return false;
      }
      const YAML::Node cameras = node["cameras"];
      if (!cameras || !cameras.IsSequence() || cameras.size() == 0) {
        return Fail(cameras ? cameras.Mark() : node.Mark(), "device.cameras",
                    "expected a non-empty list of cameras");
      }
      if (cameras.size() > static_cast<size_t>(kMaxCellCameras)) {
        return Fail(cameras.Mark(), "device.cameras",
                    "at most " + std::to_string(kMaxCellCameras) +
                        " cameras, got " + std::to_string(cameras.size()));
      }
      for (size_t i = 0; i < cameras.size(); ++i) {
        const std::string f = "device.cameras[" + std::to_string(i) + "]";
        if (!cameras[i].IsMap()) {
          return Fail(cameras[i].Mark(), f, "expected a mapping");
        }
        if (!CheckKeys(cameras[i], f, camera_keys)) return false;
        CellCamera c;
        if (!ParseCamera(cameras[i], f, &c)) return false;
        d->cameras.push_back(c);
      }
      d->min_cameras = 1;
      if (const YAML::Node m = node["min_cameras"]) {
        double v = 0;
        if (!Number(m, "device.min_cameras", &v)) return false;
        if (v != std::floor(v) || v < 1 ||
            v > static_cast<double>(d->cameras.size())) {
          return Fail(m.Mark(), "device.min_cameras",
                      "expected a whole number in [1, " +
                          std::to_string(d->cameras.size()) +
                          "] (the cameras), got " + internal::ShortestText(v));
        }
        d->min_cameras = static_cast<int>(v);
      }
      return true;
    }
    if (type == "camera") {
      d->type = DeviceType::kCamera;
      std::set<std::string> keys = camera_keys;
      keys.insert({"type", "max_viewing_angle_deg"});
      if (!CheckKeys(node, "device", keys)) return false;
      CellCamera c;
      if (!ParseCamera(node, "device", &c)) return false;
      d->cameras = {c};
      if (const YAML::Node a = node["max_viewing_angle_deg"]) {
        double v = 0;
        if (!Number(a, "device.max_viewing_angle_deg", &v)) return false;
        if (!(v > 0 && v <= 90)) {
          return Fail(a.Mark(), "device.max_viewing_angle_deg",
                      "must be in (0, 90], got " + internal::ShortestText(v));
        }
        d->max_viewing_angle_rad = v * kDegree;
      }
      return true;
    }
    return Fail(node["type"].Mark(), "device.type",
                "expected laser_tracker, mocap or camera, got '" + type + "'");
  }

  bool ParseTarget(const YAML::Node& node, const std::string& field,
                   CellTarget* t) {
    if (!node.IsMap()) {
      return Fail(node.Mark(), field,
                  "expected {xyz_m: [..], normal: [..], acceptance_deg: ..}");
    }
    if (!CheckKeys(node, field,
                   {"name", "xyz_m", "normal", "acceptance_deg"})) {
      return false;
    }
    if (node["name"] && !String(node, "name", field + ".name", &t->name)) {
      return false;
    }
    const YAML::Node xyz = node["xyz_m"];
    if (!xyz) return Fail(node.Mark(), field + ".xyz_m", "missing");
    if (!Vector(xyz, field + ".xyz_m", &t->xyz_m)) return false;
    if (!Direction(node, "normal", field, &t->normal)) return false;
    const YAML::Node a = node["acceptance_deg"];
    if (!a) return Fail(node.Mark(), field + ".acceptance_deg", "missing");
    double deg = 0;
    if (!Number(a, field + ".acceptance_deg", &deg)) return false;
    if (!(deg > 0 && deg <= 90)) {
      return Fail(a.Mark(), field + ".acceptance_deg",
                  "must be in (0, 90], got " + internal::ShortestText(deg));
    }
    t->acceptance_rad = deg * kDegree;
    return true;
  }

  std::string Where(const YAML::Mark& mark, const std::string& field) const {
    return source_ + ":" + std::to_string(mark.line + 1) + ":" +
           std::to_string(mark.column + 1) + ": " + field;
  }

  std::string source_;
  std::string directory_;
};

}  // namespace

constexpr const char* kDeviceTypeNames[] = {"laser_tracker", "mocap", "camera"};

const char* DeviceTypeName(DeviceType type) {
  return EnumToString(kDeviceTypeNames, type);
}

bool PointInsideObstacle(const Obstacle& o, const Eigen::Vector3d& point) {
  if (o.plane) return o.normal.dot(point) < o.offset_m;
  const CollisionShape& s = o.shape;
  return PointInShape(
      s, s.pose.rotation.transpose() * (point - s.pose.translation));
}

bool ReadSrdfDisabledPairs(
    const std::string& path,
    std::vector<std::pair<std::string, std::string>>* pairs,
    std::string* error) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) {
    if (error) {
      *error = path + ": " +
               (doc.ErrorID() == tinyxml2::XML_ERROR_FILE_NOT_FOUND
                    ? std::string("cannot open the file")
                    : std::string(doc.ErrorStr()));
    }
    return false;
  }
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (robot == nullptr) {
    if (error) *error = path + ": no <robot> element (not an SRDF file)";
    return false;
  }
  for (const tinyxml2::XMLElement* e =
           robot->FirstChildElement("disable_collisions");
       e != nullptr; e = e->NextSiblingElement("disable_collisions")) {
    const char* a = e->Attribute("link1");
    const char* b = e->Attribute("link2");
    if (a == nullptr || b == nullptr) {
      if (error) {
        *error = path + ":" + std::to_string(e->GetLineNum()) +
                 ": <disable_collisions> needs link1 and link2";
      }
      return false;
    }
    pairs->emplace_back(a, b);
  }
  return true;
}

bool ParseCellFile(const std::string& text, const std::string& source,
                   const std::string& directory, Cell* cell,
                   std::string* error) {
  *cell = Cell();
  cell->source = source;
  CellParser parser(source, directory);
  if (!parser.Parse(text, cell)) {
    if (error) *error = parser.error();
    return false;
  }
  return true;
}

std::vector<Cell::Eye> DeviceEyes(const Cell& cell) {
  std::vector<Cell::Eye> eyes;
  if (!cell.has_device) return eyes;
  const CellDevice& d = cell.device;
  auto eye = [&](const Eigen::Vector3d& position, const std::string& field) {
    eyes.push_back(
        {position, field,
         cell.device_where.empty() ? field : cell.device_where + ": " + field});
  };
  if (d.type == DeviceType::kLaserTracker) {
    eye(d.position, "device.xyz_m");
  } else if (d.type == DeviceType::kCamera) {
    if (!d.cameras.empty()) eye(d.cameras[0].position, "device.xyz_m");
  } else {
    for (size_t c = 0; c < d.cameras.size(); ++c) {
      eye(d.cameras[c].position,
          "device.cameras[" + std::to_string(c) + "].xyz_m");
    }
  }
  return eyes;
}

bool LoadCellFile(const std::string& path, Cell* cell, std::string* error) {
  std::string text;
  if (!ReadTextFile(path, &text, error)) return false;
  return ParseCellFile(text, path, internal::DirectoryOf(path), cell, error);
}

}  // namespace activecal
