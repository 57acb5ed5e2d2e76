// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The honest baseline of a calibration: the nominal geometry with only the
// base frame and the marker points fitted to the measurements (the
// 'registration' parameter set, core/parameter_sets.h). When the device's
// frame is unknown, the error of the nominal model as given is meaningless
// (hundreds of mm); this is the error a calibration must beat.
//
//   RegistrationFitSummary baseline;
//   FitRegistration(model, model.nominal, measurements, options, &baseline);
//   baseline.rms_m;  // RMS residual norm with the nominal geometry
//
// A 6-DOF ('frame') base is first registered in closed form
// (core/registration.h) when there are measured points (distances alone
// leave it as given); then the registration set, reduced to what the
// measurements separate (parameter_reduction.h), is identified by
// Identify() with `options` (weights and robust loss included).

#ifndef ACTIVECAL_ESTIMATION_REGISTRATION_FIT_H_
#define ACTIVECAL_ESTIMATION_REGISTRATION_FIT_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/estimation/identification.h"

namespace activecal {

struct RegistrationFitSummary {
  // kConvergence on success; otherwise `message` says why.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  // Full parameter vector: `geometry` with the base and markers fitted.
  Eigen::VectorXd parameters;
  std::vector<std::string> names;  // the parameters fitted
  double rms_m = 0.0;              // RMS of the residual norms (m)
  // The fit itself (residuals, weights, chi^2).
  IdentificationSummary identification;
};

// Fits the base frame and markers of `model` to `measurements`, the rest
// of the full vector `geometry` held as given. The free flags of `model`
// are ignored (the registration set is applied to a copy).
void FitRegistration(const RobotModel& model, const Eigen::VectorXd& geometry,
                     const std::vector<Measurement>& measurements,
                     const IdentificationOptions& options,
                     RegistrationFitSummary* summary);

// The baseline of a calibration of `model`: as FitRegistration, but only
// the registration parameters that are free in `model` are fitted (its
// free set after the parameter set, the reduction and the model
// selection), so that the baseline never has a parameter the calibrated
// model holds fixed (e.g. a tool point given in the robot file). The
// closed-form registration of a 'frame' base runs only when the whole
// base is free. Fails when no registration parameter is free.
void FitRegistrationOfFreeSet(const RobotModel& model,
                              const Eigen::VectorXd& geometry,
                              const std::vector<Measurement>& measurements,
                              const IdentificationOptions& options,
                              RegistrationFitSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_REGISTRATION_FIT_H_
