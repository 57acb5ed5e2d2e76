// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The analytic parameter Jacobian of a measured point: one forward pass
// through the chain, then every free parameter's column as the screw it
// moves the point along. The selection pool's fast path (issues #17, #32):
// the same derivative as the Ceres auto-diff residual
// (measurement_residual.h), checked against it to 1e-12 on every
// convention, without the Jets.
//
// For a parameter of block b (base, link or marker) whose transform maps a
// point x of its own frame to y = L_b x in its parent frame P_b:
//
//   d p / d theta = R_{P_b} * d(L_b x) / d theta,
//
// and d(L_b x)/d theta is, per elementary motion of the block: a
// translation along a unit axis u -> u; a rotation about axis u through
// origin o -> u x (y - o) (both expressed in P_b); gains multiply the
// joint motion's column by the joint reading q.
//
// PointJacobianKernel does, once per parameter vector, everything that does
// not depend on the joint readings: the sines and cosines of the twists
// (alpha, beta), the whole base transform, the URDF origin and correction
// rotations, and the column layout (which entry of which block lands in
// which output column; only the free columns are formed). A pose then
// costs one sine and cosine per joint, the chain's products and one 3 x 3
// product per free column. Every pose is computed by the same expressions
// in the same order whatever the batch or thread it is in, so a pose's
// Jacobian is the same bits for any batching and thread count (and the
// same bits as the per-pose MeasuredPointJacobian).

#ifndef ACTIVECAL_CORE_POINT_JACOBIAN_H_
#define ACTIVECAL_CORE_POINT_JACOBIAN_H_

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

// The Jacobians of the measured point of one marker, at one parameter
// vector, for many poses. Immutable after construction: one kernel may be
// used from several threads at once.
class PointJacobianKernel {
 public:
  // `blocks`: the parameter blocks (kinematics.h layout), copied here. The
  // model must be valid (RobotModel::Validate) and outlive the kernel;
  // `marker` is 0-based.
  PointJacobianKernel(const RobotModel& model, const double* const* blocks,
                      int marker = 0);
  ~PointJacobianKernel();
  PointJacobianKernel(PointJacobianKernel&&) noexcept;
  PointJacobianKernel& operator=(PointJacobianKernel&&) noexcept;

  // model.num_free(): the columns, in free-parameter order.
  int num_columns() const;

  // Evaluates `num_poses` poses, joint j of pose i being
  // joints[i * pose_stride + j * joint_stride] (a column-major
  // poses x joints matrix: pose_stride 1, joint_stride its rows; one pose
  // after another: pose_stride num_joints, joint_stride 1). Writes pose i's
  // 3 x num_columns() Jacobian row-major at jacobian + 3 i num_columns():
  // the derivative of the measured point in the device's frame (m per
  // unit of the parameter: m/m, m/rad, m per unit gain) = the derivative
  // of the position residual, predicted minus measured.
  void Evaluate(int64_t num_poses, const double* joints, int64_t pose_stride,
                int64_t joint_stride, double* jacobian) const;

 private:
  struct Plan;
  std::unique_ptr<const Plan> plan_;
};

// Reusable work space of MeasuredPointJacobian: keeps the kernel of the
// last parameter values and marker it saw (compared bit for bit) so that
// calls at the same parameters do the pose-independent work once.
// Construct once per thread, for one model.
class PointJacobianWorkspace {
 public:
  explicit PointJacobianWorkspace(const RobotModel& model);
  ~PointJacobianWorkspace();

 private:
  friend void MeasuredPointJacobian(const RobotModel&, const double* const*,
                                    const double*, int, PointJacobianWorkspace*,
                                    double*);
  std::vector<double> key_;
  std::unique_ptr<PointJacobianKernel> kernel_;
};

// The 3 x num_free Jacobian of the measured point of `marker` (0-based) at
// joint readings q (model.num_joints() values) and the parameter blocks
// `blocks` (kinematics.h layout), written row-major to `jacobian`
// (3 * num_free values, free-parameter order): the derivative of the
// position residual, predicted minus measured. One pose of
// PointJacobianKernel (the same bits). The workspace must have been made
// for `model`.
void MeasuredPointJacobian(const RobotModel& model, const double* const* blocks,
                           const double* q, int marker,
                           PointJacobianWorkspace* workspace, double* jacobian);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_POINT_JACOBIAN_H_
