// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The report a calibration engineer hands over: one self-contained HTML
// file (figures inline as SVG, no script, no network) with the set-up, the
// errors before (registration only) and after, on the training and the
// held-out measurements, their histograms on log bins, the posture groups,
// the parameters in mm / mrad with their std and correlation matrix, the
// model-selection curve and every warning. Printable by a browser
// (chromium --headless --print-to-pdf).
//
//   CalibrationHtmlOptions options;
//   options.robot_file = "data/ur10e.urdf";
//   options.measurements_file = "measurements.csv";
//   const HtmlReport report = CalibrationHtmlReport(summary, options);
//   WriteFileAtomically(path, RenderHtml(report));
//
// Units: the tables print mm (lengths and position errors) and degrees
// (orientation errors) with 3 decimals; parameters in mm or mrad (a gain
// in per mille). Every printed number carries data-key (its name) and
// data-value (the SI value in full precision, m or rad) attributes, so
// that a test reads the numbers back and compares them with the JSON.

#ifndef ACTIVECAL_REPORT_HTML_REPORT_H_
#define ACTIVECAL_REPORT_HTML_REPORT_H_

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_outputs.h"
#include "activecal/calibration/evaluate.h"
#include "activecal/calibration/iso9283_cycles.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/model_selection.h"

namespace activecal {

// One set of errors: a model's predictions of a set of measurements.
struct ReportErrors {
  std::string key;    // data-key prefix, e.g. "after.held_out"
  std::string label;  // e.g. "after (calibrated), held out"
  EvaluationSummary errors;
  // Per measurement: the orientation error's rotation vector components
  // (rad; rows for poses only), the per-axis orientation statistics.
  std::vector<Eigen::Vector3d> rotation_vectors;
};

// Errors of `parameters` on `measurements` with the per-axis orientation
// errors: the rotation vector of R_measured^T R_predicted (rad), in the
// target frame. False with *error naming the first bad measurement.
bool ComputeReportErrors(const RobotModel& model,
                         const Eigen::VectorXd& parameters,
                         const std::vector<Measurement>& measurements,
                         const std::string& key, const std::string& label,
                         ReportErrors* out, std::string* error);

struct ReportParameter {
  std::string name;
  std::string unit;  // "m", "rad" or "" (a gain)
  double nominal = 0, estimate = 0, std = 0;
};

struct HtmlReport {
  std::string title = "activecal calibration report";
  // The set-up, one row each: (what, value).
  std::vector<std::pair<std::string, std::string>> setup;
  // Pairs of (before, after) per data set; drawn as tables and histograms.
  std::vector<ReportErrors> errors;
  // The posture groups of the held-out (or evaluated) measurements
  // relative to the training poses, after: (group name, errors).
  std::vector<ReportErrors> groups;
  std::vector<ReportParameter> parameters;
  Eigen::MatrixXd correlation;  // of `parameters`, in order (may be empty)
  // Parameters held fixed, grouped by reason: (reason, names).
  std::vector<std::pair<std::string, std::vector<std::string>>> held;
  ModelSelectionSummary selection;  // curve empty: no model selection
  std::string selection_method;
  std::vector<std::string> warnings;
  std::vector<std::string> notes;
  // ISO 9283 AP and RP per pose (activecal_evaluate --iso9283; no poses:
  // no section), drawn by Iso9283Section (iso9283_section.h).
  Iso9283CyclesSummary iso9283;
};

struct CalibrationHtmlOptions {
  std::string robot_file;         // as given to the program
  std::string measurements_file;  // "simulated" when simulated
  std::string program = "activecal_identify";
};

// The report of a successful calibration (summary.termination_type
// kConvergence): before = the registration-only baseline
// (summary.baseline, when have_baseline), after = the calibrated
// parameters, on summary.training and (when not empty) summary.validation;
// the posture groups of the validation measurements. False with *error when
// a measurement cannot be predicted.
bool CalibrationHtmlReport(const CalibrationSummary& summary,
                           const CalibrationHtmlOptions& options,
                           HtmlReport* report, std::string* error);

// The whole HTML document (UTF-8, ends with a newline).
std::string RenderHtml(const HtmlReport& report);

// MakeCalibrationOutputs and then, with options.report_html set, the HTML
// report (CalibrationHtmlReport of options.robot_file, "built-in PUMA 560"
// when empty, and options.source) after the other files. False with
// *error, "--report_html: <why>" for the report, and no files; the notes
// of outputs->notes_before are set in either case.
bool MakeCalibrationOutputsAndReport(const CalibrationSummary& summary,
                                     const std::vector<Measurement>& check,
                                     const CalibrationOutputOptions& options,
                                     CalibrationOutputs* outputs,
                                     std::string* error);

// The evaluation as a report a person reads (activecal_evaluate
// --report_html): the set-up (robot, options.measurements_path, what
// after and before are, options.training_path), the errors before (when
// summary.have_before) and after on `measurements`, after by posture group,
// and with options.iso9283 the ISO 9283 section. The errors are those of
// robot.model without its learned correction. False with *error
// ("--measurements: <why>") when a measurement cannot be predicted.
bool EvaluationHtmlText(const RobotDescription& robot,
                        const std::vector<Measurement>& measurements,
                        const EvaluateOptions& options,
                        const EvaluateSummary& summary, std::string* html,
                        std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_REPORT_HTML_REPORT_H_
