// The analytic parameter Jacobian of a measured point: one forward pass
// through the chain, then every parameter's column as the screw it moves
// the point along. The selection pool's fast path (issue #17): the same
// derivative as the Ceres auto-diff residual (measurement_residual.h),
// checked against it to 1e-12 on every convention, without the Jets.
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

#ifndef ACTIVECAL_CORE_POINT_JACOBIAN_H_
#define ACTIVECAL_CORE_POINT_JACOBIAN_H_

#include <Eigen/Core>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

// Reusable work space of MeasuredPointJacobian (no allocation per call
// once sized): construct once per thread.
class PointJacobianWorkspace {
 public:
  explicit PointJacobianWorkspace(const RobotModel& model);

  // What a URDF link's transform and columns need that depends on its
  // parameter block only (not on the joint reading): the sines and
  // cosines of its correction angles and the rotations made of them,
  // computed once per block value instead of once per pose (a pool's poses
  // share the parameters).
  struct UrdfLinkCache {
    // The block's values, the link's nominal origin_rotation (9 entries)
    // and its axis.
    static constexpr int kKeySize = kMaxBlockSize + 9 + 3;
    bool valid = false;
    // The key the entries were computed from (compared bit for bit: a
    // workspace reused for another model, or -0.0 for 0.0, recomputes).
    double key[kKeySize] = {};
    Eigen::Matrix3d origin_rotation;      // Ro
    Eigen::Matrix3d correction_rotation;  // Rc
    Eigen::Matrix3d link_rotation;        // Ro Rc
    Eigen::Vector3d axis;                 // Rc * link.axis
    Eigen::Vector3d ax, ay;               // RpyAxes of the correction
  };

 private:
  friend void MeasuredPointJacobian(const RobotModel&, const double* const*,
                                    const double*, int, PointJacobianWorkspace*,
                                    double*);
  std::vector<UrdfLinkCache> urdf_;
  std::vector<Eigen::Matrix3d> parent_rotation_;
  std::vector<Eigen::Vector3d> parent_translation_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> full_;  // 3 x num_parameters
  std::vector<int> free_indices_;
  std::vector<int> block_offsets_;
};

// The 3 x num_free Jacobian of the measured point of `marker` (0-based) at
// joint readings q (model.num_joints() values) and the parameter blocks
// `blocks` (kinematics.h layout), written row-major to `jacobian`
// (3 * num_free values, free-parameter order): the derivative of the
// position residual, predicted minus measured. The workspace must have
// been made for `model`.
void MeasuredPointJacobian(const RobotModel& model, const double* const* blocks,
                           const double* q, int marker,
                           PointJacobianWorkspace* workspace, double* jacobian);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_POINT_JACOBIAN_H_
