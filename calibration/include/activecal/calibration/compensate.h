// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Compensate: a robot program rewritten so that the real robot, described
// by a calibrated model, reaches where the program meant (compensation.h,
// "filtering"): the program read (a poses CSV taught with a nominal model,
// or a targets CSV of Cartesian targets), the nominal model loaded and
// checked against the calibrated one, the cell's check of the results, the
// learned correction of the robot file, the size of the correction, and
// the texts: the report printed, the result line, the compensated program
// and the JSON report. What activecal_compensate calls (one call).
//
//   CompensateOptions options;
//   options.compensation.ik.match = IkMatch::kPose;
//   options.poses_csv = "program.csv";
//   options.nominal_path = "data/puma560.yaml";
//   options.out = "compensated.csv";
//   CompensateSummary summary;
//   Compensate(robot, options, &summary);
//   summary.notes, summary.report         // stdout, in this order
//   if (summary.termination_type == TerminationType::kUserFailure) {
//     ...summary.message: one line naming the option...
//   }
//   summary.outputs                       // the files, none written yet
//   summary.compensation                  // per target (compensation.h)
//
// termination_type: kConvergence when every target converged, kFailure
// when some did not (the outputs are complete, each target with its
// status; not_converged says which), kUserFailure for bad input (message;
// no outputs).

#ifndef ACTIVECAL_CALIBRATION_COMPENSATE_H_
#define ACTIVECAL_CALIBRATION_COMPENSATE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "activecal/cell/cell_setup.h"
#include "activecal/core/types.h"
#include "activecal/io/output_files.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/kinematics/compensation.h"
#include "activecal/kinematics/corrected_compensation.h"

namespace activecal {

struct CompensateOptions {
  // The solver's options (match, tolerances, weights, threads). ik.marker
  // is set by Compensate from `marker` (when not empty); check from `cell`
  // (when not null).
  CompensationOptions compensation;
  // The marker the program places (name or number). Empty:
  // compensation.ik.marker as given.
  std::string marker = "1";
  // The robot file (--robot's path, for the messages and the JSON), its
  // chain's ends and frames file (applied to the nominal model too).
  std::string robot_path;
  UrdfChainOptions chain;
  std::string frames_path;
  // The nominal model the program was taught with (required with
  // poses_csv; with targets_csv optional: the size of the correction).
  std::string nominal_path;
  // Exactly one: the program as joint targets, or as Cartesian targets;
  // files, or in memory: with nominal_model the joint targets `joint_program`
  // (one configuration per row, taught with nominal_model, which must pass
  // CheckSameChain), without it the Cartesian `targets` (points, rotation
  // vectors, starts; pose_indices empty: 0, 1, 2, ...).
  std::string poses_csv;
  std::string targets_csv;
  bool in_memory = false;
  const RobotModel* nominal_model = nullptr;  // instead of nominal_path
  Eigen::MatrixXd joint_program;
  TargetList targets;
  // ReadTargetsCsv's columns_strict.
  bool columns_strict = false;
  // The cell set up on the calibrated robot (SetUpCell, targets not as
  // markers), with cell_path its file; null: no cell. Must outlive the
  // call.
  const CellSetup* cell = nullptr;
  std::string cell_path;
  // The outputs, if not empty: the compensated program and the JSON
  // report.
  std::string out;
  std::string json_out;
  // The program's name, at the start of the notes and of the result line.
  std::string program = "activecal";

  // Exactly one of poses_csv and targets_csv (or in_memory), the solver's
  // options valid; one line naming the options as flags.
  bool IsValid(std::string* error) const;
  // IsValid's first check alone (a program given exactly once), for a
  // caller that checks it before the solver's options are set.
  bool HasOneProgram(std::string* error) const;
};

struct CompensateSummary {
  TerminationType termination_type = TerminationType::kUserFailure;
  std::string message;  // kUserFailure: what is wrong

  // The program's labels (pose_index) and the compensation, target by
  // target (summary.starts: the program's joints, or the targets' given
  // starts).
  std::vector<int64_t> labels;
  Eigen::MatrixXd starts;
  CompensationSummary compensation;
  // The learned correction's rounds (robot.learned_correction), and the
  // size of the correction (has_correction: with a nominal model).
  CorrectionRounds rounds;
  bool has_correction = false;
  CorrectionSize correction;

  // The notes of the targets file ("<program>: note: ...\n" lines), printed
  // before the report, also when the call fails.
  std::string notes;
  // The report: the compensation's, the learned correction's rounds, the
  // size of the correction and "wrote N compensated targets to <out>".
  std::string report;
  // The one-line result (what --quiet prints), without a newline.
  std::string result_line;
  // kFailure: "<counts>, written with their status to <out><first ones>".
  std::string not_converged;
  // out and json_out when set: to be written together.
  std::vector<OutputFile> outputs;
};
// Comma-separated joint weights ("10,10,1,1,1,1") into *weights (empty
// text: none). False with *error "--joint_weights: 'x' is not a number
// (comma-separated weights, one per joint)".
bool ParseJointWeights(const std::string& text, std::vector<double>* weights,
                       std::string* error);

// Said first, before anything else, when the robot is a URDF and no frames
// file is given (a URDF carries neither the base frame nor the markers a
// calibration found): "activecal_compensate: note: --robot=<robot_path> has
// no --frames: ...\n", naming tip_link when set; empty otherwise.
std::string UrdfWithoutFramesNote(const std::string& robot_path,
                                  const std::string& frames_path,
                                  const std::string& tip_link);

// Compensates the program of `options` for `robot` (the calibrated model,
// with its learned correction if any).
void Compensate(const RobotDescription& robot, const CompensateOptions& options,
                CompensateSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_COMPENSATE_H_
