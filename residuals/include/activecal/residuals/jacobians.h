// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Jacobians of the measurements with respect to the free parameters: the
// design matrix rows consumed by the pose selector. They are evaluated
// through the same cost functions the identification uses
// (measurement_residual.h), so selection and identification see the same
// derivatives.

#ifndef ACTIVECAL_RESIDUALS_JACOBIANS_H_
#define ACTIVECAL_RESIDUALS_JACOBIANS_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"

namespace activecal {

// A Jacobian column shorter than this times the longest column is taken as
// having no effect, by every identifiability rule (the analysis, the
// auto-fix, the reduction of a parameter set). Real robot files round
// their angles (data/ur10e.urdf writes pi/2 as 1.570796327): a parameter
// with no effect at exact angles (a translation along an axis that data
// cannot see, a base parameter under distances) then has a column of the
// rounding error times a lever, ~1e-10 of the longest, instead of zero.
// Normalised to unit length, that column is rounding noise taken for a
// direction of its own, kept, and the fit fails at the solution ("the
// Jacobian ... is rank deficient"). At 1e-6, moving the parameter by a
// whole metre or radian moves the measurements by a millionth of what the
// strongest parameter does: no effect a calibration can use, and files
// rounded to 7 decimals or more are read as their exact angles are.
inline constexpr double kNoEffectRelativeNorm = 1e-6;

// The dimension() x num_free Jacobian of one measurement's residual at the
// full parameter vector `parameters`, columns in free-parameter order (the
// measured values do not matter). Returns false with a message on bad input.
bool MeasurementJacobian(const RobotModel& model,
                         const Eigen::VectorXd& parameters,
                         const Measurement& measurement,
                         double rotation_weight_m_per_rad,
                         Eigen::MatrixXd* jacobian, std::string* error);

// The Jacobians of all `measurements`, stacked in order (rows: the sum of
// their dimensions). The message names the first bad measurement.
//
// With fixed points (point and point distance rows, point_constraints.h)
// the points' coordinates are unknowns that are not model parameters: they
// are eliminated. Each point row is evaluated at the joints nearest its
// own at which the model at `parameters` puts the marker at the mean
// predicted point of its label (ReachPoint), where the data are
// consistent as at the solution; then the coordinates' columns are
// projected out of the rows that involve them. What is left is the
// information the rows carry about the model: a label's single row none;
// a base frame moved with the points none (its columns are zero). Planes
// (plane rows, plane_constraints.h) the same way: each fitted to its
// touches at `parameters` (FitPlanes), each touch moved to the nearest
// joints that put it on that plane, the plane's 3 tangent-space columns
// (two of the normal, the offset) projected out.
bool StackedJacobian(const RobotModel& model, const Eigen::VectorXd& parameters,
                     const std::vector<Measurement>& measurements,
                     double rotation_weight_m_per_rad,
                     Eigen::MatrixXd* jacobian, std::string* error);

// Residual norms |predicted - measured| per measurement (rows as in
// measurement_residual.h), at `parameters`. A point row: the distance of
// its predicted point from the mean predicted point of its label among
// `measurements`; a point distance: the error of the distance between
// those means; a plane row: |n . p - d - radius| from the plane fitted to
// its label's touches.
bool MeasurementErrors(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const std::vector<Measurement>& measurements,
                       double rotation_weight_m_per_rad, Eigen::VectorXd* norms,
                       std::string* error);

struct PoolJacobianOptions {
  // Threads to spread the poses over; <= 0: all hardware threads. The result
  // is the same for every thread count.
  int num_threads = 0;
  // What is measured at each pool pose: kPosition (3 rows per pose) or
  // kPose (6 rows). A distance needs two poses, so it has no per-pose pool.
  MeasurementType type = MeasurementType::kPosition;
  double rotation_weight_m_per_rad = 1.0;
  // The measured marker (0-based).
  int marker = 0;
  // How far a pose's joint value may lie beyond its range (rad for a
  // revolute joint, m for a prismatic one): 0 for planned poses; measured
  // readings may use RobotModel::CheckJointValues' tolerances.
  double joint_tolerance_rad = 0.0;
  double joint_tolerance_m = 0.0;
  // Position pools use the analytic point Jacobian (core/point_jacobian.h,
  // equal to the auto-diff one to rounding, ~100x faster); false forces the
  // Ceres auto-diff residual (for comparison and benchmarks). Pose pools
  // always use auto-diff.
  bool analytic = true;
  // Called as poses are done (every few thousand).
  ProgressCallback progress;
};

// Jacobians of every pose in `joints` (one pose per row), stacked: rows
// t*i .. t*i + t-1 are pose i's rows (t = 3 or 6). Row-major, so each
// pose's block is contiguous. Returns false with a message naming the first
// bad pose.
bool PoolJacobians(const RobotModel& model, const Eigen::VectorXd& parameters,
                   const Eigen::MatrixXd& joints,
                   const PoolJacobianOptions& options, RowMatrixXd* stacked,
                   std::string* error);
// The same, written to `out` (t * joints.rows() * num_free values, the
// layout of `stacked`'s data): for a caller that owns the buffer.
bool PoolJacobians(const RobotModel& model, const Eigen::VectorXd& parameters,
                   const Eigen::MatrixXd& joints,
                   const PoolJacobianOptions& options, double* out,
                   std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_RESIDUALS_JACOBIANS_H_
