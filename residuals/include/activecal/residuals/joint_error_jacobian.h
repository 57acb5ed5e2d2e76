// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Jacobians and residuals of measurements with joint error terms
// (joint_errors.h, joint_error_residual.h): the free geometric parameters'
// columns, then one column per term.

#ifndef ACTIVECAL_RESIDUALS_JOINT_ERROR_JACOBIAN_H_
#define ACTIVECAL_RESIDUALS_JOINT_ERROR_JACOBIAN_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/joint_errors.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// The features of every measurement's pose (JointTermFeatures at
// `parameters`, normally the nominal vector).
std::vector<Eigen::VectorXd> MeasurementTermFeatures(
    const RobotModel& model, const Eigen::VectorXd& parameters,
    const JointErrorModel& errors,
    const std::vector<Measurement>& measurements);

// Checks that every measurement has one pose (no distances) and the terms
// are valid; one line in *error naming the measurement.
bool CheckJointErrorInputs(const RobotModel& model,
                           const JointErrorModel& errors,
                           const std::vector<Measurement>& measurements,
                           std::string* error);

// The stacked Jacobian (rows: the measurements' residual rows in order;
// columns: model's free parameters, then errors' terms) at `parameters`
// and errors.values; the features from `features` (one per measurement).
// *residuals (may be null): the residual rows.
bool JointErrorJacobian(const RobotModel& model,
                        const Eigen::VectorXd& parameters,
                        const JointErrorModel& errors,
                        const std::vector<Measurement>& measurements,
                        const std::vector<Eigen::VectorXd>& features,
                        double rotation_weight_m_per_rad,
                        Eigen::MatrixXd* jacobian, Eigen::VectorXd* residuals,
                        std::string* error);

// The norm of each measurement's residual rows (m, a pose's rotation rows
// weighted) with the joint errors applied.
bool JointErrorResidualNorms(const RobotModel& model,
                             const Eigen::VectorXd& parameters,
                             const JointErrorModel& errors,
                             const std::vector<Measurement>& measurements,
                             const std::vector<Eigen::VectorXd>& features,
                             double rotation_weight_m_per_rad,
                             Eigen::VectorXd* norms, std::string* error);

// The terms whose columns the geometry's free columns and the earlier
// terms' columns do not explain: a term is kept when the part of its
// column orthogonal to those has a relative norm above
// sqrt(rank_tolerance) (a term with no effect, e.g. the compliance of a
// vertical axis on an upright robot, or one a geometric parameter
// absorbs, is dropped). `jacobian` as from JointErrorJacobian. *dropped:
// one "name: reason" line per term dropped.
std::vector<int> IdentifiableTerms(const RobotModel& model,
                                   const JointErrorModel& errors,
                                   const Eigen::MatrixXd& jacobian,
                                   double rank_tolerance,
                                   std::vector<std::string>* dropped);

}  // namespace activecal

#endif  // ACTIVECAL_RESIDUALS_JOINT_ERROR_JACOBIAN_H_
