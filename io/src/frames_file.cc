// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/frames_file.h"

#include <yaml-cpp/yaml.h>

#include <set>
#include <sstream>
#include <vector>

#include "activecal/core/kinematics.h"
#include "activecal/io/csv_files.h"
#include "number_text.h"
#include "yaml_reader.h"

namespace activecal {
namespace {

using internal::kDegree;
using internal::ShortestText;

class FramesParser : public internal::YamlReader {
 public:
  using YamlReader::YamlReader;

  bool Parse(const std::string& text, RobotDescription* robot) {
    YAML::Node root;
    if (!LoadMap(text, "with base and markers", &root)) return false;
    if (!CheckKeys(root, "", {"angle_unit", "base", "markers"})) return false;
    double scale = 1.0;
    if (const YAML::Node unit = root["angle_unit"]) {
      const std::string u = unit.IsScalar() ? unit.Scalar() : "";
      if (u == "deg") {
        scale = kDegree;
      } else if (u != "rad") {
        return Fail(unit.Mark(), "angle_unit",
                    "expected 'rad' or 'deg', got '" + u + "'");
      }
    }
    RobotModel& m = robot->model;
    // Values by block, so that the marker blocks can be rebuilt.
    const int num_links = m.num_joints() + 1;
    Eigen::VectorXd head = m.nominal.head(m.block_offset(num_links));
    Eigen::VectorXd truth_head;
    const bool has_truth = robot->true_parameters.size() == m.num_parameters();
    if (has_truth) truth_head = robot->true_parameters.head(head.size());
    if (const YAML::Node base = root["base"]) {
      if (m.base.convention != LinkConvention::kFrame) {
        return Fail(base.Mark(), "base",
                    "the robot's base is a " +
                        std::string(LinkConventionName(m.base.convention)) +
                        " block, not a 6-DOF frame: give the base in the "
                        "robot file");
      }
      Eigen::Vector3d xyz, rpy;
      if (!Pose(base, "base", scale, &xyz, &rpy)) return false;
      if (!CheckKeys(base, "base", {"xyz", "rpy"})) return false;
      head.head(3) = xyz;
      head.segment(3, 3) = rpy;
      if (has_truth) truth_head.head(6) = head.head(6);
    }
    std::vector<Marker> markers = m.markers;
    Eigen::VectorXd marker_values =
        m.nominal.tail(m.num_parameters() - head.size());
    if (const YAML::Node list = root["markers"]) {
      if (!list.IsSequence() || list.size() == 0) {
        return Fail(list.Mark(), "markers",
                    "expected a non-empty list of markers");
      }
      const std::array<bool, kMarkerBlockSize> free = m.markers[0].free;
      markers.assign(list.size(), Marker());
      marker_values = Eigen::VectorXd::Zero(kMarkerBlockSize * list.size());
      std::set<std::string> names;
      for (size_t k = 0; k < list.size(); ++k) {
        const std::string field = "markers[" + std::to_string(k) + "]";
        const YAML::Node node = list[k];
        if (!node.IsMap())
          return Fail(node.Mark(), field, "expected a mapping");
        if (!CheckKeys(node, field, {"name", "xyz", "rpy"})) return false;
        markers[k].free = free;
        markers[k].name = k == 0 ? "tool" : "marker" + std::to_string(k + 1);
        if (const YAML::Node name = node["name"]) {
          if (!name.IsScalar() || name.Scalar().empty()) {
            return Fail(name.Mark(), field + ".name", "expected a text");
          }
          markers[k].name = name.Scalar();
        }
        if (!names.insert(markers[k].name).second) {
          return Fail(node.Mark(), field + ".name",
                      "marker '" + markers[k].name + "' is listed twice");
        }
        Eigen::Vector3d xyz, rpy;
        if (!Pose(node, field, scale, &xyz, &rpy)) return false;
        marker_values.segment(kMarkerBlockSize * k, 3) = xyz;
        marker_values.segment(kMarkerBlockSize * k + 3, 3) = rpy;
      }
    }
    // The true marker values stay the robot file's unless the frames file
    // lists the markers (then they are its values: it has no true ones).
    const Eigen::VectorXd truth_markers =
        root["markers"] || !has_truth
            ? marker_values
            : Eigen::VectorXd(robot->true_parameters.tail(m.num_parameters() -
                                                          head.size()));
    m.markers = markers;
    m.nominal.resize(head.size() + marker_values.size());
    m.nominal << head, marker_values;
    if (has_truth) {
      robot->true_parameters.resize(m.nominal.size());
      robot->true_parameters << truth_head, truth_markers;
    }
    std::string why;
    if (!m.Validate(&why)) return Fail(root.Mark(), "", why);
    return true;
  }
};

}  // namespace

bool ParseFramesFile(const std::string& text, const std::string& source,
                     RobotDescription* robot, std::string* error) {
  RobotDescription copy = *robot;
  FramesParser parser(source);
  if (!parser.Parse(text, &copy)) {
    if (error) *error = parser.error();
    return false;
  }
  *robot = std::move(copy);
  return true;
}

bool LoadFramesFile(const std::string& path, RobotDescription* robot,
                    std::string* error) {
  std::string text;
  return ReadTextFile(path, &text, error) &&
         ParseFramesFile(text, path, robot, error);
}

std::string FramesFileText(const RobotModel& model,
                           const Eigen::VectorXd& values,
                           const std::string& comment) {
  YAML::Emitter out;
  if (!comment.empty()) out << YAML::Comment(comment) << YAML::Newline;
  auto triple = [&](const double* v) {
    out << YAML::Flow << YAML::BeginSeq;
    for (int k = 0; k < 3; ++k) out << ShortestText(v[k]);
    out << YAML::EndSeq;
  };
  out << YAML::BeginMap;
  out << YAML::Key << "angle_unit" << YAML::Value << "rad";
  if (model.base.convention == LinkConvention::kFrame) {
    out << YAML::Key << "base" << YAML::Value << YAML::Flow << YAML::BeginMap
        << YAML::Key << "xyz" << YAML::Value;
    triple(values.data());
    out << YAML::Key << "rpy" << YAML::Value;
    triple(values.data() + 3);
    out << YAML::EndMap;
  }
  out << YAML::Key << "markers" << YAML::Value << YAML::BeginSeq;
  for (int k = 0; k < model.num_markers(); ++k) {
    const double* v = values.data() + model.block_offset(model.marker_block(k));
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value
        << model.block_name(model.marker_block(k)) << YAML::Key << "xyz"
        << YAML::Value;
    triple(v);
    out << YAML::Key << "rpy" << YAML::Value;
    triple(v + 3);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace activecal
