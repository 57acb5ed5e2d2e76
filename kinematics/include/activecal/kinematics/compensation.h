// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Compensation ("filtering"): rewrite a robot program so that the real
// robot, described by a calibrated model, reaches where the program meant.
//
// What a program means: a joint program taught or computed with the
// nominal model means the points (or poses) the nominal geometry (links,
// joint offsets and gains, tool) puts its marker at, with the robot placed
// by the *calibrated* base frame. The base frame is metrology (where the
// device stands relative to the robot), not geometry: a program taught in
// the robot's frame means its points relative to the robot. So
// compensation corrects the geometry only. Each target is then solved with
// the inverse kinematics of the calibrated model (inverse_kinematics.h),
// starting from the programmed joints: the smallest joint change that
// reaches the meant point, inside the joint limits.
//
//   CompensationOptions options;
//   options.ik.match = IkMatch::kPosition;
//   options.num_threads = 2;
//   CompensationSummary summary;
//   CompensateProgram(calibrated_model, calibrated_values, nominal_model,
//                     nominal_values, program_joints, options, &summary);
//   std::cout << summary.BriefReport();
//   // summary.results[i].joints: the compensated joints of program row i
//
// Every target gets a result, in the program's order, with its status;
// a target that fails keeps the best configuration found (inside the
// limits) and says why in its message. The summary's termination_type is
// CONVERGENCE when every target converged, FAILURE when some did not (the
// results are complete), USER_FAILURE for invalid input (message says
// what).

#ifndef ACTIVECAL_KINEMATICS_COMPENSATION_H_
#define ACTIVECAL_KINEMATICS_COMPENSATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/io/targets_csv.h"
#include "activecal/kinematics/inverse_kinematics.h"

namespace activecal {

// True when the two models describe the same chain: the same number of
// joints, the same joint types, the same base convention and the same
// number of markers. Otherwise false with one line in *error naming the
// first difference ("joint 3: calibrated is prismatic, nominal revolute").
bool CheckSameChain(const RobotModel& calibrated, const RobotModel& nominal,
                    std::string* error);

// The parameters of what a program means: `nominal_values` (a full vector
// of `nominal`) with the base block taken from `calibrated_values`. The
// models must pass CheckSameChain.
Eigen::VectorXd ProgramMeaningParameters(
    const RobotModel& calibrated, const Eigen::VectorXd& calibrated_values,
    const RobotModel& nominal, const Eigen::VectorXd& nominal_values);

struct CompensationOptions {
  // Match and tolerances of each target's inverse kinematics.
  InverseKinematicsOptions ik;
  // Threads (<= 0: all hardware threads); the results do not depend on it.
  int num_threads = 1;
  // The cell's check of a solution (e.g. CellCompensationCheck,
  // calibration/cell_planning.h): false, with the first reason in
  // *reason, for a configuration the robot cannot run (it collides, or
  // leaves a joint margin). Called for every converged result, in target
  // order, on the calling thread; a configuration it refuses gets status
  // kCollision and the reason as its message. Null: no check.
  std::function<bool(const Eigen::VectorXd& joints, std::string* reason)> check;
};

struct CompensationSummary {
  TerminationType termination_type = TerminationType::kUserFailure;
  // Empty on CONVERGENCE; otherwise what went wrong (USER_FAILURE) or how
  // many targets failed and the first of them (FAILURE).
  std::string message;
  // What each target means (device frame) and its result, in input order.
  std::vector<IkTarget> targets;
  std::vector<InverseKinematicsResult> results;
  int num_converged = 0;
  int num_singular = 0;
  int num_limit = 0;
  int num_unreachable = 0;
  int num_invalid = 0;
  int num_iteration_cap = 0;
  int num_collision = 0;  // converged, refused by options.check
  // Over the targets: the inverse kinematics' largest residual, position
  // (m) and rotation (rad), of the calibrated model at its own solution
  // (about 0 when every target converged: not an accuracy figure, see
  // MeasureCorrection for the size of the correction); largest change of
  // any joint (rad or m), RMS of the per-target Euclidean joint change.
  double max_position_error_m = 0.0;
  double max_rotation_error_rad = 0.0;
  double max_joint_change = 0.0;
  double rms_joint_change = 0.0;
  double seconds = 0.0;
  // The configuration each target's solve started from (the joint changes
  // are from these): one row per target.
  Eigen::MatrixXd starts;

  bool AllConverged() const;
  // The targets that are not converged, per status, the first of each by
  // its target index (0-based, input order), with its message:
  // "2 of 3 targets are not converged: 1 unreachable (the first, target 1:
  // out of reach ...), 1 collision (the first, target 2: obstacle table
  // (L6))". With `labels` (one per target, e.g. the program's pose_index)
  // each first also gets ", pose_index <label>". Empty when all converged.
  std::string NotConvergedText(
      const std::vector<int64_t>& labels = std::vector<int64_t>()) const;
  // A paragraph: counts per status, errors left, joint changes, time.
  std::string BriefReport() const;
};

// The cell's check of the converged results (options.check), then the
// counts, maxima and termination of summary->results against
// summary->starts (done by the functions below; for a caller that changes
// the results, e.g. corrected_compensation.h).
void SummarizeCompensation(const CompensationOptions& options,
                           CompensationSummary* summary);

// The size of a compensation: how far the nominal model (at `values`, for a
// program the meaning parameters, ProgramMeaningParameters) puts the marker
// `marker` at the compensated joints from each target, i.e. the error the
// compensation removes, over the targets the calibrated model reaches
// (status converged or singular; a cell's refusal after the solve is a
// collision and not counted). Rotation:
// the angle of the relative rotation (0 unless `with_rotation`).
struct CorrectionSize {
  int num_targets = 0;  // the targets counted
  double max_position_m = 0.0;
  double rms_position_m = 0.0;
  double max_rotation_rad = 0.0;
  double rms_rotation_rad = 0.0;
};
CorrectionSize MeasureCorrection(const RobotModel& nominal,
                                 const Eigen::VectorXd& values, int marker,
                                 bool with_rotation,
                                 const CompensationSummary& summary);

// Compensates a joint program (one configuration per row, SI units) taught
// with `nominal`, for the robot described by `calibrated` (see the top of
// this file). Each row must be inside the calibrated model's joint limits.
void CompensateProgram(const RobotModel& calibrated,
                       const Eigen::VectorXd& calibrated_values,
                       const RobotModel& nominal,
                       const Eigen::VectorXd& nominal_values,
                       const Eigen::MatrixXd& program,
                       const CompensationOptions& options,
                       CompensationSummary* summary);

// Compensates Cartesian targets (device frame) for the robot `model` with
// parameters `values`. `starts`: one start configuration per target (e.g.
// the controller's own solution), or no rows: each target then starts from
// the previous target's result (a path), the first from `first_start`
// (the middle of the joint ranges when it is empty). Without starts the
// targets are solved in order on one thread.
void CompensateTargets(const RobotModel& model, const Eigen::VectorXd& values,
                       const std::vector<IkTarget>& targets,
                       const Eigen::MatrixXd& starts,
                       const Eigen::VectorXd& first_start,
                       const CompensationOptions& options,
                       CompensationSummary* summary);

// The targets of a targets CSV: points, and rotations from the rotation
// vectors (identity when the file has none). A non-finite rotation vector
// gives a non-finite rotation, which the solver reports invalid ("the
// target is not finite").
std::vector<IkTarget> IkTargetsFromList(const TargetList& list);

// The poses CSV (csv_files.h: pose_index, q<j>_rad or _m, q<j>_deg or _mm)
// of the compensated joints, with two more columns: `status`
// (IkStatusName) and `position_error_m`. It reads back with ReadPosesCsv.
// `pose_indices`: the labels of the rows (empty: 0, 1, 2, ...).
std::string CompensatedPosesCsvText(const RobotModel& model,
                                    const std::vector<int64_t>& pose_indices,
                                    const CompensationSummary& summary);

}  // namespace activecal

#endif  // ACTIVECAL_KINEMATICS_COMPENSATION_H_
