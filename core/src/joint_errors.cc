// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/joint_errors.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/kinematics.h"

namespace activecal {
namespace {

// Torques below this fraction of |g| sum_b m_b max(1 m, |c_b|) are rounding
// (a vertical axis of an upright arm): set to exactly 0, so that the term
// has no effect and the identifiability check drops it.
constexpr double kTorqueFloor = 1e-12;

}  // namespace

Eigen::VectorXd GravityTorques(const RobotModel& model,
                               const Eigen::VectorXd& parameters,
                               const GravityModel& gravity,
                               const Eigen::VectorXd& q) {
  const int n = model.num_joints();
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(n);
  if (gravity.empty()) return tau;
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  // Frames from the robot's base frame (the base block B left out): frame
  // i + 1 after link i, frame 0 the base.
  std::vector<Eigen::Matrix3d> R(n + 1, Eigen::Matrix3d::Identity());
  std::vector<Eigen::Vector3d> t(n + 1, Eigen::Vector3d::Zero());
  Eigen::Matrix3d Ri;
  Eigen::Vector3d ti;
  for (int i = 0; i < n; ++i) {
    LinkTransform(model.links[i], blocks[i + 1], q[i], &Ri, &ti);
    t[i + 1] = t[i] + R[i] * ti;
    R[i + 1] = R[i] * Ri;
  }
  // The masses (kg) and their centres (base frame), with the last joint
  // that carries each.
  std::vector<double> mass;
  std::vector<Eigen::Vector3d> centre;
  std::vector<int> carried_by;
  for (const BodyInertial& b : gravity.bodies) {
    mass.push_back(b.mass_kg);
    centre.push_back(R[b.joint + 1] * b.com_m + t[b.joint + 1]);
    carried_by.push_back(b.joint);
  }
  if (gravity.payload_kg != 0.0) {
    mass.push_back(gravity.payload_kg);
    centre.push_back(R[n] * (model.tip.rotation * gravity.payload_com_m +
                             model.tip.translation) +
                     t[n]);
    carried_by.push_back(n - 1);
  }
  double scale = 0.0;
  for (size_t b = 0; b < mass.size(); ++b) {
    scale += std::abs(mass[b]) * std::max(1.0, centre[b].norm());
  }
  scale *= gravity.gravity.norm();
  for (int i = 0; i < n; ++i) {
    const Link& link = model.links[i];
    // The joint's axis and a point on it, in the base frame: the motion is
    // last in a URDF joint and a modified-DH link (about z of the link's
    // frame), first in a standard-DH or Hayati link (about z of the
    // previous frame).
    Eigen::Vector3d axis, origin;
    if (link.convention == LinkConvention::kUrdf) {
      axis = R[i + 1] * link.axis;
      origin = t[i + 1];
    } else if (link.convention == LinkConvention::kModifiedDH) {
      axis = R[i + 1].col(2);
      origin = t[i + 1];
    } else {
      axis = R[i].col(2);
      origin = t[i];
    }
    double sum = 0.0;
    for (size_t b = 0; b < mass.size(); ++b) {
      if (carried_by[b] < i) continue;
      const Eigen::Vector3d force = mass[b] * gravity.gravity;
      sum += link.joint_type == JointType::kPrismatic
                 ? axis.dot(force)
                 : axis.dot((centre[b] - origin).cross(force));
    }
    tau[i] = std::abs(sum) < kTorqueFloor * scale ? 0.0 : sum;
  }
  return tau;
}

const char* JointTermKindToString(JointTermKind kind) {
  constexpr const char* kNames[] = {"compliance", "sin", "cos"};
  return EnumToString(kNames, kind);
}

bool JointErrorModel::has_compliance() const {
  for (const JointTerm& t : terms) {
    if (t.kind == JointTermKind::kCompliance) return true;
  }
  return false;
}

std::string JointErrorModel::Name(const RobotModel& model, int term) const {
  const JointTerm& t = terms[term];
  std::string name =
      model.block_name(t.joint + 1) + "." + JointTermKindToString(t.kind);
  if (t.kind != JointTermKind::kCompliance) name += std::to_string(t.harmonic);
  return name;
}

std::vector<std::string> JointErrorModel::Names(const RobotModel& model) const {
  std::vector<std::string> names;
  for (int t = 0; t < size(); ++t) names.push_back(Name(model, t));
  return names;
}

const char* JointErrorModel::Unit(const RobotModel& model, int term) const {
  const JointTerm& t = terms[term];
  const bool prismatic =
      model.links[t.joint].joint_type == JointType::kPrismatic;
  if (t.kind == JointTermKind::kCompliance) {
    return prismatic ? "m/N" : "rad/(N m)";
  }
  return prismatic ? "m" : "rad";
}

JointErrorModel JointErrorModel::Subset(const std::vector<int>& keep) const {
  JointErrorModel out;
  out.gravity = gravity;
  out.values.resize(static_cast<int>(keep.size()));
  for (size_t k = 0; k < keep.size(); ++k) {
    out.terms.push_back(terms[keep[k]]);
    out.values[static_cast<int>(k)] =
        values.size() == size() ? values[keep[k]] : 0.0;
  }
  return out;
}

void JointErrorModel::Append(const JointErrorModel& other) {
  Eigen::VectorXd v(size() + other.size());
  v << (values.size() == size() ? values : Eigen::VectorXd::Zero(size())),
      (other.values.size() == other.size()
           ? other.values
           : Eigen::VectorXd::Zero(other.size()));
  terms.insert(terms.end(), other.terms.begin(), other.terms.end());
  values = v;
  if (gravity.empty()) gravity = other.gravity;
}

bool JointErrorModel::Validate(const RobotModel& model,
                               std::string* error) const {
  std::ostringstream msg;
  if (values.size() != size()) {
    msg << "joint error terms: " << values.size() << " values for " << size()
        << " terms";
  } else if (!values.allFinite()) {
    msg << "joint error terms: a value is not finite";
  } else if (has_compliance() && gravity.empty()) {
    msg << "joint error terms: compliance needs the links' masses "
           "(inertials) or a payload";
  } else {
    for (const JointTerm& t : terms) {
      if (t.joint < 0 || t.joint >= model.num_joints()) {
        msg << "joint error terms: joint " << t.joint << " out of range";
        break;
      }
      if (t.kind != JointTermKind::kCompliance && t.harmonic < 1) {
        msg << "joint error terms: harmonic " << t.harmonic << " < 1";
        break;
      }
    }
    for (const BodyInertial& b : gravity.bodies) {
      if (b.joint < 0 || b.joint >= model.num_joints() || !(b.mass_kg >= 0) ||
          !b.com_m.allFinite()) {
        msg << "gravity: body '" << b.name
            << "' has a bad joint, mass or centre of mass";
        break;
      }
    }
  }
  if (msg.str().empty()) return true;
  if (error) *error = msg.str();
  return false;
}

JointErrorModel ComplianceTerms(const RobotModel& model,
                                const GravityModel& gravity) {
  JointErrorModel out;
  out.gravity = gravity;
  for (int i = 0; i < model.num_joints(); ++i) {
    out.terms.push_back({i, JointTermKind::kCompliance, 0});
  }
  out.values = Eigen::VectorXd::Zero(out.size());
  return out;
}

JointErrorModel HarmonicTerms(const RobotModel& model, int harmonics) {
  JointErrorModel out;
  for (int i = 0; i < model.num_joints(); ++i) {
    if (model.links[i].joint_type != JointType::kRevolute) continue;
    for (int k = 1; k <= harmonics; ++k) {
      out.terms.push_back({i, JointTermKind::kSine, k});
      out.terms.push_back({i, JointTermKind::kCosine, k});
    }
  }
  out.values = Eigen::VectorXd::Zero(out.size());
  return out;
}

Eigen::VectorXd JointTermFeatures(const RobotModel& model,
                                  const Eigen::VectorXd& parameters,
                                  const JointErrorModel& errors,
                                  const Eigen::VectorXd& q) {
  Eigen::VectorXd phi(errors.size());
  Eigen::VectorXd tau;
  if (errors.has_compliance()) {
    tau = GravityTorques(model, parameters, errors.gravity, q);
  }
  for (int t = 0; t < errors.size(); ++t) {
    const JointTerm& term = errors.terms[t];
    const double x = q[term.joint];
    switch (term.kind) {
      case JointTermKind::kCompliance:
        phi[t] = tau[term.joint];
        break;
      case JointTermKind::kSine:
        phi[t] = std::sin(term.harmonic * x);
        break;
      case JointTermKind::kCosine:
        phi[t] = std::cos(term.harmonic * x);
        break;
    }
  }
  return phi;
}

int MotionOffsetEntry(const Link& link) {
  if (link.convention == LinkConvention::kUrdf) return kUrdfOffset;
  return link.joint_type == JointType::kPrismatic ? kD : kGamma;
}

Eigen::VectorXd ParametersAtPose(const RobotModel& model,
                                 const Eigen::VectorXd& parameters,
                                 const JointErrorModel& errors,
                                 const Eigen::VectorXd& features) {
  Eigen::VectorXd p = parameters;
  if (errors.empty()) return p;
  std::vector<double> e(model.num_joints());
  JointErrors(errors, features, errors.values.data(), model.num_joints(),
              e.data());
  for (int i = 0; i < model.num_joints(); ++i) {
    p[model.block_offset(i + 1) + MotionOffsetEntry(model.links[i])] += e[i];
  }
  return p;
}

namespace {

Eigen::Matrix3d FromRotationVector(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  return angle > 0 ? Eigen::AngleAxisd(angle, v / angle).toRotationMatrix()
                   : Eigen::Matrix3d::Identity();
}

}  // namespace

bool SimulateWithJointErrors(
    const RobotModel& model, const Eigen::VectorXd& true_parameters,
    const Eigen::VectorXd& feature_parameters, const JointErrorModel& errors,
    const std::vector<Measurement>& plan, const SimulationNoise& noise,
    uint64_t seed, std::vector<Measurement>* out, std::string* error) {
  if (!errors.Validate(model, error)) return false;
  for (size_t i = 0; i < plan.size(); ++i) {
    if (plan[i].type == MeasurementType::kDistance && !errors.empty()) {
      if (error) {
        *error = "simulation: measurement " + std::to_string(i) +
                 ": joint errors cannot be simulated for a distance";
      }
      return false;
    }
  }
  std::vector<Measurement> noisy;
  if (!SimulateMeasurements(model, true_parameters, plan, noise, seed, &noisy,
                            error)) {
    return false;
  }
  for (size_t i = 0; i < noisy.size(); ++i) {
    Measurement& m = noisy[i];
    const Measurement exact = PredictMeasurement(model, true_parameters, m);
    const Eigen::VectorXd at = ParametersAtPose(
        model, true_parameters, errors,
        JointTermFeatures(model, feature_parameters, errors, m.joints));
    const Measurement moved = PredictMeasurement(model, at, m);
    m.position += moved.position - exact.position;
    if (m.type == MeasurementType::kPose) {
      const Eigen::Matrix3d R = FromRotationVector(moved.rotation) *
                                FromRotationVector(exact.rotation).transpose() *
                                FromRotationVector(m.rotation);
      const Eigen::AngleAxisd aa(R);
      m.rotation = aa.angle() * aa.axis();
    }
  }
  *out = std::move(noisy);
  return true;
}

}  // namespace activecal
