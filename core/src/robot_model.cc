// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/robot_model.h"

#include <glog/logging.h>

#include <Eigen/LU>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/validation.h"

namespace activecal {
namespace {

// A proper rotation to rounding: orthonormal and of determinant +1.
bool IsRotation(const Eigen::Matrix3d& R) {
  return R.allFinite() &&
         (R.transpose() * R - Eigen::Matrix3d::Identity())
                 .cwiseAbs()
                 .maxCoeff() <= 1e-9 &&
         R.determinant() > 0.0;
}

// The largest entry of |RpyRotation(angles * unit) - R|.
double RpyError(const Eigen::Vector3d& angles, double unit,
                const Eigen::Matrix3d& R) {
  const Eigen::Vector3d a = angles * unit;
  return (RpyRotation(a[0], a[1], a[2]) - R).cwiseAbs().maxCoeff();
}

}  // namespace

int LinkBlockSize(LinkConvention convention) {
  return convention == LinkConvention::kUrdf ? 8 : 6;
}

const char* LinkParameterName(LinkConvention convention, int index) {
  static const char* const kDh[6] = {"gamma", "alpha", "a",
                                     "d",     "beta",  "gain"};
  static const char* const kUrdf[8] = {"x",  "y",  "z",      "rx",
                                       "ry", "rz", "offset", "gain"};
  switch (convention) {
    case LinkConvention::kUrdf:
      return kUrdf[index];
    case LinkConvention::kFrame:
      return MarkerParameterName(index);
    default:
      return kDh[index];
  }
}

ParameterKind LinkParameterKind(LinkConvention convention, JointType joint,
                                int index) {
  switch (convention) {
    case LinkConvention::kUrdf:
      if (index == kUrdfGain) return ParameterKind::kGain;
      if (index == kUrdfOffset) {
        return joint == JointType::kPrismatic ? ParameterKind::kLength
                                              : ParameterKind::kAngle;
      }
      return index < 3 ? ParameterKind::kLength : ParameterKind::kAngle;
    case LinkConvention::kFrame:
      return index < 3 ? ParameterKind::kLength : ParameterKind::kAngle;
    default:
      switch (index) {
        case kA:
        case kD:
          return ParameterKind::kLength;
        case kGain:
          return ParameterKind::kGain;
        default:
          return ParameterKind::kAngle;
      }
  }
}

const char* MarkerParameterName(int index) {
  static const char* const kNames[kMarkerBlockSize] = {"x",  "y",  "z",
                                                       "rx", "ry", "rz"};
  return kNames[index];
}

const char* ParameterKindUnit(ParameterKind kind) {
  constexpr const char* kNames[] = {"m", "rad", "1"};
  return EnumToString(kNames, kind, "?");
}

const char* LinkConventionName(LinkConvention convention) {
  constexpr const char* kNames[] = {"standard_dh", "modified_dh", "hayati",
                                    "urdf", "frame"};
  return EnumToString(kNames, convention);
}

const char* JointTypeName(JointType type) {
  constexpr const char* kNames[] = {"revolute", "prismatic", "fixed"};
  return EnumToString(kNames, type);
}

int RobotModel::num_parameters() const { return block_offset(num_blocks()); }

int RobotModel::block_size(int block) const {
  return is_marker_block(block) ? kMarkerBlockSize
                                : LinkBlockSize(link(block).convention);
}

int RobotModel::block_offset(int block) const {
  int offset = 0;
  for (int b = 0; b < block; ++b) offset += block_size(b);
  return offset;
}

int RobotModel::BlockOf(int parameter_index, int* within) const {
  int offset = 0;
  for (int b = 0; b < num_blocks(); ++b) {
    const int size = block_size(b);
    if (parameter_index < offset + size) {
      if (within) *within = parameter_index - offset;
      return b;
    }
    offset += size;
  }
  return -1;
}

std::string RobotModel::block_name(int block) const {
  if (is_marker_block(block)) {
    const Marker& m = markers[block - num_joints() - 1];
    if (!m.name.empty()) return m.name;
    return block == marker_block(0)
               ? "tool"
               : "marker" + std::to_string(block - num_joints());
  }
  if (block == 0) return base.name.empty() ? "B" : base.name;
  const Link& l = links[block - 1];
  return l.name.empty() ? "L" + std::to_string(block) : l.name;
}

const char* RobotModel::BlockParameterName(int block, int within) const {
  return is_marker_block(block)
             ? MarkerParameterName(within)
             : LinkParameterName(link(block).convention, within);
}

bool RobotModel::IsFree(int parameter_index) const {
  int within = 0;
  const int block = BlockOf(parameter_index, &within);
  if (block < 0) return false;
  if (is_marker_block(block)) {
    return markers[block - num_joints() - 1].free[within];
  }
  return link(block).free[within];
}

void RobotModel::SetFree(int parameter_index, bool free) {
  int within = 0;
  const int block = BlockOf(parameter_index, &within);
  if (block < 0) return;
  if (is_marker_block(block)) {
    markers[block - num_joints() - 1].free[within] = free;
  } else if (block == 0) {
    base.free[within] = free;
  } else {
    links[block - 1].free[within] = free;
  }
}

ParameterKind RobotModel::Kind(int parameter_index) const {
  int within = 0;
  const int block = BlockOf(parameter_index, &within);
  CHECK_GE(block, 0) << "parameter index " << parameter_index
                     << " is outside the model's " << num_parameters();
  if (is_marker_block(block)) {
    return within < 3 ? ParameterKind::kLength : ParameterKind::kAngle;
  }
  const Link& l = link(block);
  return LinkParameterKind(l.convention, l.joint_type, within);
}

const char* RobotModel::ParameterUnit(int parameter_index) const {
  return ParameterKindUnit(Kind(parameter_index));
}

int RobotModel::ParameterIndex(const std::string& parameter_name) const {
  const std::vector<std::string> names = ParameterNames();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == parameter_name) return static_cast<int>(i);
  }
  return -1;
}

int RobotModel::MarkerIndex(const std::string& name_or_number) const {
  for (int k = 0; k < num_markers(); ++k) {
    if (block_name(marker_block(k)) == name_or_number) return k;
  }
  if (!name_or_number.empty() &&
      name_or_number.find_first_not_of("0123456789") == std::string::npos &&
      name_or_number.size() < 6) {
    const int k = std::stoi(name_or_number) - 1;
    if (k >= 0 && k < num_markers()) return k;
  }
  return -1;
}

int RobotModel::num_free() const {
  return static_cast<int>(FreeParameterIndices().size());
}

std::vector<int> RobotModel::FreeParameterIndices() const {
  std::vector<int> indices;
  int offset = 0;
  for (int b = 0; b < num_blocks(); ++b) {
    const int size = block_size(b);
    for (int j = 0; j < size; ++j) {
      const bool free = is_marker_block(b)
                            ? markers[b - num_joints() - 1].free[j]
                            : link(b).free[j];
      if (free) indices.push_back(offset + j);
    }
    offset += size;
  }
  return indices;
}

std::vector<std::string> RobotModel::ParameterNames() const {
  std::vector<std::string> names;
  for (int b = 0; b < num_blocks(); ++b) {
    for (int j = 0; j < block_size(b); ++j) {
      names.push_back(block_name(b) + "." + BlockParameterName(b, j));
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

void DefaultBlockValues(const RobotModel& model, int block, double* values) {
  const int size = model.block_size(block);
  std::fill(values, values + size, 0.0);
  if (model.is_marker_block(block)) return;
  const LinkConvention c = model.link(block).convention;
  if (c == LinkConvention::kUrdf) {
    values[kUrdfGain] = 1.0;
  } else if (c != LinkConvention::kFrame) {
    values[kGain] = 1.0;
  }
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
    auto dh_family = [](LinkConvention c) {
      return c != LinkConvention::kUrdf && c != LinkConvention::kFrame;
    };
    for (int b = 0; b <= num_joints() && msg.tellp() == 0; ++b) {
      const Link& l = link(b);
      const int offset = block_offset(b);
      if (b > 0 && l.joint_type == JointType::kFixed) {
        msg << "link '" << block_name(b) << "': joint type 'fixed' is only "
            << "allowed for the base";
      } else if (b == 0 && l.convention == LinkConvention::kUrdf) {
        msg << "base '" << block_name(0) << "': convention 'urdf' is for "
            << "joints; a base is 'frame' or a DH convention";
      } else if (b > 0 && l.convention == LinkConvention::kFrame) {
        msg << "link '" << block_name(b) << "': convention 'frame' is only "
            << "allowed for the base";
      } else if (dh_family(l.convention) &&
                 l.convention != LinkConvention::kHayati &&
                 (l.free[kBeta] || nominal[offset + kBeta] != 0.0)) {
        msg << "link '" << block_name(b) << "': beta is a Hayati parameter, "
            << "but the link's convention is '"
            << LinkConventionName(l.convention)
            << "' (beta must be 0 and not free)";
      } else if (b == 0 && dh_family(l.convention) && l.free[kGain]) {
        msg << "base '" << block_name(0) << "': has no joint, so no gain to "
            << "identify";
      } else if (b > 0 && !(l.joint_min <= l.joint_max)) {
        msg << "link '" << block_name(b) << "': joint range [" << l.joint_min
            << ", " << l.joint_max << "] is empty or not a number";
      } else if (l.convention == LinkConvention::kUrdf &&
                 (!l.origin_xyz.allFinite() || !l.axis.allFinite() ||
                  std::abs(l.axis.norm() - 1.0) > 1e-9)) {
        msg << "link '" << block_name(b) << "': the URDF origin must be "
            << "finite and the axis a unit vector";
      } else if (l.convention == LinkConvention::kUrdf &&
                 !IsRotation(l.origin_rotation)) {
        msg << "link '" << block_name(b) << "': the URDF origin's rotation "
            << "is not a rotation matrix (orthonormal, determinant +1)";
      } else {
        for (int j = LinkBlockSize(l.convention); j < kMaxBlockSize; ++j) {
          if (l.free[j]) {
            msg << "link '" << block_name(b) << "': free flag " << j
                << " is beyond the block's " << LinkBlockSize(l.convention)
                << " entries";
            break;
          }
        }
      }
    }
    if (msg.tellp() == 0 && markers.empty()) {
      msg << "robot '" << name << "': no markers (measured points)";
    }
    for (int k = 0; k < num_markers() && msg.tellp() == 0; ++k) {
      const std::string& n = markers[k].name;
      if (!n.empty() &&
          n.find_first_not_of("0123456789") == std::string::npos) {
        msg << "marker '" << n << "': a marker name must not be a number "
            << "(numbers name markers by position: 1, 2, ...)";
      }
    }
    if (msg.tellp() == 0 &&
        (!tip.rotation.allFinite() || !tip.translation.allFinite())) {
      msg << "robot '" << name << "': the tip transform is not finite";
    }
    if (msg.tellp() == 0) {
      for (int a = 0; a < num_blocks() && msg.tellp() == 0; ++a) {
        for (int b = a + 1; b < num_blocks(); ++b) {
          if (block_name(a) == block_name(b)) {
            msg << "robot '" << name << "': two parameter blocks are named '"
                << block_name(a) << "'";
            break;
          }
        }
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
  return FinishValidation(msg, error);
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
  return FinishValidation(msg, error);
}

double RobotModel::JointRangeExcess(int joint, double q) const {
  const Link& l = links[joint];
  const double slack = 1e-9 * std::max(1.0, std::max(std::abs(l.joint_min),
                                                     std::abs(l.joint_max)));
  const double excess = q > l.joint_max ? q - l.joint_max : l.joint_min - q;
  return excess > slack ? excess : 0.0;
}

bool RobotModel::CheckJointValues(const Eigen::VectorXd& q, std::string* error,
                                  double tolerance_rad,
                                  double tolerance_m) const {
  std::ostringstream msg;
  if (q.size() != num_joints()) {
    msg << "expected " << num_joints() << " joint values, got " << q.size();
  } else {
    for (int i = 0; i < q.size(); ++i) {
      const Link& l = links[i];
      if (!std::isfinite(q[i])) {
        msg << "joint " << i + 1 << " (" << block_name(i + 1)
            << ") value is not finite (" << q[i] << ")";
        break;
      }
      const bool revolute = l.joint_type == JointType::kRevolute;
      const double tolerance = revolute ? tolerance_rad : tolerance_m;
      if (JointRangeExcess(i, q[i]) <= tolerance) continue;
      msg << "joint " << i + 1 << " (" << block_name(i + 1) << ") value "
          << q[i];
      const double scale = revolute ? 180.0 / M_PI : 1.0;
      const char* unit = revolute ? "deg" : "m";
      if (revolute) {
        msg << " rad (" << q[i] * scale << " deg) is outside its range [";
      } else {
        msg << " m is outside its range [";
      }
      msg << l.joint_min * scale << ", " << l.joint_max * scale << "] " << unit;
      if (tolerance > 0) {
        msg << " by more than the " << tolerance * scale << " " << unit
            << " a measured joint may lie beyond it";
      }
      break;
    }
  }
  return FinishValidation(msg, error);
}

Eigen::Vector3d RotationToRpy(const Eigen::Matrix3d& R) {
  // Yaw first (at gimbal lock only yaw -+ roll is defined: roll = 0), then
  // roll and pitch from Rz(-yaw) R = Ry(pitch) Rx(roll), whose entries stay
  // well conditioned near pitch = +-pi/2 (atan2 of the small entries
  // R21, R22 alone would turn their rounding into radian-size errors).
  const double cp = std::hypot(R(0, 0), R(1, 0));
  const double yaw =
      cp < 1e-15 ? std::atan2(-R(0, 1), R(1, 1)) : std::atan2(R(1, 0), R(0, 0));
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double roll =
      std::atan2(s * R(0, 2) - c * R(1, 2), c * R(1, 1) - s * R(0, 1));
  const double pitch = std::atan2(-R(2, 0), c * R(0, 0) + s * R(1, 0));
  return Eigen::Vector3d(roll, pitch, yaw);
}

Eigen::Vector3d RotationToShortRpy(const Eigen::Matrix3d& R, double unit) {
  // The angles, and those of the other branch (pitch beyond +-pi/2: R =
  // Rz(yaw + pi) Ry(pi - pitch) Rx(roll + pi)), wrapped to (-pi, pi].
  const Eigen::Vector3d rpy = RotationToRpy(R);
  auto wrap = [](double a) {
    return a > M_PI ? a - 2 * M_PI : (a <= -M_PI ? a + 2 * M_PI : a);
  };
  const Eigen::Vector3d branches[2] = {
      rpy / unit, Eigen::Vector3d(wrap(rpy[0] + M_PI),
                                  wrap((rpy[1] < 0 ? -M_PI : M_PI) - rpy[1]),
                                  wrap(rpy[2] + M_PI)) /
                      unit};
  // The fewest decimal places at which the angles of either branch read
  // back to exactly R (a rotation read from short decimals gets them back,
  // whichever way they were written).
  for (const Eigen::Vector3d& raw : branches) {
    for (int places = 0; places <= 20; ++places) {
      Eigen::Vector3d rounded;
      for (int k = 0; k < 3; ++k) {
        // Locale-independent decimal text, and back.
        char text[64];
        const std::to_chars_result end =
            std::to_chars(text, text + sizeof(text), raw[k],
                          std::chars_format::fixed, places);
        double value = raw[k];
        std::from_chars(text, end.ptr, value);
        rounded[k] = value + 0.0;  // no -0
      }
      if (RpyError(rounded, unit, R) == 0.0) return rounded;
    }
  }
  return branches[0];
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
                              const Eigen::VectorXd& q, int marker) {
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  return MeasuredPoint<double>(model, blocks.data(), q.data(), marker);
}

void TargetFrame(const RobotModel& model, const Eigen::VectorXd& parameters,
                 const Eigen::VectorXd& q, Eigen::Matrix3d* R,
                 Eigen::Vector3d* t, int marker) {
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  TargetFrame<double>(model, blocks.data(), q.data(), R, t, marker);
}

}  // namespace activecal
