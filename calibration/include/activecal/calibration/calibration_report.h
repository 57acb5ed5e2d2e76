// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// What activecal_identify prints and writes for a calibration
// (calibrate.h): the lines of the stages as they ran, the estimates table
// and the closing lines, the note on what was held fixed, and the JSON
// report (docs/formats.md, "identify report").
//
//   CalibrationTextOptions text;            // "--" option spelling
//   text.angle_unit = robot.angle_unit;      // the table in the file's units
//   std::cout << CalibrationStagesText(summary, text);
//   std::cout << CalibrationResultText(summary, text);
//   const std::string json = CalibrationJson(summary, json_options);

#ifndef ACTIVECAL_CALIBRATION_CALIBRATION_REPORT_H_
#define ACTIVECAL_CALIBRATION_CALIBRATION_REPORT_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/io/robot_file.h"

namespace activecal {

// How the messages name the calibration's options: as the program's flags
// ("--auto_fix", "--register_base=false") or as the Python module's keyword
// arguments ("auto_fix=True", "register_base=False").
enum class OptionSpelling { kFlags, kKeywords };

struct CalibrationTextOptions {
  OptionSpelling option_spelling = OptionSpelling::kFlags;
  // The notes on stdout start "<program>: ".
  std::string program = "activecal";
  // The table's unit of angles (the robot file's: what --model_out
  // writes); the JSON stays SI.
  AngleUnit angle_unit = AngleUnit::kRadian;
  // The true parameter vector (a simulation): a truth column and the count
  // of estimates more than 4 std from it. Empty: none.
  Eigen::VectorXd true_parameters;
  // The held-fixed note names the calibrated model file ("not in 'free' of
  // --model_out").
  bool model_out = false;
};

// The lines of the stages up to model selection, in order: the
// registration, each parameter the set's reduction held and why, the note
// on what the reduction or the auto-fix held, the model selection's report.
// For a failed calibration, those of the stages it passed.
std::string CalibrationStagesText(const CalibrationSummary& summary,
                                  const CalibrationTextOptions& options);

// After a successful calibration: the estimates table (nominal, estimate,
// std, the scaled std when the stated sigmas are implausible, the truth),
// the fit's report, the baseline and validation lines, the warnings, the
// held-fixed note and the outliers (their indices in the input).
std::string CalibrationResultText(const CalibrationSummary& summary,
                                  const CalibrationTextOptions& options);

// The errors of data with 6D poses told apart. The fit's RMS residual
// weights a pose's rotation rows by the rotation weight (m per rad), so on
// 6D data it changes with the weight and is no position error: what is
// printed, written and reported there is the position RMS over every
// measured point (m) and the rotation RMS over the poses' orientations
// (the angle of R_measured^T R_predicted, rad), EvaluateModel's
// (evaluation.h). num_poses is 0 when `data` hold no 6D pose (the
// position-only output is unchanged) or cannot be evaluated.
struct PoseErrorRms {
  int num_poses = 0;
  double position_m = 0;
  double rotation_rad = 0;
};
PoseErrorRms PoseErrorRmsOf(const RobotModel& model,
                            const Eigen::VectorXd& parameters,
                            const std::vector<Measurement>& data);

// The result in one line (what --quiet prints): "13 of 54 parameters
// identified from 23 measurements, RMS 3.269 mm (registration only 3.603
// mm)[, held out: 3.9 mm RMS on 5 measurements]", errors in mm with 3
// decimals. On 6D data position and rotation apart (PoseErrorRms): "...,
// RMS position 2.345 mm, rotation 4.567 mrad (registration only 2.9 mm,
// 5.1 mrad)[, held out: 3.1 mm, 4.0 mrad RMS on 5 measurements]".
std::string CalibrationResultLine(const CalibrationSummary& summary);

// "<stages>: held fixed at their nominal values (not in 'free'[ of
// --model_out]): a b c", the stages named as options
// ("--parameter_set=full and --model_selection=cv"); empty when nothing was
// held.
std::string HeldFixedNote(const CalibrationSummary& summary,
                          const CalibrationTextOptions& options);

// The failure as the caller reports it: summary.message with the
// calibration's options named in the caller's spelling
// ("--parameter_set=full: ...", "--model_selection: ...") and the hint of
// the failed stage: a failed registration suggests a frames file and
// register_base off; an unidentifiable file set (auto_fix_would_help)
// suggests fixing parameters or auto_fix.
std::string CalibrationFailureText(const CalibrationSummary& summary,
                                   const CalibrationTextOptions& options);

// A message of CalibrationOptions::IsValid (or LearnedResidualIsValid)
// with the options named in the caller's spelling ("--folds must be >= 2",
// "--learned_residual with --compliance or --harmonics: ...").
std::string OptionsErrorText(const std::string& message,
                             const CalibrationTextOptions& options);

// The learned residual's report (options.learned_residual.mode on or
// auto): LearnedResidualSummary::BriefReport and, when it was computed,
// "  validation (N held-out position measurements): RMS A mm parametric, B
// mm with the correction"; empty for kOff.
std::string LearnedResidualText(const CalibrationSummary& summary);

// The model selection's curve for a plot: (parameters kept, training RMS
// mm, held-out RMS mm) of each point fitted.
std::vector<std::vector<double>> SelectionCurveRows(
    const CalibrationSummary& summary);
// The gnuplot commands drawing the data block $curve (SelectionCurveRows):
// the title naming the method, both RMS against the count, the count kept
// marked by a dashed line.
std::string SelectionCurveGnuplot(const CalibrationSummary& summary);

struct CalibrationJsonOptions {
  std::string measurements = "simulated";  // the input's name
  std::string validation;  // the selection_validation file's name, if any
  Eigen::VectorXd true_parameters;  // empty: none
  // A simulation's lattice poses and noise (empty, 0: not simulated).
  std::vector<int64_t> simulated_poses;
  double noise_m = 0;
  bool simulated = false;
};

// The JSON report of a successful calibration (2-space indented, ending
// with a newline).
std::string CalibrationJson(const CalibrationSummary& summary,
                            const CalibrationJsonOptions& options);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_CALIBRATION_REPORT_H_
