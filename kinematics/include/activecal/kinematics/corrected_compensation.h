// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Compensation with the hybrid model (core/learned_correction.h): the
// robot reaches point(q) = MeasuredPoint(q) + R_B c(q), the parametric
// point moved by the learned correction c (a smooth function of the
// joints, a fraction of a millimetre). Solved as a fixed point on top of
// the parametric compensation (compensation.h): round k solves each target
// t with the parametric inverse kinematics for t - R_B c(q_{k-1}), from
// q_{k-1}, until no reached target's correction moves by more than the
// position tolerance (at most max_rounds). Each result's position_error_m is then
// that of the hybrid model, |point(q) - t|; a target the parametric solver
// reached whose hybrid error stays above the tolerance becomes
// kIterationCap ("the learned correction did not settle ..."). The
// orientation is not corrected (c moves the point only).
//
//   CompensateProgram(model, values, nominal, nominal_values, program,
//                     options, &summary);
//   ApplyLearnedCorrection(model, values, robot.learned_correction,
//                          options, &summary);

#ifndef ACTIVECAL_KINEMATICS_CORRECTED_COMPENSATION_H_
#define ACTIVECAL_KINEMATICS_CORRECTED_COMPENSATION_H_

#include <Eigen/Core>

#include "activecal/core/learned_correction.h"
#include "activecal/core/robot_model.h"
#include "activecal/kinematics/compensation.h"

namespace activecal {

struct CorrectionRounds {
  int rounds = 0;  // fixed-point rounds run
  // The largest move of a target's correction (m) in the last round.
  double last_change_m = 0.0;
};

// Refines `summary` (a finished CompensateProgram or CompensateTargets of
// `model` at `values` with `options`) for the hybrid model with
// `correction` (empty: nothing changes). The joint changes stay measured
// from summary->starts. Returns the rounds run.
CorrectionRounds ApplyLearnedCorrection(const RobotModel& model,
                                        const Eigen::VectorXd& values,
                                        const LearnedCorrection& correction,
                                        const CompensationOptions& options,
                                        CompensationSummary* summary,
                                        int max_rounds = 20);

}  // namespace activecal

#endif  // ACTIVECAL_KINEMATICS_CORRECTED_COMPENSATION_H_
