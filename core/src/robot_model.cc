#include "activecal/core/robot_model.h"

#include <cmath>
#include <sstream>

#include "activecal/core/kinematics.h"

namespace activecal {

const char* LinkParameterName(int index) {
  static const char* const kNames[kLinkBlockSize] = {"gamma", "alpha", "a",
                                                     "d",     "beta",  "gain"};
  return kNames[index];
}

const char* ToolParameterName(int index) {
  static const char* const kNames[kToolBlockSize] = {"x",  "y",  "z",
                                                     "rx", "ry", "rz"};
  return kNames[index];
}

const char* LinkConventionName(LinkConvention convention) {
  switch (convention) {
    case LinkConvention::kStandardDH:
      return "standard_dh";
    case LinkConvention::kModifiedDH:
      return "modified_dh";
    case LinkConvention::kHayati:
      return "hayati";
  }
  return "unknown";
}

const char* JointTypeName(JointType type) {
  switch (type) {
    case JointType::kRevolute:
      return "revolute";
    case JointType::kPrismatic:
      return "prismatic";
    case JointType::kFixed:
      return "fixed";
  }
  return "unknown";
}

std::string RobotModel::block_name(int block) const {
  if (block == num_joints() + 1) return "tool";
  if (block == 0) return base.name.empty() ? "B" : base.name;
  const Link& l = links[block - 1];
  return l.name.empty() ? "L" + std::to_string(block) : l.name;
}

bool RobotModel::IsFree(int parameter_index) const {
  const int block = parameter_index / kLinkBlockSize;
  const int within = parameter_index % kLinkBlockSize;
  if (block == num_joints() + 1) return tool_free[within];
  return link(block).free[within];
}

void RobotModel::SetFree(int parameter_index, bool free) {
  const int block = parameter_index / kLinkBlockSize;
  const int within = parameter_index % kLinkBlockSize;
  if (block == num_joints() + 1) {
    tool_free[within] = free;
  } else if (block == 0) {
    base.free[within] = free;
  } else {
    links[block - 1].free[within] = free;
  }
}

const char* RobotModel::ParameterUnit(int parameter_index) const {
  const int block = parameter_index / kLinkBlockSize;
  const int within = parameter_index % kLinkBlockSize;
  if (block == num_joints() + 1) return within < 3 ? "m" : "rad";
  switch (within) {
    case kA:
    case kD:
      return "m";
    case kGain:
      return "1";
    default:
      return "rad";
  }
}

int RobotModel::ParameterIndex(const std::string& parameter_name) const {
  const std::vector<std::string> names = ParameterNames();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == parameter_name) return static_cast<int>(i);
  }
  return -1;
}

int RobotModel::num_free() const {
  return static_cast<int>(FreeParameterIndices().size());
}

std::vector<int> RobotModel::FreeParameterIndices() const {
  std::vector<int> indices;
  for (int i = 0; i < num_parameters(); ++i) {
    if (IsFree(i)) indices.push_back(i);
  }
  return indices;
}

std::vector<std::string> RobotModel::ParameterNames() const {
  std::vector<std::string> names;
  names.reserve(num_parameters());
  for (int b = 0; b < num_blocks(); ++b) {
    const bool tool = b == num_joints() + 1;
    for (int j = 0; j < block_size(b); ++j) {
      names.push_back(block_name(b) + "." +
                      (tool ? ToolParameterName(j) : LinkParameterName(j)));
    }
  }
  return names;
}

std::vector<std::string> RobotModel::FreeParameterNames() const {
  const std::vector<std::string> all = ParameterNames();
  std::vector<std::string> names;
  for (int i : FreeParameterIndices()) names.push_back(all[i]);
  return names;
}

bool RobotModel::Validate(std::string* error) const {
  std::ostringstream msg;
  if (base.joint_type != JointType::kFixed) {
    msg << "robot '" << name << "': the base frame must have joint type "
        << "'fixed', got '" << JointTypeName(base.joint_type) << "'";
  } else if (links.empty()) {
    msg << "robot '" << name << "': no links";
  } else if (nominal.size() != num_parameters()) {
    msg << "robot '" << name << "': expected " << num_parameters()
        << " nominal parameter values, got " << nominal.size();
  } else {
    for (int b = 0; b <= num_joints() && msg.tellp() == 0; ++b) {
      const Link& l = link(b);
      if (b > 0 && l.joint_type == JointType::kFixed) {
        msg << "link '" << block_name(b) << "': joint type 'fixed' is only "
            << "allowed for the base";
      } else if (l.convention != LinkConvention::kHayati &&
                 (l.free[kBeta] || nominal[block_offset(b) + kBeta] != 0.0)) {
        msg << "link '" << block_name(b) << "': beta is a Hayati parameter, "
            << "but the link's convention is '"
            << LinkConventionName(l.convention)
            << "' (beta must be 0 and not free)";
      } else if (b == 0 && l.free[kGain]) {
        msg << "base '" << block_name(0) << "': has no joint, so no gain to "
            << "identify";
      } else if (b > 0 && !(l.joint_min <= l.joint_max)) {
        msg << "link '" << block_name(b) << "': joint range [" << l.joint_min
            << ", " << l.joint_max << "] is empty or not a number";
      }
    }
    if (msg.tellp() == 0) {
      const std::vector<std::string> names = ParameterNames();
      for (int i = 0; i < num_parameters(); ++i) {
        if (!std::isfinite(nominal[i])) {
          msg << "robot '" << name << "': nominal value of " << names[i]
              << " is not finite (" << nominal[i] << ")";
          break;
        }
      }
    }
  }
  if (msg.tellp() == 0) return true;
  if (error) *error = msg.str();
  return false;
}

bool RobotModel::CheckParameters(const Eigen::VectorXd& parameters,
                                 std::string* error) const {
  std::ostringstream msg;
  if (parameters.size() != num_parameters()) {
    msg << "expected " << num_parameters() << " parameter values, got "
        << parameters.size();
  } else {
    for (int i = 0; i < parameters.size(); ++i) {
      if (!std::isfinite(parameters[i])) {
        msg << "parameter " << ParameterNames()[i] << " is not finite ("
            << parameters[i] << ")";
        break;
      }
    }
  }
  if (msg.tellp() == 0) return true;
  if (error) *error = msg.str();
  return false;
}

bool RobotModel::CheckJointValues(const Eigen::VectorXd& q,
                                  std::string* error) const {
  std::ostringstream msg;
  if (q.size() != num_joints()) {
    msg << "expected " << num_joints() << " joint values, got " << q.size();
  } else {
    // A tolerance of a few ulps lets lattice end points through.
    for (int i = 0; i < q.size(); ++i) {
      const Link& l = links[i];
      const double slack =
          1e-9 *
          std::max(1.0, std::max(std::abs(l.joint_min), std::abs(l.joint_max)));
      if (!std::isfinite(q[i])) {
        msg << "joint " << i + 1 << " (" << block_name(i + 1)
            << ") value is not finite (" << q[i] << ")";
        break;
      }
      if (q[i] < l.joint_min - slack || q[i] > l.joint_max + slack) {
        msg << "joint " << i + 1 << " (" << block_name(i + 1) << ") value "
            << q[i];
        if (l.joint_type == JointType::kRevolute) {
          const double deg = 180.0 / M_PI;
          msg << " rad (" << q[i] * deg << " deg) is outside its range ["
              << l.joint_min * deg << ", " << l.joint_max * deg << "] deg";
        } else {
          msg << " m is outside its range [" << l.joint_min << ", "
              << l.joint_max << "] m";
        }
        break;
      }
    }
  }
  if (msg.tellp() == 0) return true;
  if (error) *error = msg.str();
  return false;
}

Eigen::VectorXd ExtractFree(const RobotModel& model,
                            const Eigen::VectorXd& parameters) {
  const std::vector<int> idx = model.FreeParameterIndices();
  Eigen::VectorXd free(idx.size());
  for (size_t i = 0; i < idx.size(); ++i) free[i] = parameters[idx[i]];
  return free;
}

void ForwardKinematics(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const Eigen::VectorXd& q, Eigen::Matrix3d* R,
                       Eigen::Vector3d* t) {
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  ForwardKinematics<double>(model, blocks.data(), q.data(), R, t);
}

Eigen::Vector3d MeasuredPoint(const RobotModel& model,
                              const Eigen::VectorXd& parameters,
                              const Eigen::VectorXd& q) {
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  return MeasuredPoint<double>(model, blocks.data(), q.data());
}

void TargetFrame(const RobotModel& model, const Eigen::VectorXd& parameters,
                 const Eigen::VectorXd& q, Eigen::Matrix3d* R,
                 Eigen::Vector3d* t) {
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  TargetFrame<double>(model, blocks.data(), q.data(), R, t);
}

}  // namespace activecal
