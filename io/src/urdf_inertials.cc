// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/urdf_inertials.h"

#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <sstream>
#include <vector>

namespace activecal {

bool ParseUrdfInertials(const std::string& xml, const std::string& source,
                        const UrdfChainOptions& options, GravityModel* gravity,
                        std::string* error) {
  std::vector<UrdfChainJoint> joints;
  if (!UrdfChainJoints(xml, source, options, &joints, error)) return false;
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    if (error) *error = source + ": not a valid URDF: " + e.what();
    return false;
  }
  if (!model) {
    if (error) *error = source + ": not a valid URDF";
    return false;
  }
  gravity->bodies.clear();
  std::vector<std::string> without;
  int joint = -1;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (const UrdfChainJoint& j : joints) {
    if (j.moving) {
      ++joint;
      R.setIdentity();
      t.setZero();
    } else {
      if (joint < 0) continue;  // the base: carries no torque
      t += R * j.xyz;
      R = R * j.rotation;
    }
    const urdf::LinkConstSharedPtr link = model->getLink(j.child_link);
    if (!link || !link->inertial || !(link->inertial->mass > 0)) {
      if (j.moving) without.push_back(j.child_link);
      continue;
    }
    const urdf::Vector3& c = link->inertial->origin.position;
    BodyInertial b;
    b.name = j.child_link;
    b.joint = joint;
    b.mass_kg = link->inertial->mass;
    b.com_m = R * Eigen::Vector3d(c.x, c.y, c.z) + t;
    gravity->bodies.push_back(b);
  }
  if (gravity->bodies.empty()) {
    std::ostringstream msg;
    msg << source << ": compliance needs link masses: no <inertial> with a "
        << "mass > 0 on links ";
    for (size_t k = 0; k < without.size(); ++k) {
      msg << (k ? ", " : "") << without[k];
    }
    msg << " (add them from the robot's datasheet)";
    if (error) *error = msg.str();
    return false;
  }
  return true;
}

bool LoadUrdfInertials(const std::string& path, const UrdfChainOptions& options,
                       GravityModel* gravity, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = path + ": cannot open";
    return false;
  }
  std::ostringstream xml;
  xml << in.rdbuf();
  return ParseUrdfInertials(xml.str(), path, options, gravity, error);
}

}  // namespace activecal
