// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Inverse kinematics of any activecal RobotModel (standard DH, modified DH,
// Hayati, URDF joints; revolute and prismatic joints; joint offsets and
// gains; any marker): the joint values that put a marker at a target point,
// or the marker's frame at a target pose, closest to a start configuration
// and inside the joint limits.
//
//   InverseKinematicsOptions options;
//   options.match = IkMatch::kPose;          // point + orientation
//   IkTarget target;
//   target.point = {0.4, 0.1, 0.6};          // m, in the device's frame
//   target.rotation = R;                     // marker frame in that frame
//   InverseKinematicsResult result;
//   SolveInverseKinematics(model, parameters, target, q_start, options,
//                          &result);
//   if (result.status != IkStatus::kConverged) { ... result.message ... }
//
// Method: Levenberg-Marquardt (damped least squares) on the exact joint
// Jacobian, computed with Ceres Jets through the templated kinematics
// (kinematics.h). The step is the damped minimum-norm step towards the
// target plus, in the null space, a pull back to the start:
//
//   dq = W^-1 J^T (J W^-1 J^T + lambda I)^-1 (r + J z) - z,
//   z = q - q_start,  W = diag(joint_weights),
//
// which, as lambda -> 0, converges to the solution closest to the start
// (min |q - q_start|_W subject to reaching the target, |x|_W^2 =
// sum_j w_j x_j^2). A chain without spare joints has no null space and
// takes no pull (in a damped step the pull leaks into directions the
// Jacobian barely moves and holds the iterate short of the target). A
// redundant arm
// (7 axes, or a 6-axis arm matched on position only) therefore stays on the
// start's branch instead of jumping to another. With the joint limits each
// step is the minimiser of the same damped merit subject to the limits
// (a box-constrained least squares, solved exactly by an active-set
// method), so the configuration returned is always inside them.
//
// The smallest joint change, with limits: the run inside the limits and,
// when it does not reach the target or meets a limit on the way, a run
// without them are the candidates; each revolute joint of each is turned
// by whole periods (2 pi / |gain|) to the equivalent value inside its
// limits nearest the start (a UR's +-2 pi joints, a joint of range exactly
// 2 pi, a continuous joint), and of the candidates that reach the target
// the one of smallest weighted change |q - q_start|_W is returned. When
// that best candidate still turns a joint by more than half a turn,
// `restarts` more runs inside the limits from points spread around the
// start look for other solutions (another branch of the arm, close to the
// start near a singularity) of smaller change. A joint is therefore turned
// a whole turn only when no solution inside the limits of smaller change
// was found.
//
// Units: metres and radians; joint values in SI (rad, or m for prismatic
// joints). Rotation residual: the rotation vector of R_target R(q)^T (rad),
// weighted by rotation_weight_m (m/rad) in the least-squares merit.
//
// Status of each solve:
//   converged    position (and rotation) error within tolerance at a
//                well-conditioned configuration
//   singular     the target is reached at a configuration whose Jacobian
//                is rank-deficient
//                (sigma_min / sigma_max < singular_threshold): nearby
//                targets may need large joint motions
//   limit        not reached inside the joint limits, but reached when the
//                limits are lifted: the solution near the start lies beyond
//                a limit (message names the joint and value)
//   iteration_cap
//                not reached when max_iterations Jacobian evaluations were
//                used up (the error was still falling, or the solver was
//                crawling along a near-singular direction); the
//                configuration reached is returned, and a larger
//                max_iterations may reach the target
//   unreachable  the error stays above tolerance: the target is out of
//                the robot's reach (outside the workspace, or an
//                orientation it cannot take); the closest configuration
//                found is returned
//   invalid      bad input (a non-finite target or start, a start outside
//                the limits, wrong sizes); the start is returned unchanged

#ifndef ACTIVECAL_KINEMATICS_INVERSE_KINEMATICS_H_
#define ACTIVECAL_KINEMATICS_INVERSE_KINEMATICS_H_

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

// The largest chain the inverse kinematics takes (joints).
inline constexpr int kMaxIkJoints = 16;

// What to match: the marker's point (3 equations) or its full pose (6).
enum class IkMatch { kPosition, kPose };

// "position", "pose".
const char* IkMatchName(IkMatch match);
// Parses "position" or "pose"; false otherwise.
bool ParseIkMatch(const std::string& text, IkMatch* match);

enum class IkStatus {
  kConverged,
  kSingular,
  kLimit,
  kUnreachable,
  kInvalid,
  kIterationCap,
  // Converged, but the configuration fails a check of the cell it runs in
  // (collision, joint margin): set by the compensation
  // (CompensationOptions::check), never by the solver.
  kCollision,
};

// "converged", "singular", "limit", "unreachable", "invalid",
// "iteration_cap", "collision".
const char* IkStatusName(IkStatus status);

// A target for the marker, in the device's frame (the base frame's parent).
struct IkTarget {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // m
  // The marker frame's orientation (marker angles applied to the tip
  // frame, as kinematics.h's TargetFrame); used with IkMatch::kPose only.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

struct InverseKinematicsOptions {
  IkMatch match = IkMatch::kPosition;
  // The marker to place (0-based).
  int marker = 0;
  // Converged when the point is within this distance of the target (m) ...
  double position_tolerance_m = 1e-9;
  // ... and, for kPose, the orientation within this angle (rad).
  double rotation_tolerance_rad = 1e-9;
  // Metres per radian of orientation error in the merit (kPose).
  double rotation_weight_m = 1.0;
  // Jacobian evaluations per run of Levenberg-Marquardt (a solve makes
  // one run inside the limits, one without them when the first met a
  // limit, and the restarts, each of at most min(max_iterations, 30));
  // InverseKinematicsResult::iterations counts them all.
  int max_iterations = 100;
  // The weight of each joint in the joint change |q - q_start|_W^2 =
  // sum_j w_j (q_j - q_start_j)^2 that the solver minimises and the
  // candidates are ranked by (per rad, or per m for a prismatic joint).
  // Empty: 1 each (rad and m alike); otherwise num_joints() values > 0.
  std::vector<double> joint_weights;
  // When the best solution found turns a revolute joint by more than half
  // a turn from the start: this many more runs inside the limits, from
  // starts with each revolute joint moved by up to restart_spread_rad
  // (a Halton sequence: deterministic), for a solution of smaller change.
  int restarts = 24;
  double restart_spread_rad = M_PI;
  // sigma_min / sigma_max of the (weighted) Jacobian below which a
  // configuration counts as singular.
  double singular_threshold = 1e-6;
  // False lifts the joint limits (for diagnosis only): the configuration
  // returned may then be outside them, and no target gets kLimit.
  bool respect_limits = true;

  // False with the reason in *error for an option out of range.
  bool IsValid(std::string* error) const;
};

struct InverseKinematicsResult {
  IkStatus status = IkStatus::kInvalid;
  // The configuration found, inside the joint limits whenever
  // respect_limits is set (the start for kInvalid).
  Eigen::VectorXd joints;
  // |target point - point reached| (m), and the angle between the target
  // and reached orientations (rad; kPose only, else 0).
  double position_error_m = 0.0;
  double rotation_error_rad = 0.0;
  // Jacobian evaluations used.
  int iterations = 0;
  // sigma_min / sigma_max of the (weighted) Jacobian at `joints`.
  double conditioning = 0.0;
  // Empty when converged; otherwise one line saying why.
  std::string message;
};

// The marker frame at q and the exact joint Jacobian there (Ceres Jets):
// rows 0-2 the derivative of the point (m per rad or m per m), rows 3-5
// the angular velocity of the frame in the device's frame (rad per unit of
// q), one column per joint. False with a message for a model of more than
// kMaxIkJoints joints or wrong sizes.
bool JointJacobian(const RobotModel& model, const Eigen::VectorXd& parameters,
                   const Eigen::VectorXd& q, int marker, Eigen::Matrix3d* R,
                   Eigen::Vector3d* t, Eigen::MatrixXd* jacobian,
                   std::string* error);

// Solves one target from `start` (model.num_joints() values). `parameters`
// is a full parameter vector (model.num_parameters()), e.g. a calibrated
// model's.
void SolveInverseKinematics(const RobotModel& model,
                            const Eigen::VectorXd& parameters,
                            const IkTarget& target,
                            const Eigen::VectorXd& start,
                            const InverseKinematicsOptions& options,
                            InverseKinematicsResult* result);

// Solves many targets, target i from row i of `starts`, on num_threads
// threads (ParallelFor: the results do not depend on the thread count).
void SolveInverseKinematicsBatch(const RobotModel& model,
                                 const Eigen::VectorXd& parameters,
                                 const std::vector<IkTarget>& targets,
                                 const Eigen::MatrixXd& starts,
                                 const InverseKinematicsOptions& options,
                                 int num_threads,
                                 std::vector<InverseKinematicsResult>* results);

}  // namespace activecal

#endif  // ACTIVECAL_KINEMATICS_INVERSE_KINEMATICS_H_
