// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal: kinematic calibration of serial robot arms.
//
// RobotModel describes a serial arm for calibration: a base frame, one link
// per joint, a fixed tip transform, and one or more measured points
// (markers) on the end effector. It holds the structure (conventions, joint
// types, joint limits, URDF joint origins and axes, which parameters are
// free) and the nominal parameter values; the kinematics (kinematics.h) take
// any parameter vector, so the same model serves the nominal, the true
// (simulated) and the identified values.
//
// Parameters are grouped in blocks, one per physical group, in this order:
//
//   block 0              the base frame "B"
//   block 1 .. n         the links, one per joint (named after the joint)
//   block n + 1 .. n + K the markers "tool", "marker2", ...
//
// A block's entries depend on its convention (BlockParameterName):
//
//   standard_dh, modified_dh, hayati (6):
//     gamma  joint offset (rad): theta = gain * q + gamma (revolute)
//     alpha  link twist (rad)
//     a      link length (m)
//     d      link offset (m): d + gain * q for a prismatic joint
//     beta   Hayati twist about the new y axis (rad); Hayati links only
//     gain   joint gain (dimensionless), scales the joint reading q
//   urdf (8): a URDF joint: its nominal origin (translation and rotation
//     matrix) and axis are structure; the parameters correct them:
//     x, y, z     translation (m) applied after the nominal origin, in the
//                 joint's frame
//     rx, ry, rz  rotation Rz(rz) Ry(ry) Rx(rx) (rad) applied after that
//     offset      joint offset: the motion is gain * q + offset about
//                 (revolute, rad) or along (prismatic, m) the axis
//     gain        joint gain (dimensionless)
//   frame (6, the base only): a rigid 6-DOF transform, the registration of
//     the robot's base in the measuring device's frame:
//     x, y, z     translation (m); rx, ry, rz rotation Rz(rz) Ry(ry) Rx(rx)
//   marker (6): the measured point (x, y, z) in metres in the tip frame,
//     then the orientation of the measured target frame relative to the tip
//     frame as fixed-axis angles (rx, ry, rz) in radians:
//     R = Rz(rz) Ry(ry) Rx(rx). Only 6D pose measurements see rx, ry, rz.
//
// The tip frame is the last link's frame followed by the fixed transform
// `tip` (identity for DH models; for a URDF chain the fixed joints after the
// last moving joint). Units are metres and radians throughout.
//
// The full parameter vector concatenates the blocks; the free parameters are
// the entries marked free, taken in that same order. Jacobian columns,
// estimates and standard deviations use the free-parameter order.

#ifndef ACTIVECAL_CORE_ROBOT_MODEL_H_
#define ACTIVECAL_CORE_ROBOT_MODEL_H_

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <vector>

namespace activecal {

// How a link's frame follows the previous one.
enum class LinkConvention {
  // Standard (distal) Denavit-Hartenberg: Rz(theta) Tz(d) Tx(a) Rx(alpha).
  kStandardDH,
  // Modified (proximal, Craig) DH: Rx(alpha) Tx(a) Rz(theta) Tz(d).
  kModifiedDH,
  // Hayati-Mirmirani, for nearly parallel consecutive axes:
  // Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta); d is normally held at 0.
  kHayati,
  // A URDF joint: Origin(xyz, rotation) Correction(x..rz) Motion(axis,
  // offset + gain * q).
  kUrdf,
  // A rigid 6-DOF frame (the base only): Trans(x, y, z) Rz Ry Rx.
  kFrame,
};

enum class JointType {
  kRevolute,   // the joint reading q is an angle (rad)
  kPrismatic,  // the joint reading q is a length (m)
  kFixed,      // no joint: the base frame
};

// The largest block (a URDF joint's).
inline constexpr int kMaxBlockSize = 8;
// A marker block: x, y, z, rx, ry, rz.
inline constexpr int kMarkerBlockSize = 6;

// Index of each value inside a DH-family block (standard, modified, Hayati).
enum LinkParameter : int {
  kGamma = 0,
  kAlpha = 1,
  kA = 2,
  kD = 3,
  kBeta = 4,
  kGain = 5,
};

// Index of each value inside a URDF-joint block.
enum UrdfParameter : int {
  kUrdfX = 0,
  kUrdfY = 1,
  kUrdfZ = 2,
  kUrdfRx = 3,
  kUrdfRy = 4,
  kUrdfRz = 5,
  kUrdfOffset = 6,
  kUrdfGain = 7,
};

// What a parameter measures, for units and priors.
enum class ParameterKind { kLength, kAngle, kGain };

// Number of entries of a link block of this convention.
int LinkBlockSize(LinkConvention convention);
// Name of entry `index` of a link block of this convention: "gamma", "alpha",
// "a", "d", "beta", "gain"; "x" ... "rz", "offset", "gain"; "x" ... "rz".
const char* LinkParameterName(LinkConvention convention, int index);
ParameterKind LinkParameterKind(LinkConvention convention, JointType joint,
                                int index);
// Name of a marker-block entry: "x", "y", "z", "rx", "ry", "rz".
const char* MarkerParameterName(int index);
const char* LinkConventionName(LinkConvention convention);
const char* JointTypeName(JointType type);
// "m", "rad" or "1".
const char* ParameterKindUnit(ParameterKind kind);

struct Link {
  std::string name;
  LinkConvention convention = LinkConvention::kStandardDH;
  JointType joint_type = JointType::kRevolute;
  // Joint range, in radians (revolute) or metres (prismatic), both ends
  // included. Unused for the base.
  double joint_min = -std::numeric_limits<double>::infinity();
  double joint_max = std::numeric_limits<double>::infinity();
  // Which entries of the block are identified (the first
  // LinkBlockSize(convention) are used).
  std::array<bool, kMaxBlockSize> free{};
  // kUrdf only: the nominal origin of the joint frame in the previous
  // link's frame, a point x of the joint frame being origin_rotation * x +
  // origin_xyz there, and the unit joint axis in the joint frame. The
  // rotation is held as a matrix (a proper rotation: orthonormal, det +1),
  // never as angles: a URDF's rpy="r p y" is Rz(y) Ry(p) Rx(r), read from
  // urdfdom's quaternion, and converted back to angles only to write a file
  // (RotationToRpy, RotationToShortRpy), so that origins at pitch +-90 deg
  // keep their rotation.
  Eigen::Vector3d origin_xyz = Eigen::Vector3d::Zero();
  Eigen::Matrix3d origin_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
};

// A measured point on the end effector (a retro-reflector, a mocap marker,
// a target frame), with its own parameter block.
struct Marker {
  std::string name = "tool";
  std::array<bool, kMarkerBlockSize> free{};
};

// A fixed rigid transform (structure, not parameters).
struct FixedTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  bool IsIdentity() const {
    return rotation == Eigen::Matrix3d::Identity() && translation.isZero(0);
  }
};

struct RobotModel {
  std::string name;
  Link base;                // joint_type kFixed
  std::vector<Link> links;  // one per joint, base to tool
  // From the last link's frame to the tip frame the markers are given in.
  FixedTransform tip;
  // At least one; the first is the default of every measurement.
  std::vector<Marker> markers = {Marker()};
  // Nominal values of all parameters, in block order (num_parameters()).
  Eigen::VectorXd nominal;

  int num_joints() const { return static_cast<int>(links.size()); }
  int num_markers() const { return static_cast<int>(markers.size()); }
  int num_blocks() const { return num_joints() + 1 + num_markers(); }
  // The block of marker k (0-based).
  int marker_block(int marker) const { return num_joints() + 1 + marker; }
  bool is_marker_block(int block) const { return block > num_joints(); }
  int num_parameters() const;
  int block_size(int block) const;
  int block_offset(int block) const;
  // The block holding a parameter (index into the full vector), and the
  // parameter's position inside it.
  int BlockOf(int parameter_index, int* within = nullptr) const;
  // "B", the link's name, or the marker's name.
  std::string block_name(int block) const;
  // The link of a link block (0: base, 1..n: links).
  const Link& link(int block) const {
    return block == 0 ? base : links[block - 1];
  }

  bool IsFree(int parameter_index) const;
  // Marks a parameter (index into the full vector) free or fixed.
  void SetFree(int parameter_index, bool free);
  ParameterKind Kind(int parameter_index) const;
  // Unit of a parameter (index into the full vector): "rad", "m" or "1"
  // (a gain).
  const char* ParameterUnit(int parameter_index) const;
  // Name of entry `within` of a block: "gamma", "x", "offset", ...
  const char* BlockParameterName(int block, int within) const;
  // Index into the full vector of a parameter name such as "L2.beta", or -1.
  int ParameterIndex(const std::string& parameter_name) const;
  // Index of a marker by name, or by its 1-based number ("2"); -1 if none.
  int MarkerIndex(const std::string& name_or_number) const;
  int num_free() const;
  // Indices into the full parameter vector of the free parameters.
  std::vector<int> FreeParameterIndices() const;
  // "B.gamma", "L2.beta", "tool.x", ... for every parameter.
  std::vector<std::string> ParameterNames() const;
  std::vector<std::string> FreeParameterNames() const;

  // Checks the structure and the nominal values. On failure returns false
  // and says what is wrong in *error.
  bool Validate(std::string* error) const;

  // Checks a full parameter vector: size and finiteness.
  bool CheckParameters(const Eigen::VectorXd& parameters,
                       std::string* error) const;
  // Checks one joint configuration: size, finiteness and joint ranges.
  // Joint readings (measured, not planned) may lie beyond a range by up to
  // tolerance_rad (revolute) or tolerance_m (prismatic); the message then
  // says so.
  bool CheckJointValues(const Eigen::VectorXd& q, std::string* error,
                        double tolerance_rad = 0.0,
                        double tolerance_m = 0.0) const;
  // How far q lies beyond joint `joint`'s (0-based) range, in rad or m: 0
  // inside it or within a few ulps of an end (lattice end points).
  double JointRangeExcess(int joint, double q) const;
};

// The nominal values of a fresh block: zeros, gains 1.
void DefaultBlockValues(const RobotModel& model, int block, double* values);

// Free parameters of a full vector, in free-parameter order.
Eigen::VectorXd ExtractFree(const RobotModel& model,
                            const Eigen::VectorXd& parameters);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_ROBOT_MODEL_H_
