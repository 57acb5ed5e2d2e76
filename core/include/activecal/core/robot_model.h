// activecal: kinematic calibration of serial robot arms.
//
// RobotModel describes a serial arm for calibration: a base frame, one link
// per joint, and a tool point. It holds the structure (conventions, joint
// types, joint limits, which parameters are free) and the nominal parameter
// values; the kinematics (kinematics.h) take any parameter vector, so the
// same model serves the nominal, the true (simulated) and the identified
// values.
//
// Parameters are grouped in blocks, one per physical group, in this order:
//
//   block 0            the base frame "B"          kLinkBlockSize values
//   block 1 .. n       the links "L1" .. "Ln"      kLinkBlockSize values each
//   block n + 1        the tool "tool"             kToolBlockSize values
//
// A link block holds, in this order (LinkParameter):
//
//   gamma  joint offset (rad): theta = gain * q + gamma for a revolute joint
//   alpha  link twist (rad)
//   a      link length (m)
//   d      link offset (m): d + gain * q for a prismatic joint
//   beta   Hayati twist about the new y axis (rad); Hayati links only
//   gain   joint gain (dimensionless), scales the joint reading q
//
// The tool block is the measured point (x, y, z) in metres, in the last
// link's frame, then the orientation of the measured target frame relative
// to the last link's frame as fixed-axis angles (rx, ry, rz) in radians:
// R_tool = Rz(rz) Ry(ry) Rx(rx). Only 6D pose measurements see rx, ry, rz.
// Units are metres and radians throughout.
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
};

enum class JointType {
  kRevolute,   // the joint reading q is an angle (rad) added to theta
  kPrismatic,  // the joint reading q is a length (m) added to d
  kFixed,      // no joint: the base frame
};

inline constexpr int kLinkBlockSize = 6;
inline constexpr int kToolBlockSize = 6;

// Index of each value inside a link block.
enum LinkParameter : int {
  kGamma = 0,
  kAlpha = 1,
  kA = 2,
  kD = 3,
  kBeta = 4,
  kGain = 5,
};

// Name of a link-block entry: "gamma", "alpha", "a", "d", "beta", "gain".
const char* LinkParameterName(int index);
// Name of a tool-block entry: "x", "y", "z", "rx", "ry", "rz".
const char* ToolParameterName(int index);
const char* LinkConventionName(LinkConvention convention);
const char* JointTypeName(JointType type);

struct Link {
  std::string name;
  LinkConvention convention = LinkConvention::kStandardDH;
  JointType joint_type = JointType::kRevolute;
  // Joint range, in radians (revolute) or metres (prismatic), both ends
  // included. Unused for the base.
  double joint_min = -std::numeric_limits<double>::infinity();
  double joint_max = std::numeric_limits<double>::infinity();
  // Which entries of the block are identified.
  std::array<bool, kLinkBlockSize> free{};
};

struct RobotModel {
  std::string name;
  Link base;                // joint_type must be kFixed
  std::vector<Link> links;  // one per joint, base to tool
  std::array<bool, kToolBlockSize> tool_free{};
  // Nominal values of all parameters, in block order (num_parameters()).
  Eigen::VectorXd nominal;

  int num_joints() const { return static_cast<int>(links.size()); }
  int num_blocks() const { return num_joints() + 2; }
  int num_parameters() const {
    return kLinkBlockSize * (num_joints() + 1) + kToolBlockSize;
  }
  int block_size(int block) const {
    return block == num_joints() + 1 ? kToolBlockSize : kLinkBlockSize;
  }
  int block_offset(int block) const { return kLinkBlockSize * block; }
  // "B", the link's name, or "tool".
  std::string block_name(int block) const;
  // The link of a link block (0: base, 1..n: links).
  const Link& link(int block) const {
    return block == 0 ? base : links[block - 1];
  }

  bool IsFree(int parameter_index) const;
  // Marks a parameter (index into the full vector) free or fixed.
  void SetFree(int parameter_index, bool free);
  // Unit of a parameter (index into the full vector): "rad", "m" or "1"
  // (a gain).
  const char* ParameterUnit(int parameter_index) const;
  // Index into the full vector of a parameter name such as "L2.beta", or -1.
  int ParameterIndex(const std::string& parameter_name) const;
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
  bool CheckJointValues(const Eigen::VectorXd& q, std::string* error) const;
};

// Free parameters of a full vector, in free-parameter order.
Eigen::VectorXd ExtractFree(const RobotModel& model,
                            const Eigen::VectorXd& parameters);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_ROBOT_MODEL_H_
