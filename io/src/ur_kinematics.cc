// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/ur_kinematics.h"

#include <Eigen/Geometry>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "number_text.h"
#include "yaml_reader.h"

namespace activecal {

const char* const kUrKinematicsEntries[6] = {
    "shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3"};
const char* const kUrJointNames[6] = {
    "shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
    "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};

namespace {

const char* const kFields[6] = {"x", "y", "z", "roll", "pitch", "yaw"};

class UrKinematicsReader : public internal::YamlReader {
 public:
  explicit UrKinematicsReader(const std::string& source) : YamlReader(source) {}

  bool Read(const std::string& text, UrKinematics* out) {
    YAML::Node root;
    if (!LoadMap(text, "(kinematics: {shoulder: ..., hash: ...})", &root) ||
        !CheckKeys(root, "", {"kinematics"})) {
      return false;
    }
    const YAML::Node k = root["kinematics"];
    if (!k || !k.IsMap()) {
      return Fail(root.Mark(), "kinematics", "expected a mapping");
    }
    std::set<std::string> allowed(std::begin(kUrKinematicsEntries),
                                  std::end(kUrKinematicsEntries));
    allowed.insert("hash");
    if (!CheckKeys(k, "kinematics", allowed)) return false;
    for (int j = 0; j < 6; ++j) {
      const std::string name =
          std::string("kinematics.") + kUrKinematicsEntries[j];
      const YAML::Node e = k[kUrKinematicsEntries[j]];
      if (!e || !e.IsMap()) return Fail(k.Mark(), name, "missing");
      if (!CheckKeys(e, name, {std::begin(kFields), std::end(kFields)})) {
        return false;
      }
      for (int f = 0; f < 6; ++f) {
        const YAML::Node v = e[kFields[f]];
        const std::string field = name + "." + kFields[f];
        if (!v) return Fail(e.Mark(), field, "missing");
        double* target =
            f < 3 ? &out->joints[j].xyz[f] : &out->joints[j].rpy[f - 3];
        if (!Number(v, field, target)) return false;
      }
    }
    if (k["hash"]) {
      if (!String(k, "hash", "kinematics.hash", &out->hash)) return false;
    }
    return true;
  }
};

Eigen::Matrix3d Rpy(double r, double p, double y) {
  return RpyRotation<double>(r, p, y);
}

}  // namespace

std::string UrKinematicsText(const UrKinematics& kinematics,
                             const std::string& comment) {
  std::ostringstream out;
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) {
    out << "# " << line << "\n";
  }
  out << "kinematics:\n";
  for (int j = 0; j < 6; ++j) {
    out << "  " << kUrKinematicsEntries[j] << ":\n";
    for (int f = 0; f < 6; ++f) {
      const double v =
          f < 3 ? kinematics.joints[j].xyz[f] : kinematics.joints[j].rpy[f - 3];
      // + 0.0: no "-0".
      out << "    " << kFields[f] << ": " << internal::ShortestText(v + 0.0)
          << "\n";
    }
  }
  out << "  hash: " << kinematics.hash << "\n";
  return out.str();
}

bool ParseUrKinematics(const std::string& text, const std::string& source,
                       UrKinematics* kinematics, std::string* error) {
  *kinematics = UrKinematics();
  UrKinematicsReader reader(source);
  if (!reader.Read(text, kinematics)) {
    *error = reader.error();
    return false;
  }
  return true;
}

void UrTool0Pose(const UrKinematics& kinematics, const Eigen::VectorXd& q,
                 Eigen::Matrix3d* R, Eigen::Vector3d* t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Rpy(0, 0, M_PI);  // base_link -> base_link_inertia
  for (int j = 0; j < 6; ++j) {
    const UrJointOrigin& o = kinematics.joints[j];
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    origin.translation() = o.xyz;
    origin.linear() = Rpy(o.rpy[0], o.rpy[1], o.rpy[2]);
    T = T * origin * Eigen::AngleAxisd(q[j], Eigen::Vector3d::UnitZ());
  }
  Eigen::Isometry3d flange = Eigen::Isometry3d::Identity();
  flange.linear() = Rpy(0, -M_PI / 2, -M_PI / 2);  // wrist_3_link -> flange
  Eigen::Isometry3d tool0 = Eigen::Isometry3d::Identity();
  tool0.linear() = Rpy(M_PI / 2, 0, M_PI / 2);  // flange -> tool0
  T = T * flange * tool0;
  *R = T.linear();
  *t = T.translation();
}

}  // namespace activecal
