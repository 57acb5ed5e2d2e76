// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Joint error terms: errors of a joint's motion that depend on the pose, on
// top of the geometric (kinematic) parameters of robot_model.h.
//
//   compliance  the joint deflects under the gravity torque it carries:
//               e_i = c_i * tau_i(q), c_i in rad/(N m) (revolute) or
//               m/N (prismatic), tau_i the torque (force) gravity exerts
//               about (along) joint i's axis, from the links' masses and
//               centres of mass and the payload (GravityModel);
//   harmonics   gear and encoder eccentricity, periodic in the joint angle:
//               e_i = a_ik sin(k q_i) + b_ik cos(k q_i), k = 1..K, in rad
//               (revolute joints only).
//
// The error is added to the joint's motion: a revolute joint turns by
// offset + gain * q + e_i(q) about its axis (a prismatic one moves by that
// along it), e_i the sum of its terms. Each term is one parameter,
// linear in the error: e_i = sum_t theta_t * phi_t(q), with the feature
// phi_t = tau_i(q), sin(k q_i) or cos(k q_i). Torques are taken at the
// nominal geometry (the geometry's correction changes them by a relative
// amount of the order of the geometric errors, 1e-3: second order in the
// deflection).
//
// Gravity: g (m/s^2) in the robot's base frame, the frame after the base
// block B (upright robot: (0, 0, -9.80665)). A body's centre of mass is
// given in the frame of the joint that carries it (the frame after that
// link's transform); the payload's in the tip frame.
//
// Names: "<joint>.compliance", "<joint>.sin<k>", "<joint>.cos<k>".

#ifndef ACTIVECAL_CORE_JOINT_ERRORS_H_
#define ACTIVECAL_CORE_JOINT_ERRORS_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/simulation.h"

namespace activecal {

// Standard gravity (m/s^2).
inline constexpr double kStandardGravity = 9.80665;

// A rigid body carried by a joint: the child link of a URDF joint (with
// the fixed links after it).
struct BodyInertial {
  std::string name;  // the link's name, for messages
  int joint = 0;     // 0-based: the body moves with joints 0..joint
  double mass_kg = 0.0;
  Eigen::Vector3d com_m = Eigen::Vector3d::Zero();  // in joint's frame
};

struct GravityModel {
  std::vector<BodyInertial> bodies;
  // In the robot's base frame (m/s^2).
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -kStandardGravity);
  double payload_kg = 0.0;
  Eigen::Vector3d payload_com_m = Eigen::Vector3d::Zero();  // tip frame
  bool empty() const { return bodies.empty() && payload_kg == 0.0; }
};

// The torque (revolute: N m about the axis) or force (prismatic: N along
// it) gravity exerts at each joint at the full parameter vector
// `parameters` and joint readings q: axis . sum_b (c_b - o) x m_b g over
// the bodies (and payload) the joint carries, o a point on its axis
// (prismatic: axis . sum_b m_b g), the derivative of gravity's work
// sum_b m_b g . c_b(q) with respect to the joint's motion. Torques below
// 1e-12 of |g| sum_b m_b max(1 m, |c_b|) (rounding, e.g. about a vertical
// axis) are exactly 0.
Eigen::VectorXd GravityTorques(const RobotModel& model,
                               const Eigen::VectorXd& parameters,
                               const GravityModel& gravity,
                               const Eigen::VectorXd& q);

enum class JointTermKind { kCompliance, kSine, kCosine };
// "compliance", "sin", "cos".
const char* JointTermKindToString(JointTermKind kind);

struct JointTerm {
  int joint = 0;  // 0-based
  JointTermKind kind = JointTermKind::kCompliance;
  int harmonic = 0;  // k of kSine / kCosine
};

// A set of joint error terms with their values and the gravity model the
// compliance terms need.
struct JointErrorModel {
  std::vector<JointTerm> terms;
  Eigen::VectorXd values;  // one per term (0 when not yet identified)
  GravityModel gravity;

  int size() const { return static_cast<int>(terms.size()); }
  bool empty() const { return terms.empty(); }
  bool has_compliance() const;
  // "elbow_joint.compliance", "elbow_joint.sin2", ...
  std::string Name(const RobotModel& model, int term) const;
  std::vector<std::string> Names(const RobotModel& model) const;
  // "rad/(N m)", "m/N" or "rad".
  const char* Unit(const RobotModel& model, int term) const;
  // The same model with only the terms at `keep` (ascending).
  JointErrorModel Subset(const std::vector<int>& keep) const;
  // The terms of `other` appended (values too; `other`'s gravity kept when
  // this one has none).
  void Append(const JointErrorModel& other);
  // Checks term joints, values' size and finiteness; compliance terms need
  // a non-empty gravity model. One line in *error.
  bool Validate(const RobotModel& model, std::string* error) const;
};

// One compliance term per joint.
JointErrorModel ComplianceTerms(const RobotModel& model,
                                const GravityModel& gravity);
// sin/cos k q for k = 1..harmonics on every revolute joint.
JointErrorModel HarmonicTerms(const RobotModel& model, int harmonics);

// The features phi_t(q) of every term (see above); torques at `parameters`.
Eigen::VectorXd JointTermFeatures(const RobotModel& model,
                                  const Eigen::VectorXd& parameters,
                                  const JointErrorModel& errors,
                                  const Eigen::VectorXd& q);

// The index, inside a link block, of the entry the joint's motion error
// adds to: the URDF offset, the DH gamma (revolute) or d (prismatic).
int MotionOffsetEntry(const Link& link);

// The errors e_i (one per joint) for features `features`
// (JointTermFeatures) and term values `values`.
template <typename T>
void JointErrors(const JointErrorModel& errors, const Eigen::VectorXd& features,
                 const T* values, int num_joints, T* e) {
  for (int i = 0; i < num_joints; ++i) e[i] = T(0.0);
  for (int t = 0; t < errors.size(); ++t) {
    e[errors.terms[t].joint] += values[t] * features[t];
  }
}

// The full parameter vector that predicts the pose q with the joint errors
// applied: each joint's motion offset moved by e_i(q) (the motion is then
// offset + gain * q + e_i). `features` at q from JointTermFeatures. The
// prediction with the errors is the geometric prediction at this vector.
Eigen::VectorXd ParametersAtPose(const RobotModel& model,
                                 const Eigen::VectorXd& parameters,
                                 const JointErrorModel& errors,
                                 const Eigen::VectorXd& features);

// SimulateMeasurements (simulation.h) with the joint errors of `errors`
// (its values the true ones) applied at every pose, features at
// `feature_parameters` (the nominal vector, as the fit takes them): the
// same noise draws as SimulateMeasurements for the seed, on the
// predictions with the errors. Distances are refused.
bool SimulateWithJointErrors(const RobotModel& model,
                             const Eigen::VectorXd& true_parameters,
                             const Eigen::VectorXd& feature_parameters,
                             const JointErrorModel& errors,
                             const std::vector<Measurement>& plan,
                             const SimulationNoise& noise, uint64_t seed,
                             std::vector<Measurement>* out, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_JOINT_ERRORS_H_
