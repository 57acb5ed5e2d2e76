// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/orientation_check.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

namespace activecal {

PoseFit PoseFitOf(const RobotModel& model, const Eigen::VectorXd& parameters,
                  const std::vector<Measurement>& measurements) {
  const auto matrix = [](const Eigen::Vector3d& v) -> Eigen::Matrix3d {
    const double angle = v.norm();
    return angle == 0 ? Eigen::Matrix3d::Identity()
                      : Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
  };
  std::vector<Eigen::Matrix3d> R_measured, R_model;
  std::vector<Eigen::Vector3d> p_measured, p_model;
  for (const Measurement& m : measurements) {
    if (m.type != MeasurementType::kPose) continue;
    if (static_cast<int>(R_measured.size()) == kPoseFitMaxPoses) break;
    const Measurement p = PredictMeasurement(model, parameters, m);
    R_measured.push_back(matrix(m.rotation));
    R_model.push_back(matrix(p.rotation));
    p_measured.push_back(m.position);
    p_model.push_back(p.position);
  }
  PoseFit fit;
  fit.num_poses = static_cast<int>(R_measured.size());
  double rotation2 = 0, distance2 = 0;
  int pairs = 0;
  for (int i = 0; i < fit.num_poses; ++i) {
    for (int j = i + 1; j < fit.num_poses; ++j) {
      const double measured =
          Eigen::AngleAxisd(R_measured[i].transpose() * R_measured[j]).angle();
      const double modelled =
          Eigen::AngleAxisd(R_model[i].transpose() * R_model[j]).angle();
      rotation2 += (measured - modelled) * (measured - modelled);
      const double d = (p_measured[i] - p_measured[j]).norm() -
                       (p_model[i] - p_model[j]).norm();
      distance2 += d * d;
      ++pairs;
    }
  }
  if (pairs > 0) {
    fit.rotation_rms_rad = std::sqrt(rotation2 / pairs);
    fit.position_rms_m = std::sqrt(distance2 / pairs);
  }
  return fit;
}

bool OrientationFitsBadly(const PoseFit& fit) {
  return fit.num_poses > 0 && fit.rotation_rms_rad > kOrientationHintRad &&
         fit.rotation_rms_rad > kOrientationHintRatio * fit.position_rms_m;
}

std::string OrientationHint(const PoseFit& fit, const std::string& what) {
  char text[200];
  std::snprintf(text, sizeof(text),
                "orientations fit badly (between %d poses, relative "
                "rotations differ from the model's by %.3g mrad RMS, "
                "distances by %.3g mm): check the orientation convention (",
                fit.num_poses, fit.rotation_rms_rad * 1e3,
                fit.position_rms_m * 1e3);
  return text + what + ")";
}

}  // namespace activecal
