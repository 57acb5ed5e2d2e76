// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/learned_correction.h"

#include <cmath>

#include "activecal/core/kinematics.h"

namespace activecal {

int LearnedCorrection::num_inputs() const {
  int n = 0;
  for (bool p : periodic) n += p ? 2 : 1;
  return n;
}

Eigen::VectorXd LearnedCorrection::Inputs(const Eigen::VectorXd& q) const {
  Eigen::VectorXd x(num_inputs());
  int k = 0;
  for (int j = 0; j < num_joints(); ++j) {
    if (periodic[j]) {
      x[k++] = std::sin(q[j]);
      x[k++] = std::cos(q[j]);
    } else {
      x[k++] = q[j] / scale[j];
    }
  }
  return x;
}

Eigen::VectorXd LearnedCorrection::Features(const Eigen::VectorXd& q) const {
  const Eigen::VectorXd x = Inputs(q);
  const double amplitude = std::sqrt(2.0 / num_features());
  Eigen::VectorXd z = frequencies * x + phases;
  for (int k = 0; k < z.size(); ++k) z[k] = amplitude * std::cos(z[k]);
  return z;
}

Eigen::Vector3d LearnedCorrection::Correction(const Eigen::VectorXd& q,
                                              int marker) const {
  if (empty()) return Eigen::Vector3d::Zero();
  const Eigen::VectorXd z = Features(q);
  return weights.middleCols(3 * marker, 3).transpose() * z +
         bias.segment(3 * marker, 3);
}

bool LearnedCorrection::Validate(const RobotModel* model,
                                 std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  const int d = num_features();
  if (d < 1) return fail("no features");
  if (scale.size() != num_joints()) {
    return fail("scale has " + std::to_string(scale.size()) + " entries for " +
                std::to_string(num_joints()) + " joints");
  }
  if (frequencies.rows() != d || frequencies.cols() != num_inputs()) {
    return fail("frequencies are " + std::to_string(frequencies.rows()) +
                " x " + std::to_string(frequencies.cols()) + ", expected " +
                std::to_string(d) + " x " + std::to_string(num_inputs()) +
                " (features x inputs)");
  }
  if (bias.size() < 3 || bias.size() % 3 != 0) {
    return fail("bias has " + std::to_string(bias.size()) +
                " entries, expected 3 per marker");
  }
  if (weights.rows() != d || weights.cols() != bias.size()) {
    return fail("weights are " + std::to_string(weights.rows()) + " x " +
                std::to_string(weights.cols()) + ", expected " +
                std::to_string(d) + " x " + std::to_string(bias.size()) +
                " (features x 3 per marker)");
  }
  if (!scale.allFinite() || !(scale.array() > 0).all()) {
    return fail("scale must be finite and > 0");
  }
  if (!frequencies.allFinite() || !phases.allFinite() || !weights.allFinite() ||
      !bias.allFinite()) {
    return fail("a value is not finite");
  }
  if (model) {
    if (num_joints() != model->num_joints()) {
      return fail("it is for " + std::to_string(num_joints()) +
                  " joints, the robot has " +
                  std::to_string(model->num_joints()));
    }
    for (int j = 0; j < num_joints(); ++j) {
      const bool revolute = model->links[j].joint_type == JointType::kRevolute;
      if (periodic[j] != revolute) {
        return fail("joint " + std::to_string(j + 1) + " is " +
                    (revolute ? "revolute" : "prismatic") +
                    " but its input is " +
                    (periodic[j] ? "periodic" : "linear"));
      }
    }
    if (num_markers() != model->num_markers()) {
      return fail("it has weights for " + std::to_string(num_markers()) +
                  " markers, the robot has " +
                  std::to_string(model->num_markers()));
    }
  }
  return true;
}

void SetCorrectionInputs(const RobotModel& model, LearnedCorrection* c) {
  const int n = model.num_joints();
  c->periodic.assign(n, true);
  c->scale = Eigen::VectorXd::Ones(n);
  for (int j = 0; j < n; ++j) {
    const Link& link = model.links[j];
    if (link.joint_type == JointType::kRevolute) continue;
    c->periodic[j] = false;
    const double range = link.joint_max - link.joint_min;
    if (std::isfinite(range) && range > 0) c->scale[j] = range;
  }
}

Eigen::Matrix3d BaseRotation(const RobotModel& model,
                             const Eigen::VectorXd& parameters) {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  LinkTransform(model.base, parameters.data() + model.block_offset(0), 0.0, &R,
                &t);
  return R;
}

Measurement PredictCorrectedMeasurement(const RobotModel& model,
                                        const Eigen::VectorXd& parameters,
                                        const LearnedCorrection& correction,
                                        const Measurement& like) {
  if (correction.empty()) return PredictMeasurement(model, parameters, like);
  const Eigen::Matrix3d RB = BaseRotation(model, parameters);
  Measurement out = PredictMeasurement(model, parameters, like);
  if (like.type == MeasurementType::kDistance) {
    const Eigen::Vector3d a =
        MeasuredPoint(model, parameters, like.joints, like.marker) +
        RB * correction.Correction(like.joints, like.marker);
    const Eigen::Vector3d b =
        MeasuredPoint(model, parameters, like.joints2, like.marker) +
        RB * correction.Correction(like.joints2, like.marker);
    out.distance = (a - b).norm();
    return out;
  }
  out.position += RB * correction.Correction(like.joints, like.marker);
  return out;
}

}  // namespace activecal
