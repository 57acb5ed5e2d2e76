// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A check of the measured values' unit before anything is calibrated.
//
// After the registration (the base frame and the markers fitted to the
// measurements), the residuals of measurements in the right unit are the
// robot's geometric errors and the device's noise: millimetres, at most
// centimetres. They cannot exceed the size of the robot, since a rigid fit
// of the measured points leaves residuals no larger than the points'
// spread. Millimetres written in metre columns (x_m = 1234.5) leave
// residuals about a thousand times the robot's reach.
//
// The rule: refuse when the RMS residual norm after registration is
// greater than the reach at the measured poses (the largest distance from
// the base frame to a measured point, forward kinematics at `parameters`
// with the base at the identity; both poses of a distance). Pass the
// nominal geometry as given, not the registration fit's parameters: fitted
// to millimetres, the marker points move metres away and the reach with
// them. A registration fit that stopped at its iteration cap counts too:
// millimetres read as metres put a far base (the PUMA's, 20 m away) 20 km
// away, where the fit does not converge.
//
//   std::string error;
//   if (!ResidualWithinReach(model, model.nominal, measurements,
//                            baseline.rms_m, &error)) Fail(error);

#ifndef ACTIVECAL_ESTIMATION_RESIDUAL_SCALE_H_
#define ACTIVECAL_ESTIMATION_RESIDUAL_SCALE_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// The reach defined above (m). The measurements must be valid for `model`
// (CheckMeasurement); 0 when there are none.
double ReachAtPoses(const RobotModel& model, const Eigen::VectorXd& parameters,
                    const std::vector<Measurement>& measurements);

// True when rms_m (the RMS residual norm after registration, m) is at most
// ReachAtPoses; otherwise false with *error naming both and suggesting
// millimetre columns.
bool ResidualWithinReach(const RobotModel& model,
                         const Eigen::VectorXd& parameters,
                         const std::vector<Measurement>& measurements,
                         double rms_m, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_RESIDUAL_SCALE_H_
