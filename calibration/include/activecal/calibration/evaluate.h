// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Evaluate: how well a robot model predicts measurements, with no fitting
// of the model itself (e.g. a calibrated model on poses it was not fitted
// to): the errors of every row with the model as given (and its learned
// correction), the registration-only 'before' baseline (the base frame and
// markers of a nominal geometry refitted), the fixed points' spread and
// the planes' flatness, the ISO 9283 cycle figures, the posture groups
// against the training poses, and the texts: the report printed, the
// result line and the JSON report. What activecal_evaluate calls (one
// call); the HTML report and the plot are drawn from the summary.
//
//   EvaluateOptions options;
//   options.measurements_path = "validation.csv";
//   options.json_out = "evaluation.json";
//   EvaluateSummary summary;
//   Evaluate(robot, measurements, options, &summary);
//   if (summary.termination_type != TerminationType::kConvergence) {
//     ...summary.message: one line naming the option...
//   }
//   std::cout << summary.report;
//   summary.outputs  // the JSON report, not written yet

#ifndef ACTIVECAL_CALIBRATION_EVALUATE_H_
#define ACTIVECAL_CALIBRATION_EVALUATE_H_

#include <string>
#include <vector>

#include "activecal/calibration/iso9283_cycles.h"
#include "activecal/core/measurement.h"
#include "activecal/core/types.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/registration_fit.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/output_files.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

// What 'before' is. kTraining: the nominal geometry with the base frame
// and markers fitted to the training measurements, predicting the
// measurements as they are. kRefit: the nominal geometry (default the
// robot's) refitted to the measurements themselves. kNone: no 'before'.
// kAuto: kTraining with training measurements and a nominal robot, kRefit
// otherwise.
enum class BeforeBaseline { kAuto, kTraining, kRefit, kNone };
// "auto", "training", "refit", "none".
const char* BeforeBaselineToString(BeforeBaseline before);
bool StringToBeforeBaseline(const std::string& text, BeforeBaseline* before);

// Where the ISO 9283 figures put the robot's base frame: kRobot, the
// robot's own; kFile, its base and markers fitted to the measurements.
enum class Iso9283Registration { kRobot, kFile };
// "robot", "file".
const char* Iso9283RegistrationToString(Iso9283Registration registration);
bool StringToIso9283Registration(const std::string& text,
                                 Iso9283Registration* registration);

struct EvaluateOptions {
  // The files, for the messages and the JSON (read by the caller): the
  // robot, the measurements.
  std::string robot_path;
  std::string measurements_path;
  // The uncalibrated robot (loaded with `chain`), the geometry of 'before'.
  // Empty: the robot's own (then 'before' is a refit, not a
  // registration-only baseline).
  std::string nominal_robot_path;
  UrdfChainOptions chain;
  // The measurements the model was calibrated on (training_path their
  // file): each posture group then gets its own errors. Empty: none.
  std::vector<Measurement> training;
  std::string training_path;
  BeforeBaseline before = BeforeBaseline::kAuto;
  // Weight of 6D orientation rows (m per rad) of the registration fits.
  double rotation_weight = 1.0;
  // ISO 9283 pose accuracy and repeatability of the measurements as
  // repeated cycles to `commanded` (ReadCommandedPosesCsv of the
  // measurements file); `lines`: each measurement's line in its file.
  bool iso9283 = false;
  Iso9283Registration iso9283_registration = Iso9283Registration::kRobot;
  std::vector<CommandedPose> commanded;
  std::vector<int> lines;
  // If not empty, the JSON report is an output.
  std::string json_out;
  // The program's name, at the start of the result line.
  std::string program = "activecal";
};

struct EvaluateSummary {
  // kConvergence: evaluated; kUserFailure: bad input (message).
  TerminationType termination_type = TerminationType::kUserFailure;
  std::string message;

  // 'after': the robot as given, with its learned correction.
  EvaluationSummary after;
  // 'before' (have_before: its fit converged; otherwise baseline.message
  // says why); `kind` resolved from kAuto; `description` says what it is.
  BeforeBaseline kind = BeforeBaseline::kNone;
  std::string description;
  bool have_before = false;
  RegistrationFitSummary baseline;
  RobotModel nominal;  // the geometry of 'before'
  EvaluationSummary before;
  // With options.iso9283.
  Iso9283CyclesSummary iso9283;
  // With training measurements: each measurement's posture group.
  std::vector<PostureGroup> groups;

  // The report: the evaluation's, what 'after' and 'before' are, their
  // lines, the notes, the points and planes, the ISO 9283 table, the
  // posture groups' lines.
  std::string report;
  // The one-line result (what --quiet prints), without a newline.
  std::string result_line;
  // The JSON report when options.json_out is set.
  std::vector<OutputFile> outputs;
};

// The measurements of `all` in posture group `group` (`groups`: one per
// measurement).
std::vector<Measurement> PostureGroupSubset(
    const std::vector<Measurement>& all,
    const std::vector<PostureGroup>& groups, PostureGroup group);

// The histograms of the position errors before and after: one row
// {before, after} (mm) per measurement with a position error (distance rows
// left out). False with *error when there is nothing to compare: "no
// 'before' to compare with (--before=none)" (or ": <why the fit failed>"),
// "the histograms are of position errors, and the measurements have none
// (distances only)"; or when the summary's errors are not one per
// measurement (a summary of other measurements).
bool BeforeAfterPositionErrorsMm(const std::vector<Measurement>& measurements,
                                 const EvaluateSummary& summary,
                                 std::vector<std::vector<double>>* rows,
                                 std::string* error);

// The gnuplot commands after the data block $errors (rows of
// BeforeAfterPositionErrorsMm) drawing both histograms, before and after,
// in bins of a 30th of the largest error.
std::string PositionErrorHistogramGnuplot(
    const std::vector<std::vector<double>>& rows);

// Said before any number when `model` has a 'frame' base at the identity
// and no frames file is given: "note: no --frames: the robot's base frame
// is the identity, ...\n"; empty otherwise.
std::string NoFramesNote(const RobotModel& model, bool frames_given);

// Evaluates `robot` (the model as given, with its learned correction) on
// `measurements`.
void Evaluate(const RobotDescription& robot,
              const std::vector<Measurement>& measurements,
              const EvaluateOptions& options, EvaluateSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_EVALUATE_H_
