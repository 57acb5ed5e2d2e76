// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/registration.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <sstream>

#include "activecal/core/kinematics.h"

namespace activecal {

bool RigidTransformBetween(const std::vector<Eigen::Vector3d>& from,
                           const std::vector<Eigen::Vector3d>& to,
                           Eigen::Matrix3d* rotation,
                           Eigen::Vector3d* translation, std::string* error) {
  const int n = static_cast<int>(from.size());
  if (n != static_cast<int>(to.size()) || n < 3) {
    if (error) {
      *error = "registration needs at least 3 measured points, got " +
               std::to_string(std::min<size_t>(from.size(), to.size()));
    }
    return false;
  }
  Eigen::Matrix3Xd a(3, n), b(3, n);
  for (int i = 0; i < n; ++i) {
    a.col(i) = from[i];
    b.col(i) = to[i];
  }
  // The spread of both point sets: a frame needs them off a line.
  auto off_a_line = [](const Eigen::Matrix3Xd& p) {
    const Eigen::Matrix3Xd centred = p.colwise() - p.rowwise().mean();
    const Eigen::Vector3d s =
        Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
    return s[1] > 1e-6 * std::max(1.0, s[0]);
  };
  if (!off_a_line(a) || !off_a_line(b)) {
    if (error) {
      *error = std::string("registration: the ") +
               (off_a_line(a) ? "measured" : "predicted") +
               " points lie on a line (or coincide): they cannot fix the "
               "device's frame; measure poses spread in space";
    }
    return false;
  }
  const Eigen::Matrix4d T = Eigen::umeyama(a, b, /*with_scaling=*/false);
  *rotation = T.topLeftCorner<3, 3>();
  *translation = T.topRightCorner<3, 1>();
  return true;
}

bool RegisterBaseFrame(const RobotModel& model,
                       const std::vector<Measurement>& measurements,
                       Eigen::VectorXd* parameters,
                       RegistrationSummary* summary) {
  *summary = RegistrationSummary();
  if (model.base.convention != LinkConvention::kFrame) {
    summary->message =
        "the robot's base is not a 6-DOF frame (convention 'frame'), so it "
        "is not registered in closed form";
    return false;
  }
  std::string error;
  if (!model.CheckParameters(*parameters, &error)) {
    summary->message = error;
    return false;
  }
  Eigen::VectorXd at_identity = *parameters;
  at_identity.head(6).setZero();
  std::vector<Eigen::Vector3d> predicted, measured;
  for (const Measurement& m : measurements) {
    // Distances and fixed points carry no coordinates in the device frame.
    if (m.type == MeasurementType::kDistance || m.involves_points()) continue;
    if (!CheckMeasurement(model, m, &error)) {
      summary->message = "registration: " + error;
      return false;
    }
    predicted.push_back(MeasuredPoint(model, at_identity, m.joints, m.marker));
    measured.push_back(m.position);
  }
  summary->num_points = static_cast<int>(predicted.size());
  if (!RigidTransformBetween(predicted, measured, &summary->rotation,
                             &summary->translation, &error)) {
    summary->message = error;
    return false;
  }
  double ss = 0.0;
  for (size_t i = 0; i < predicted.size(); ++i) {
    ss +=
        (summary->rotation * predicted[i] + summary->translation - measured[i])
            .squaredNorm();
  }
  summary->rms_m = std::sqrt(ss / predicted.size());
  parameters->head(3) = summary->translation;
  parameters->segment(3, 3) = RotationToRpy(summary->rotation);
  summary->success = true;
  std::ostringstream msg;
  msg << "base frame registered in closed form to " << summary->num_points
      << " measured points; RMS " << summary->rms_m
      << " m with the nominal geometry";
  summary->message = msg.str();
  return true;
}

}  // namespace activecal
