// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/residual_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace activecal {

double ReachAtPoses(const RobotModel& model, const Eigen::VectorXd& parameters,
                    const std::vector<Measurement>& measurements) {
  // The base at the identity: zero is the identity for a 'frame' base and
  // for every DH-family base.
  Eigen::VectorXd p = parameters;
  p.head(model.block_size(0)).setZero();
  double reach = 0.0;
  auto point = [&](const Eigen::VectorXd& q, int marker) {
    Measurement m;
    m.type = MeasurementType::kPosition;
    m.joints = q;
    m.marker = marker;
    reach = std::max(reach, PredictMeasurement(model, p, m).position.norm());
  };
  for (const Measurement& m : measurements) {
    // A known distance between fixed points has no pose.
    if (m.type == MeasurementType::kPointDistance) continue;
    point(m.joints, m.marker);
    if (m.type == MeasurementType::kDistance) point(m.joints2, m.marker);
  }
  return reach;
}

bool ResidualWithinReach(const RobotModel& model,
                         const Eigen::VectorXd& parameters,
                         const std::vector<Measurement>& measurements,
                         double rms_m, std::string* error) {
  const double reach = ReachAtPoses(model, parameters, measurements);
  if (rms_m <= reach) return true;
  if (error) {
    char text[512];
    std::snprintf(
        text, sizeof(text),
        "after registration (base frame and markers fitted) the RMS "
        "residual is %.4g m, more than the robot's reach at the measured "
        "poses (%.4g m): are the measured values in millimetres? x_m, y_m, "
        "z_m and distance_m are metres; name the columns x_mm, y_mm, z_mm "
        "(distance_mm) for millimetres",
        rms_m, reach);
    *error = text;
  }
  return false;
}

}  // namespace activecal
