// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Reducing a named parameter set (core/parameter_sets.h) to the parameters
// the measurements can separate, by a rule a calibration engineer can
// predict: parameters are considered in a fixed priority order and each is
// kept when its Jacobian column adds a direction the kept ones do not span.
//
// Priority: the base frame, then the markers, then the links from base to
// tip, each link's joint offset before its geometric corrections; inside a
// block, the block's own order. So a redundancy between the base frame and
// the first joint's origin is resolved for the base (the registration stays
// whole), a marker's point wins over the last joint's origin, and an offset
// over a rotation about the same axis. A column shorter than
// kNoEffectRelativeNorm (1e-6, residuals/jacobians.h) times the longest has
// no effect and is dropped (rounded angles in a robot file leave such
// columns at ~1e-10 instead of 0). The others are scaled to unit norm (the
// rule does not depend on units); a column is dropped when the part of it
// outside the span of the kept columns is shorter than `tolerance`
// (kRedundancyTolerance below for the parameter sets). Ties cannot occur:
// the order is total. The result is the same on every platform up to
// rounding of that test.
//
//   std::vector<HeldParameter> held;
//   const FreeSet kept =
//       ReduceToIdentifiable(model, J, kRedundancyTolerance, &held);
//   // held[k].name = "shoulder_pan_joint.rx",
//   // held[k].reason = "a combination of B.rx, B.ry (residual 2e-16)"
//   // held[k].stage = HoldStage::kParameterSet

#ifndef ACTIVECAL_ESTIMATION_PARAMETER_REDUCTION_H_
#define ACTIVECAL_ESTIMATION_PARAMETER_REDUCTION_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/free_set.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// The tolerance of ApplyAndReduceParameterSet: a structural redundancy is
// ~1e-15 at a generic point with exact angles, and of the order of the
// angles' rounding when a robot file writes pi/2 with few decimals
// (1.570796, 3.3e-7 off: the UR10e's B.z and shoulder_lift_joint.y are then
// 3.3e-7 apart, and a tolerance of 1e-7 kept both for a fit whose
// Jacobian was rank deficient). A direction of relative size r is
// estimated with its noise amplified ~1/r: below 1e-5 (a 10 um tracker
// giving a 1 m standard deviation) it is no parameter a calibration can
// use. Files rounded to 6 or more decimals of a radian are reduced as
// their exact copies are; to 4, to as many parameters (a ballbar may keep
// the other one of a pair 3.7e-6 apart).
constexpr double kRedundancyTolerance = 1e-5;

// Free parameters of `model` in the priority order above (indices into the
// full parameter vector).
std::vector<int> ReductionPriority(const RobotModel& model);

// `jacobian`: m x num_free, columns in model.FreeParameterNames() order.
// Returns the free set of `model` without the dropped parameters, and
// describes those in *held (priority order; stage kParameterSet; reason
// "has no effect on these measurements" or "a combination of A, B, ...
// (residual r)" naming the kept parameters that explain it, largest
// coefficients first).
FreeSet ReduceToIdentifiable(const RobotModel& model,
                             const Eigen::MatrixXd& jacobian, double tolerance,
                             std::vector<HeldParameter>* held);

// The whole step from a named parameter set to the parameters to identify:
// the free set `set` names on `model` (ParameterSetFreeSet, with marker
// angles free when `measurements` hold 6D poses), unless it is kFile
// reduced to what the Jacobian of `measurements` separates where the fit
// will be: at *point (a full parameter vector, e.g. the nominal or
// registered start), except that a marker whose point is at the tip
// frame's origin (the default guess, on the last joint's axis) has its
// free parameters moved to GenericPoint(*point) (about 1 mm), the start the
// fit needs to see every kept direction. A marker given elsewhere (e.g. a
// reflector on the flange axis) stays where it was given. Every held
// parameter keeps its value in *point. *free: the set to identify; *held:
// what the reduction dropped (empty for kFile). Returns false with *error
// when a Jacobian cannot be evaluated or nothing is free; *point is then
// unchanged.
bool ReduceParameterSet(const RobotModel& model, ParameterSet set,
                        const std::vector<Measurement>& measurements,
                        double rotation_weight_m_per_rad,
                        Eigen::VectorXd* point, FreeSet* free,
                        std::vector<HeldParameter>* held, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_PARAMETER_REDUCTION_H_
