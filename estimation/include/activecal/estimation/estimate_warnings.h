// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Warnings a calibration engineer wants about an identification's
// estimates, one line each, naming the parameters:
//
//   - a standard deviation larger than a plausible range (max_std_m for
//     lengths, max_std_rad for angles and gains): the data hardly see it;
//   - correlations beyond max_abs_correlation: the data separate only
//     combinations; parameters linked by such pairs share one line (a
//     pair: "A and B are correlated -0.995: ...");
//   - a link parameter whose estimate moved from the nominal value both far
//     in absolute terms (more than max_moved_m for lengths, max_moved_rad
//     for angles and gains: beyond what a manufacturing tolerance or a
//     calibration correction is) and significantly (more than
//     max_moved_std of its standard deviations): often a wrong nominal
//     model (e.g. a UR10e read as a UR10), so all of them share one line.
//     A significant millimetre correction from thousands of poses is what
//     a calibration is for and is not warned about. The base frame and the
//     markers are unknowns rather than nominal values and are not checked.
//
// When the rows were weighted by stated sigmas that the residuals
// contradict (summary.chi_square_plausible false, identification.h), one
// line says so first (chi^2 / dof, its 99.9 % interval, the noise the
// residuals imply), and the std and moved warnings use the scaled standard
// deviations ("scaled std").
//
//   for (const std::string& w : EstimateWarnings(model, summary, {}))
//     std::cout << "warning: " << w << "\n";

#ifndef ACTIVECAL_ESTIMATION_ESTIMATE_WARNINGS_H_
#define ACTIVECAL_ESTIMATION_ESTIMATE_WARNINGS_H_

#include <string>
#include <vector>

#include "activecal/core/robot_model.h"
#include "activecal/estimation/identification.h"

namespace activecal {

struct EstimateWarningOptions {
  double max_std_m = 0.01;   // 10 mm
  double max_std_rad = 0.1;  // also for unitless gains
  double max_abs_correlation = 0.99;
  double max_moved_std = 5.0;
  double max_moved_m = 0.005;   // 5 mm
  double max_moved_rad = 0.01;  // 10 mrad (0.57 deg); also for gains
};

// `model` is the one identified (its free flags and nominal values), and
// `summary` a converged identification of it. Lines in the order: chi^2
// (when implausible), std (one
// per parameter), correlation (one per group of parameters linked by pairs
// beyond the threshold, ordered by their first parameter), moved
// (one line naming them all, with the move and its std count).
std::vector<std::string> EstimateWarnings(
    const RobotModel& model, const IdentificationSummary& summary,
    const EstimateWarningOptions& options);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_ESTIMATE_WARNINGS_H_
