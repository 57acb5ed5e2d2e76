// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/ros_frames.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "number_text.h"
#include "yaml_reader.h"

namespace activecal {
namespace {

using internal::ParseFiniteNumber;
using internal::ShortestText;
using internal::Trim;

// tf2 frame ids activecal writes: no blanks or shell metacharacters (the
// script passes them unquoted), no leading '/' (tf2 strips and warns).
bool CheckFrameName(const std::string& name, const std::string& what,
                    std::string* error) {
  std::string why;
  if (name.empty()) {
    why = "is empty";
  } else if (name[0] == '/') {
    why = "starts with '/' (tf2 frame ids do not)";
  } else {
    for (char c : name) {
      const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                      (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                      c == '.' || c == '/';
      if (!ok) {
        why = "has '" + std::string(1, c) +
              "': use letters, digits, '_', '-', '.' and '/'";
        break;
      }
    }
  }
  if (why.empty()) return true;
  *error = what + " '" + name + "' " + why;
  return false;
}

// A double for YAML 1.1 readers (PyYAML): with a '.' before any exponent.
std::string YamlFloat(double value) {
  std::string s = ShortestText(value);
  if (s.find_first_of(".n") != std::string::npos) return s;  // 1.5, nan, inf
  const size_t e = s.find('e');
  if (e == std::string::npos) return s + ".0";
  return s.substr(0, e) + ".0" + s.substr(e);
}

// `q` normalised if its squared norm is within 0.01 of 1 (tf2's tolerance).
bool UnitQuaternion(double x, double y, double z, double w,
                    Eigen::Quaterniond* q, std::string* why) {
  const double norm2 = x * x + y * y + z * z + w * w;
  if (!(std::abs(norm2 - 1.0) <= 0.01)) {
    *why = "the quaternion (" + ShortestText(x) + ", " + ShortestText(y) +
           ", " + ShortestText(z) + ", " + ShortestText(w) +
           ") is not a unit quaternion (squared norm " + ShortestText(norm2) +
           ")";
    return false;
  }
  *q = Eigen::Quaterniond(w, x, y, z).normalized();
  return true;
}

class Tf2YamlParser : public internal::YamlReader {
 public:
  using YamlReader::YamlReader;

  bool Parse(const std::string& text, std::vector<RosTransform>* out) {
    YAML::Node root;
    if (!LoadMap(text, "with transforms (a tf2_msgs/msg/TFMessage)", &root) ||
        !CheckKeys(root, "", {"transforms"})) {
      return false;
    }
    const YAML::Node list = root["transforms"];
    if (!list) return Fail(root.Mark(), "transforms", "missing");
    if (!list.IsSequence()) {
      return Fail(list.Mark(), "transforms", "expected a list of transforms");
    }
    out->clear();
    for (size_t n = 0; n < list.size(); ++n) {
      const YAML::Node item = list[n];
      const std::string field = "transforms[" + std::to_string(n) + "]";
      if (!item.IsMap()) return Fail(item.Mark(), field, "expected a mapping");
      RosTransform t;
      if (!CheckKeys(item, field, {"header", "child_frame_id", "transform"}) ||
          !String(item, "child_frame_id", field + ".child_frame_id",
                  &t.child_frame_id)) {
        return false;
      }
      const YAML::Node header = item["header"];
      if (!header) return Fail(item.Mark(), field + ".header", "missing");
      if (!header.IsMap()) {
        return Fail(header.Mark(), field + ".header", "expected a mapping");
      }
      if (!CheckKeys(header, field + ".header", {"stamp", "frame_id"}) ||
          !String(header, "frame_id", field + ".header.frame_id",
                  &t.frame_id)) {
        return false;
      }
      if (t.frame_id.empty() || t.child_frame_id.empty()) {
        return Fail(item.Mark(), field, "empty frame id");
      }
      const YAML::Node transform = item["transform"];
      const std::string tf = field + ".transform";
      if (!transform) return Fail(item.Mark(), tf, "missing");
      if (!transform.IsMap())
        return Fail(transform.Mark(), tf, "expected a mapping");
      if (!CheckKeys(transform, tf, {"translation", "rotation"})) return false;
      double v[7];
      if (!Fields(transform, "translation", tf, {"x", "y", "z"}, v) ||
          !Fields(transform, "rotation", tf, {"x", "y", "z", "w"}, v + 3)) {
        return false;
      }
      t.translation << v[0], v[1], v[2];
      std::string why;
      if (!UnitQuaternion(v[3], v[4], v[5], v[6], &t.rotation, &why)) {
        return Fail(transform["rotation"].Mark(), tf + ".rotation", why);
      }
      out->push_back(t);
    }
    return true;
  }

 private:
  // map[key] as {names...: number}, every name required.
  bool Fields(const YAML::Node& map, const char* key, const std::string& parent,
              const std::set<std::string>& names, double* values) {
    const std::string field = parent + "." + key;
    const YAML::Node node = map[key];
    if (!node) return Fail(map.Mark(), field, "missing");
    if (!node.IsMap()) return Fail(node.Mark(), field, "expected a mapping");
    if (!CheckKeys(node, field, names)) return false;
    // In x, y, z, w order, not the set's.
    int k = 0;
    for (const char* name : {"x", "y", "z", "w"}) {
      if (!names.count(name)) continue;
      const YAML::Node value = node[name];
      if (!value) return Fail(node.Mark(), field + "." + name, "missing");
      if (!Number(value, field + "." + name, &values[k++])) return false;
    }
    return true;
  }
};

// One command of a script: the tokens after the program's name.
bool ParseCommandArguments(const std::vector<std::string>& args,
                           RosTransform* t, std::string* why) {
  auto number = [&](const std::string& text, const std::string& what,
                    double* value) {
    std::string reason;
    if (ParseFiniteNumber(text, value, &reason)) return true;
    *why = what + ": " + reason;
    return false;
  };
  double v[7] = {0, 0, 0, 0, 0, 0, 1};  // x y z, then qx qy qz qw
  double rpy[3] = {0, 0, 0};
  bool have_quaternion = false, have_rpy = false;
  const bool flags = !args.empty() && args[0].rfind("--", 0) == 0;
  if (flags) {
    static const std::map<std::string, int> kNumbers = {
        {"--x", 0},  {"--y", 1},  {"--z", 2},    {"--qx", 3},    {"--qy", 4},
        {"--qz", 5}, {"--qw", 6}, {"--roll", 7}, {"--pitch", 8}, {"--yaw", 9}};
    std::set<std::string> seen;
    for (size_t n = 0; n < args.size(); n += 2) {
      const std::string& flag = args[n];
      const auto number_flag = kNumbers.find(flag);
      if (number_flag == kNumbers.end() && flag != "--frame-id" &&
          flag != "--child-frame-id") {
        *why = "unknown argument '" + flag +
               "' (expected --x --y --z, --qx --qy --qz --qw or --roll "
               "--pitch --yaw, --frame-id, --child-frame-id)";
        return false;
      }
      if (n + 1 >= args.size()) {
        *why = flag + ": missing its value";
        return false;
      }
      if (!seen.insert(flag).second) {
        *why = flag + " given twice";
        return false;
      }
      const std::string& value = args[n + 1];
      if (flag == "--frame-id") {
        t->frame_id = value;
      } else if (flag == "--child-frame-id") {
        t->child_frame_id = value;
      } else {
        const int k = number_flag->second;
        if (!number(value, flag, k < 7 ? &v[k] : &rpy[k - 7])) return false;
        if (k >= 7) {
          have_rpy = true;
        } else if (k >= 3) {
          have_quaternion = true;
        }
      }
    }
    if (have_quaternion && have_rpy) {
      *why = "both a quaternion (--qx ...) and angles (--roll ...) given";
      return false;
    }
    if (t->frame_id.empty() || t->child_frame_id.empty()) {
      *why = "--frame-id and --child-frame-id are required";
      return false;
    }
  } else if (args.size() == 9 || args.size() == 8) {
    // x y z qx qy qz qw frame child, or x y z yaw pitch roll frame child.
    const int count = static_cast<int>(args.size()) - 2;
    static const char* kNames9[] = {"x", "y", "z", "qx", "qy", "qz", "qw"};
    static const char* kNames8[] = {"x", "y", "z", "yaw", "pitch", "roll"};
    double values[7];
    for (int k = 0; k < count; ++k) {
      if (!number(args[k], count == 7 ? kNames9[k] : kNames8[k], &values[k])) {
        return false;
      }
    }
    for (int k = 0; k < 3; ++k) v[k] = values[k];
    if (count == 7) {
      for (int k = 3; k < 7; ++k) v[k] = values[k];
    } else {
      rpy[0] = values[5];
      rpy[1] = values[4];
      rpy[2] = values[3];
      have_rpy = true;
    }
    t->frame_id = args[count];
    t->child_frame_id = args[count + 1];
  } else {
    *why =
        "expected the flags --x ... --child-frame-id, or 9 (x y z qx qy qz "
        "qw frame child) or 8 (x y z yaw pitch roll frame child) "
        "arguments, got " +
        std::to_string(args.size());
    return false;
  }
  t->translation << v[0], v[1], v[2];
  if (have_rpy) {
    // The angles a user gave: their matrix, then its quaternion.
    *t = RosTransformFromMatrix(t->frame_id, t->child_frame_id,
                                RpyRotation(rpy[0], rpy[1], rpy[2]),
                                t->translation);
    return true;
  }
  return UnitQuaternion(v[3], v[4], v[5], v[6], &t->rotation, why);
}

}  // namespace

Eigen::Matrix4d RosTransform::Matrix() const {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = rotation.toRotationMatrix();
  T.topRightCorner<3, 1>() = translation;
  return T;
}

RosTransform RosTransformFromMatrix(const std::string& frame_id,
                                    const std::string& child_frame_id,
                                    const Eigen::Matrix3d& R,
                                    const Eigen::Vector3d& t) {
  RosTransform out;
  out.frame_id = frame_id;
  out.child_frame_id = child_frame_id;
  out.translation = t;
  out.rotation = Eigen::Quaterniond(R).normalized();
  if (out.rotation.w() < 0) out.rotation.coeffs() *= -1.0;
  return out;
}

bool MetrologyRosTransforms(const RobotModel& model,
                            const Eigen::VectorXd& values,
                            const RosFramesOptions& options,
                            std::vector<RosTransform>* transforms,
                            std::string* error) {
  if (!CheckFrameName(options.device_frame, "device frame", error) ||
      !CheckFrameName(options.base_frame, "base frame", error) ||
      !CheckFrameName(options.tip_frame, "tip frame", error)) {
    return false;
  }
  std::vector<RosTransform> out;
  if (model.base.convention == LinkConvention::kFrame) {
    if (options.device_frame == options.base_frame) {
      *error = "the device frame and the base frame are both '" +
               options.base_frame + "'";
      return false;
    }
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    LinkTransform(model.base, values.data() + model.block_offset(0), 0.0, &R,
                  &t);
    out.push_back(
        RosTransformFromMatrix(options.device_frame, options.base_frame, R, t));
  }
  std::set<std::string> children = {options.device_frame, options.base_frame,
                                    options.tip_frame};
  for (int k = 0; k < model.num_markers(); ++k) {
    const int block = model.marker_block(k);
    const std::string name = model.block_name(block);
    if (!CheckFrameName(name, "marker", error)) return false;
    if (!children.insert(name).second) {
      *error = "marker '" + name +
               "' has the name of another frame (the device, base or tip "
               "frame, or another marker): tf2 frames need one parent";
      return false;
    }
    const double* v = values.data() + model.block_offset(block);
    out.push_back(RosTransformFromMatrix(options.tip_frame, name,
                                         ToolRotation(v),
                                         Eigen::Vector3d(v[0], v[1], v[2])));
  }
  *transforms = out;
  return true;
}

std::string StaticTransformPublisherScript(
    const std::vector<RosTransform>& transforms, const std::string& comment) {
  std::ostringstream out;
  out << "#!/bin/sh\n";
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);)
    out << "# " << line << "\n";
  out << "# One static_transform_publisher per transform (ROS 2); sh FILE "
         "starts them all.\n";
  for (const RosTransform& t : transforms) {
    const Eigen::Quaterniond& q = t.rotation;
    out << "ros2 run tf2_ros static_transform_publisher"
        << " --x " << ShortestText(t.translation.x()) << " --y "
        << ShortestText(t.translation.y()) << " --z "
        << ShortestText(t.translation.z()) << " --qx " << ShortestText(q.x())
        << " --qy " << ShortestText(q.y()) << " --qz " << ShortestText(q.z())
        << " --qw " << ShortestText(q.w()) << " --frame-id " << t.frame_id
        << " --child-frame-id " << t.child_frame_id << " &\n";
  }
  out << "wait\n";
  return out.str();
}

std::string Tf2StaticTransformsYaml(const std::vector<RosTransform>& transforms,
                                    const std::string& comment) {
  std::ostringstream out;
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);)
    out << "# " << line << "\n";
  if (transforms.empty()) return out.str() + "transforms: []\n";
  out << "transforms:\n";
  for (const RosTransform& t : transforms) {
    const Eigen::Quaterniond& q = t.rotation;
    out << "  - header:\n"
        << "      stamp: {sec: 0, nanosec: 0}\n"
        << "      frame_id: \"" << t.frame_id << "\"\n"
        << "    child_frame_id: \"" << t.child_frame_id << "\"\n"
        << "    transform:\n"
        << "      translation: {x: " << YamlFloat(t.translation.x())
        << ", y: " << YamlFloat(t.translation.y())
        << ", z: " << YamlFloat(t.translation.z()) << "}\n"
        << "      rotation: {x: " << YamlFloat(q.x())
        << ", y: " << YamlFloat(q.y()) << ", z: " << YamlFloat(q.z())
        << ", w: " << YamlFloat(q.w()) << "}\n";
  }
  return out.str();
}

bool ParseStaticTransformPublisherScript(const std::string& text,
                                         const std::string& source,
                                         std::vector<RosTransform>* transforms,
                                         std::string* error) {
  std::vector<RosTransform> out;
  std::istringstream in(text);
  std::string line, command;
  int number = 0, first = 0;
  while (std::getline(in, line)) {
    ++number;
    line = Trim(line);
    if (command.empty()) first = number;
    if (!line.empty() && line.back() == '\\') {  // continued
      command += line.substr(0, line.size() - 1) + " ";
      continue;
    }
    command += line;
    std::string whole = Trim(command);
    command.clear();
    if (whole.empty() || whole[0] == '#' || whole == "wait") continue;
    if (whole.back() == '&') whole = Trim(whole.substr(0, whole.size() - 1));
    std::istringstream words(whole);
    std::vector<std::string> tokens;
    for (std::string w; words >> w;) tokens.push_back(w);
    const auto fail = [&](const std::string& what) {
      *error = source + ":" + std::to_string(first) + ": " + what;
      return false;
    };
    size_t skip = 0;
    if (tokens.size() >= 4 && tokens[0] == "ros2" && tokens[1] == "run" &&
        tokens[2] == "tf2_ros" && tokens[3] == "static_transform_publisher") {
      skip = 4;
    } else if (tokens.size() >= 3 && tokens[0] == "rosrun" &&
               tokens[1] == "tf2_ros" &&
               tokens[2] == "static_transform_publisher") {
      skip = 3;
    } else {
      return fail(
          "expected a 'ros2 run tf2_ros static_transform_publisher ...' "
          "command, got '" +
          whole + "'");
    }
    RosTransform t;
    std::string why;
    if (!ParseCommandArguments(
            std::vector<std::string>(tokens.begin() + skip, tokens.end()), &t,
            &why)) {
      return fail(why);
    }
    out.push_back(t);
  }
  if (!command.empty()) {
    *error = source + ":" + std::to_string(first) +
             ": the file ends in a line continuation ('\\')";
    return false;
  }
  *transforms = out;
  return true;
}

bool ParseTf2StaticTransformsYaml(const std::string& text,
                                  const std::string& source,
                                  std::vector<RosTransform>* transforms,
                                  std::string* error) {
  Tf2YamlParser parser(source);
  if (parser.Parse(text, transforms)) return true;
  *error = parser.error();
  return false;
}

}  // namespace activecal
