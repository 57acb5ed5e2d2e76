// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/urdf_robot.h"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "activecal/io/csv_files.h"

namespace activecal {
namespace {

struct Chain {
  std::string robot_name;
  std::string base_link, tip_link;
  std::vector<urdf::JointConstSharedPtr> joints;  // base to tip
};

Eigen::Matrix3d Rotation(const urdf::Rotation& r) {
  return Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
}

Eigen::Vector3d Vec(const urdf::Vector3& v) {
  return Eigen::Vector3d(v.x, v.y, v.z);
}

// Collects urdfdom's console_bridge errors while it lives (one parse at a
// time: console_bridge's handler is process-wide).
class UrdfdomErrors : public console_bridge::OutputHandler {
 public:
  UrdfdomErrors() {
    Mutex().lock();
    level_ = console_bridge::getLogLevel();
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_ERROR);
    console_bridge::useOutputHandler(this);
  }
  ~UrdfdomErrors() override {
    console_bridge::restorePreviousOutputHandler();
    console_bridge::setLogLevel(level_);
    Mutex().unlock();
  }
  void log(const std::string& text, console_bridge::LogLevel level, const char*,
           int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && first_.empty()) {
      first_ = text;
      while (!first_.empty() &&
             std::isspace(static_cast<unsigned char>(first_.back()))) {
        first_.pop_back();
      }
      // One line.
      for (char& c : first_) {
        if (c == '\n' || c == '\r') c = ' ';
      }
    }
  }
  const std::string& first() const { return first_; }

 private:
  static std::mutex& Mutex() {
    static std::mutex mutex;
    return mutex;
  }
  console_bridge::LogLevel level_;
  std::string first_;
};

bool Moving(const urdf::Joint& j) {
  return j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS ||
         j.type == urdf::Joint::PRISMATIC;
}

const char* TypeName(int type) {
  switch (type) {
    case urdf::Joint::FLOATING:
      return "floating";
    case urdf::Joint::PLANAR:
      return "planar";
    default:
      return "unknown";
  }
}

// Collects the leaves below `link`, in name order.
void Leaves(const urdf::Link& link, std::vector<std::string>* out) {
  if (link.child_links.empty()) {
    out->push_back(link.name);
    return;
  }
  for (const urdf::LinkSharedPtr& c : link.child_links) Leaves(*c, out);
}

bool FindChain(const std::string& xml, const std::string& source,
               const UrdfChainOptions& options, Chain* chain,
               std::string* error) {
  auto fail = [&](const std::string& what) {
    if (error) *error = source + ": " + what;
    return false;
  };
  // urdfdom reports through console_bridge on stderr: its first error is
  // kept for our one-line message instead.
  UrdfdomErrors errors;
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    return fail(std::string("not a valid URDF: ") + e.what());
  }
  if (!model || !model->getRoot()) {
    return fail("not a valid URDF: " +
                (errors.first().empty()
                     ? std::string("malformed XML, a missing <robot> "
                                   "element, or links and joints that do "
                                   "not form one tree")
                     : errors.first()));
  }
  chain->robot_name = model->getName();
  chain->base_link =
      options.base_link.empty() ? model->getRoot()->name : options.base_link;
  const urdf::LinkConstSharedPtr base = model->getLink(chain->base_link);
  if (!base) return fail("no link named '" + chain->base_link + "'");
  if (options.tip_link.empty()) {
    std::vector<std::string> leaves;
    Leaves(*base, &leaves);
    std::sort(leaves.begin(), leaves.end());
    if (leaves.size() != 1) {
      std::string list;
      for (const std::string& l : leaves)
        list += (list.empty() ? "" : ", ") + l;
      return fail("the tree below '" + chain->base_link + "' has " +
                  std::to_string(leaves.size()) + " leaves (" + list +
                  "): choose the chain's end with --tip_link");
    }
    chain->tip_link = leaves[0];
  } else {
    chain->tip_link = options.tip_link;
  }
  urdf::LinkConstSharedPtr link = model->getLink(chain->tip_link);
  if (!link) return fail("no link named '" + chain->tip_link + "'");
  std::vector<urdf::JointConstSharedPtr> up;
  while (link->name != chain->base_link) {
    if (!link->parent_joint) {
      return fail("link '" + chain->tip_link + "' is not below link '" +
                  chain->base_link +
                  "': the two do not bound a chain (swap --base_link and "
                  "--tip_link?)");
    }
    up.push_back(link->parent_joint);
    link = model->getLink(link->parent_joint->parent_link_name);
    if (!link) return fail("a joint names a parent link that is not there");
  }
  chain->joints.assign(up.rbegin(), up.rend());
  for (const urdf::JointConstSharedPtr& j : chain->joints) {
    if (j->type == urdf::Joint::FLOATING || j->type == urdf::Joint::PLANAR) {
      return fail("joint '" + j->name + "' on the chain is " +
                  TypeName(j->type) +
                  ": only revolute, continuous, prismatic and fixed joints "
                  "can be calibrated");
    }
    if (j->type == urdf::Joint::UNKNOWN) {
      return fail("joint '" + j->name + "' has an unknown type");
    }
    if (j->mimic && Moving(*j)) {
      return fail("joint '" + j->name + "' mimics joint '" +
                  j->mimic->joint_name +
                  "': mimic joints are not supported in a calibrated chain");
    }
  }
  return true;
}

}  // namespace

bool UrdfChainJoints(const std::string& xml, const std::string& source,
                     const UrdfChainOptions& options,
                     std::vector<UrdfChainJoint>* joints, std::string* error) {
  Chain chain;
  if (!FindChain(xml, source, options, &chain, error)) return false;
  joints->clear();
  for (const urdf::JointConstSharedPtr& j : chain.joints) {
    UrdfChainJoint out;
    out.name = j->name;
    out.moving = Moving(*j);
    out.parent_link = j->parent_link_name;
    out.child_link = j->child_link_name;
    const urdf::Pose& o = j->parent_to_joint_origin_transform;
    out.xyz = Vec(o.position);
    out.rotation = Rotation(o.rotation);
    joints->push_back(out);
  }
  return true;
}

bool ParseUrdfRobot(const std::string& xml, const std::string& source,
                    const UrdfChainOptions& options, RobotDescription* robot,
                    std::string* error) {
  Chain chain;
  if (!FindChain(xml, source, options, &chain, error)) return false;
  RobotModel m;
  m.name = chain.robot_name;
  m.base.name = "B";
  m.base.convention = LinkConvention::kFrame;
  m.base.joint_type = JointType::kFixed;
  // The fixed transform accumulated since the last moving joint. Rotations
  // are read as the quaternions urdfdom holds, never through its getRPY
  // (which snaps a pitch within 0.26 deg of +-90 deg to +-90 deg).
  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();
  for (const urdf::JointConstSharedPtr& j : chain.joints) {
    const urdf::Pose& o = j->parent_to_joint_origin_transform;
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    origin.linear() = Rotation(o.rotation);
    origin.translation() = Vec(o.position);
    pending = pending * origin;
    if (!Moving(*j)) continue;
    Link l;
    l.name = j->name;
    l.convention = LinkConvention::kUrdf;
    l.joint_type = j->type == urdf::Joint::PRISMATIC ? JointType::kPrismatic
                                                     : JointType::kRevolute;
    if (j->type != urdf::Joint::CONTINUOUS && j->limits) {
      l.joint_min = j->limits->lower;
      l.joint_max = j->limits->upper;
    }
    l.origin_xyz = pending.translation();
    l.origin_rotation = pending.linear();
    const Eigen::Vector3d axis = Vec(j->axis);
    if (!(axis.norm() > 0)) {
      if (error) *error = source + ": joint '" + j->name + "' has a zero axis";
      return false;
    }
    l.axis = axis.normalized();
    m.links.push_back(l);
    pending = Eigen::Isometry3d::Identity();
  }
  if (m.links.empty()) {
    if (error) {
      *error = source +
               ": no revolute, continuous or prismatic joint between '" +
               chain.base_link + "' and '" + chain.tip_link + "'";
    }
    return false;
  }
  m.tip.rotation = pending.linear();
  m.tip.translation = pending.translation();
  m.nominal = Eigen::VectorXd::Zero(m.num_parameters());
  for (int b = 0; b < m.num_blocks(); ++b) {
    DefaultBlockValues(m, b, m.nominal.data() + m.block_offset(b));
  }
  std::string why;
  if (!m.Validate(&why)) {
    if (error) *error = source + ": " + why;
    return false;
  }
  robot->model = std::move(m);
  robot->true_parameters.resize(0);
  robot->angle_unit = AngleUnit::kRadian;
  return true;
}

bool LoadUrdfRobot(const std::string& path, const UrdfChainOptions& options,
                   RobotDescription* robot, std::string* error) {
  std::string xml;
  return ReadTextFile(path, &xml, error) &&
         ParseUrdfRobot(xml, path, options, robot, error);
}

}  // namespace activecal
