// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_evaluate: how well a robot model predicts a measurements file,
// with no fitting at all (the model as given, e.g. a calibrated one on
// poses it was not fitted to).

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>

#include "activecal/calibration/evaluate.h"
#include "activecal/report/html_report.h"
#include "app_common.h"
#include "gnuplot.h"

constexpr char kUsage[] =
    "Predicts every measurement of a measurements CSV with --robot as "
    "given (no fitting) and reports the errors: position RMSE (norm and "
    "per axis), mean, 95th percentile and max; orientation and distance "
    "errors separately.\n  activecal_evaluate --robot=calibrated.yaml "
    "--measurements=validation.csv --json_out=evaluation.json\n  "
    "activecal_evaluate --robot=cal.urdf --tip_link=tool0 "
    "--frames=frames.yaml --measurements=session2.csv";

DEFINE_string(measurements, "",
              "Measurements CSV (docs/formats.md) to predict. Required.");
DEFINE_string(points, "",
              "Points file (YAML, docs/formats.md) of known distances "
              "between the fixed points of type=point rows: their errors "
              "are reported beside each point's spread.");
DEFINE_string(json_out, "",
              "If set, write the report here: rmse_m, rmse_xyz_m, mean_m, "
              "p95_m, max_m, num_measurements, orientation and distance "
              "errors, and the error of every measurement; 'before' the "
              "same for the registration-only baseline; 'groups' per "
              "posture group with --training.");
DEFINE_string(nominal_robot, "",
              "The uncalibrated robot (same chain flags): the geometry of "
              "the registration-only 'before' report. Empty: --robot's own "
              "geometry (then 'before' is a refit of --robot, not a "
              "registration-only baseline).");
DEFINE_string(training, "",
              "Measurements CSV the model was calibrated on: the report then "
              "gives each posture group (repeated, new, out of range) its "
              "own errors, and with --nominal_robot 'before' is by default "
              "the registration fitted on it (--before).");
DEFINE_string(before, "auto",
              "What 'before' is. training: --nominal_robot's geometry with "
              "the base frame and markers fitted to --training, predicting "
              "--measurements as they are (the registration-only baseline "
              "of a calibration on --training: the fair comparison on new "
              "poses). refit: the geometry of --nominal_robot (default "
              "--robot) with the base frame and markers refitted to "
              "--measurements themselves (what that geometry allows at "
              "best). none: no 'before'. auto (default): training when "
              "--training and --nominal_robot are given, refit otherwise.");
DEFINE_string(plot, "",
              "If set, draw histograms of the position errors before "
              "(registration only) and after here (PNG, gnuplot; skipped "
              "with a note when gnuplot is missing).");
DEFINE_string(report_html, "",
              "Write the evaluation as a report a person reads: one "
              "self-contained HTML file (before and after errors in mm and "
              "deg, histograms on log bins, posture groups).");
DEFINE_bool(iso9283, false,
            "ISO 9283 pose accuracy (AP) and repeatability (RP) of the "
            "measurements as repeated cycles to commanded poses: the file's "
            "'pose' column groups the cycles, commanded_x_m.. (or _mm) and "
            "commanded_qw.. (or commanded_r11..r33) give each commanded pose "
            "in the robot's base frame (docs/iso9283.md). Printed per pose "
            "without the model (as measured) and with it (predicted after "
            "compensation by --robot); 'iso9283' in --json_out and "
            "--report_html.");
DEFINE_string(iso9283_registration, "robot",
              "With --iso9283, where the robot's base frame is in the "
              "device's: robot (--robot's base, e.g. the --frames identify "
              "wrote) or file (--robot's base and markers fitted to these "
              "measurements).");
DEFINE_double(rotation_weight, 1.0,
              "Weight of 6D pose orientation rows (m per rad) in the "
              "registration-only fit of the 'before' report.");

namespace activecal {
namespace {

void PlotHistograms(const std::vector<Measurement>& measurements,
                    const EvaluateSummary& summary) {
  std::vector<std::vector<double>> rows;
  std::string error;
  if (!BeforeAfterPositionErrorsMm(measurements, summary, &rows, &error)) {
    app::Fail("--plot: " + error);
  }
  app::PlotOrNote(
      GnuplotDataBlock("errors", rows) + PositionErrorHistogramGnuplot(rows),
      FLAGS_plot, "plot");
}

int Main() {
  if (FLAGS_measurements.empty()) app::Fail("--measurements is required");
  const RobotDescription robot = app::LoadRobotOrDie();
  const RobotModel& model = robot.model;
  // Said first, before any number: without --frames a URDF robot's base
  // is the identity, and every error below includes where the device
  // stands (hundreds of mm).
  std::printf("%s", NoFramesNote(model, !FLAGS_frames.empty()).c_str());
  EvaluateOptions options;
  const std::vector<Measurement> measurements = app::WithPointsFileOrDie(
      FLAGS_points, app::ReadMeasurementsOrDie(FLAGS_measurements, model,
                                               "measurements", &options.lines));
  options.robot_path = FLAGS_robot;
  options.chain = app::Chain();
  options.measurements_path = FLAGS_measurements;
  options.nominal_robot_path = FLAGS_nominal_robot;
  options.rotation_weight = FLAGS_rotation_weight;
  options.iso9283 = FLAGS_iso9283;
  if (FLAGS_iso9283) {
    options.commanded = app::ReadCommandedPosesOrDie(FLAGS_measurements, model);
    if (!StringToIso9283Registration(FLAGS_iso9283_registration,
                                     &options.iso9283_registration)) {
      app::Fail("--iso9283_registration must be robot or file, got '" +
                FLAGS_iso9283_registration + "'");
    }
  }
  options.training_path = FLAGS_training;
  if (!FLAGS_training.empty()) {
    options.training =
        app::ReadMeasurementsOrDie(FLAGS_training, model, "training");
  }
  if (!StringToBeforeBaseline(FLAGS_before, &options.before)) {
    app::Fail("--before must be auto, training, refit or none, got '" +
              FLAGS_before + "'");
  }
  options.json_out = FLAGS_json_out;
  options.program = app::ProgramName();
  EvaluateSummary summary;
  Evaluate(robot, measurements, options, &summary);
  if (summary.termination_type != TerminationType::kConvergence) {
    app::Fail(summary.message);
  }
  std::printf("%s", summary.report.c_str());
  if (!FLAGS_plot.empty()) PlotHistograms(measurements, summary);
  app::WriteFilesOrDie(summary.outputs);
  std::string html, error;
  if (!FLAGS_report_html.empty()) {
    if (!EvaluationHtmlText(robot, measurements, options, summary, &html,
                            &error)) {
      app::Fail(error);
    }
    app::WriteTextOrDie(FLAGS_report_html, html);
  }
  app::PrintResult(summary.result_line);
  return 0;
}

}  // namespace
}  // namespace activecal

ACTIVECAL_APP_MAIN(kUsage, activecal::Main)
