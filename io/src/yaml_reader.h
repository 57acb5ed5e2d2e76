// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The reading habits of core's YAML files (robot descriptions, frames):
// messages "<source>:<line>:<column>: <field>: <what>", unknown keys refused,
// finite numbers, [x, y, z] lists and {xyz, rpy} poses. Not installed.

#ifndef ACTIVECAL_CORE_SRC_YAML_READER_H_
#define ACTIVECAL_CORE_SRC_YAML_READER_H_

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <set>
#include <sstream>
#include <string>

#include "number_text.h"

namespace activecal {
namespace internal {

class YamlReader {
 public:
  explicit YamlReader(std::string source) : source_(std::move(source)) {}
  const std::string& error() const { return error_; }

 protected:
  // Parses `text` into *root, which must be a mapping (`what` says of
  // what, for the message).
  bool LoadMap(const std::string& text, const std::string& what,
               YAML::Node* root) {
    try {
      *root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
      return Fail(e.mark, "", "not valid YAML: " + e.msg);
    }
    if (!root->IsMap()) {
      return Fail(root->Mark(), "", "expected a mapping " + what);
    }
    return true;
  }

  // Sets the message and returns false.
  bool Fail(const YAML::Mark& mark, const std::string& field,
            const std::string& what) {
    std::ostringstream msg;
    msg << source_;
    if (!mark.is_null()) msg << ":" << mark.line + 1 << ":" << mark.column + 1;
    msg << ": ";
    if (!field.empty()) msg << field << ": ";
    msg << what;
    error_ = msg.str();
    return false;
  }

  // Every key of `map` is one of `allowed`, and none is given twice
  // (map[key] would read the first and silently drop the other).
  bool CheckKeys(const YAML::Node& map, const std::string& field,
                 const std::set<std::string>& allowed) {
    std::set<std::string> seen;
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      const std::string name = field.empty() ? key : field + "." + key;
      if (!allowed.count(key)) {
        std::string list;
        for (const std::string& a : allowed) {
          list += (list.empty() ? "" : ", ") + a;
        }
        return Fail(kv.first.Mark(), name,
                    "unknown field (expected one of: " + list + ")");
      }
      if (!seen.insert(key).second) {
        return Fail(kv.first.Mark(), name, "given twice");
      }
    }
    return true;
  }

  // The text of map[key], required.
  bool String(const YAML::Node& map, const char* key, const std::string& field,
              std::string* out) {
    const YAML::Node node = map[key];
    if (!node) return Fail(map.Mark(), field, "missing");
    if (!node.IsScalar()) return Fail(node.Mark(), field, "expected a text");
    *out = node.Scalar();
    return true;
  }

  bool Number(const YAML::Node& node, const std::string& field, double* out) {
    if (!node.IsScalar()) return Fail(node.Mark(), field, "expected a number");
    std::string why;
    return ParseFiniteNumber(node.Scalar(), out, &why) ||
           Fail(node.Mark(), field, why);
  }

  // A list of three numbers.
  bool Vector(const YAML::Node& node, const std::string& field,
              Eigen::Vector3d* out) {
    if (!node.IsSequence() || node.size() != 3) {
      return Fail(node.Mark(), field, "expected [x, y, z]");
    }
    for (int k = 0; k < 3; ++k) {
      if (!Number(node[k], field + "[" + std::to_string(k) + "]", &(*out)[k])) {
        return false;
      }
    }
    return true;
  }

  // {xyz: [..], rpy: [..]}, both optional (zero), rpy times `angle_scale`
  // (the file's angle unit). The caller checks the keys.
  bool Pose(const YAML::Node& node, const std::string& field,
            double angle_scale, Eigen::Vector3d* xyz, Eigen::Vector3d* rpy) {
    if (!node.IsMap()) {
      return Fail(node.Mark(), field,
                  "expected {xyz: [x, y, z], rpy: [r, p, y]}");
    }
    xyz->setZero();
    rpy->setZero();
    if (node["xyz"] && !Vector(node["xyz"], field + ".xyz", xyz)) return false;
    if (node["rpy"] && !Vector(node["rpy"], field + ".rpy", rpy)) return false;
    *rpy *= angle_scale;
    return true;
  }

 private:
  std::string source_;
  std::string error_;
};

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_CORE_SRC_YAML_READER_H_
