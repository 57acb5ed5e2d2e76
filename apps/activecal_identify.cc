// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_identify: identify a robot's kinematic parameters from
// measurements (a CSV file from the device, or simulated ones), validate on
// held-out measurements, and write the calibrated model and a report: the
// flags as CalibrationOptions, one Calibrate call (calibration/calibrate.h),
// its report printed and written.

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_choices.h"
#include "activecal/calibration/calibration_setup.h"
#include "activecal/calibration/defaults.h"
#include "activecal/io/robot_loader.h"
#include "activecal/report/calibration_run.h"
#include "app_common.h"

constexpr char kUsage[] =
    "Identifies the free kinematic parameters of --robot (default: the Sun "
    "& Hollerbach PUMA 560) from a measurements CSV, or from simulated "
    "position measurements when none is given (Ceres, "
    "Levenberg-Marquardt). Checks identifiability first, validates on "
    "held-out measurements, and writes the calibrated model and a JSON "
    "report.\n  activecal_identify --robot=data/puma560.yaml "
    "--measurements=measurements.csv --validation_fraction=0.2 "
    "--model_out=calibrated.yaml --json_out=report.json";

DEFINE_string(measurements, "",
              "Measurements CSV (docs/formats.md): position, pose and "
              "distance rows, mixed freely. Empty: simulate --num_poses "
              "position measurements at random lattice poses from the "
              "robot's true values.");
DEFINE_string(points, "",
              "Points file (YAML, docs/formats.md): known distances between "
              "the fixed points of type=point rows ('distances: - {from: "
              "hole_0, to: hole_1, distance_m: 0.05}'), which fix the scale "
              "that points alone cannot.");
DEFINE_string(model_out, "",
              "If set, write the calibrated robot (same YAML format as "
              "--robot, identified values as nominal) here.");
DEFINE_string(json_out, "",
              "If set, write the report here: estimates, std, correlation "
              "and covariance "
              "matrix, residual per measurement, RMS before and after, "
              "outliers, validation errors.");
DEFINE_double(validation_fraction, 0.0,
              "Fraction of the measurements held out (chosen at random with "
              "--seed) to validate the calibrated model on; in [0, 0.9].");
DEFINE_string(robust_loss, activecal::defaults::kRobustLoss,
              "none, huber or cauchy: a robust loss on each measurement's "
              "residual norm, for data with outliers.");
DEFINE_double(robust_scale_m, 0.0,
              "Scale of the robust loss (m): residual norms below it count "
              "as in least squares. Required with --robust_loss; about 3 "
              "times the device's noise is a good start.");
DEFINE_string(report_html, "",
              "Write the calibration report a person reads: one "
              "self-contained HTML file (set-up, errors before and after in "
              "mm and deg, histograms, parameters, correlations, model "
              "selection, warnings), printable to PDF by a browser.");
DEFINE_double(outlier_probability,
              activecal::IdentificationOptions().outlier_probability,
              "Flag a measurement as an outlier when its residual is this "
              "improbable under the fitted (robust) noise, Bonferroni over "
              "the measurements: clean data flag any with this probability.");
DEFINE_double(rotation_weight, activecal::defaults::kRotationWeightMPerRad,
              "Weight of 6D pose orientation rows, m per rad (set it to "
              "sigma_position / sigma_rotation of the device).");
DEFINE_bool(auto_fix, false,
            "If the measurements cannot identify some free parameters, hold "
            "them at their nominal values (named on stderr and in the "
            "report) instead of failing.");
DEFINE_bool(register_base, true,
            "Before the fit, register the robot's 6-DOF base frame to the "
            "measured points in closed form (no initial guess of the "
            "device's frame needed). Only for a 'frame' base (URDF robots).");
DEFINE_string(urdf_out, "",
              "If set, write the calibrated robot as URDF here: a URDF "
              "robot's file with only the calibrated joints' origins "
              "changed, or a YAML robot written as URDF. Reloaded and "
              "checked against every measurement (1e-9 m).");
DEFINE_string(ur_calibration_out, "",
              "If set, write the calibrated UR's kinematics for the UR ROS "
              "driver here (ur_description's default_kinematics.yaml form; "
              "load it with kinematics_params_file:=FILE). Only for a UR "
              "loaded from its URDF (base_link to tool0); checked by "
              "rebuilding the chain as ur_description does (1e-9 m, rad).");
DEFINE_string(frames_out, "",
              "If set, write the identified metrology frames (base "
              "registration, markers) here, for --frames.");
DEFINE_int32(num_poses, 30,
             "Simulation only: distinct random lattice poses to measure.");
DEFINE_int32(levels, 5,
             "Simulation only: lattice values per joint (range ends "
             "included).");
DEFINE_double(noise_m, 0.01,
              "Simulation only: noise standard deviation on each axis (m).");
DEFINE_uint64(seed, activecal::defaults::kSeed,
              "Seed of the validation split, of the cross-validation folds "
              "and of the simulation (pose draw and noise).");
DEFINE_string(model_selection, activecal::defaults::kModelSelection,
              "auto (default), cv, validation or none. none identifies "
              "every identifiable parameter of the set; cv and validation "
              "rank them and keep the number --selection_rule chooses from "
              "the RMS error on held-out measurements: --folds-fold "
              "cross-validation over the poses, or --validation (a separate "
              "file, e.g. another session; base frame and markers refitted "
              "to it). auto: none when the robot file names the free set "
              "(--parameter_set=file, the default for YAML robots) or with "
              "a prior, cv for a named set (docs/accuracy.md).");
DEFINE_string(selection_rule, activecal::defaults::kSelectionRule,
              "How --model_selection chooses the count from its curve: "
              "1se_most (default: the most parameters whose held-out error "
              "is within one standard error of the minimum, so a parameter "
              "is dropped only when the held-out poses show it predicts "
              "worse), min (the minimum), 1se (the fewest within one "
              "standard error) or ftest (the fewest whose training fit an "
              "F test at 1 % does not reject against the fit of all).");
DEFINE_string(validation, "",
              "Measurements CSV of held-out poses for "
              "--model_selection=validation (same robot, same markers).");
DEFINE_int32(folds, activecal::defaults::kFolds,
             "Folds of --model_selection=cv (all rows of one pose in one "
             "fold; assigned from --seed); at most the number of poses.");
DEFINE_string(selection_ranking, activecal::defaults::kSelectionRanking,
              "Order in which --model_selection adds link parameters: "
              "significance (|estimate - nominal| / std of the full fit, "
              "ranked inside each fold) or jacobian (QR with column "
              "pivoting on the scaled Jacobian; the poses only).");
DEFINE_int32(threads, 0,
             "Threads for the fits of --model_selection (<= 0: all "
             "hardware threads); the result is the same for any count.");
DEFINE_string(selection_plot, "",
              "If set (with --model_selection), draw the curve parameters "
              "kept -> training and held-out RMS here (PNG, gnuplot).");
DEFINE_double(prior_std_m, 0.0,
              "MAP fit: prior standard deviation (m) of every free link "
              "length parameter around its nominal value (0: no prior).");
DEFINE_double(prior_std_rad, 0.0,
              "MAP fit: prior standard deviation (rad) of every free link "
              "angle (and gain) around its nominal value (0: no prior).");
DEFINE_double(default_sigma_m, 0.0,
              "Standard deviation (m) of position and distance rows whose "
              "measurement states none (0: none). Measurements with sigma "
              "columns are weighted by 1/sigma.");
DEFINE_double(default_sigma_rad, 0.0,
              "Standard deviation (rad) of pose rotation rows whose "
              "measurement states none (0: none).");
DEFINE_bool(compliance, false,
            "Offer joint compliance under gravity (one compliance per joint, "
            "rad/(N m)), kept only when it predicts held-out poses better; "
            "needs the URDF's <inertial> masses or --payload_kg");
DEFINE_int32(harmonics, 0,
             "Offer joint-periodic errors: sin/cos k q, k = 1..N, of every "
             "revolute joint, kept only when they predict better (0: none)");
DEFINE_double(payload_kg, 0.0,
              "Payload mass at the tip (kg), for the compliance terms");
DEFINE_string(payload_com_m, "",
              "Payload centre of mass in the tip frame, 'x,y,z' (m)");
DEFINE_string(gravity, "0,0,-9.80665",
              "Gravity in the robot's base frame, 'x,y,z' (m/s^2)");
DEFINE_double(term_standard_errors, 2.0,
              "A joint error family is kept when its paired held-out gain "
              "exceeds this many standard errors");
DEFINE_string(learned_residual, "off",
              "off (default), on or auto: after the parametric fit, learn "
              "the position error it leaves as a smooth function of the "
              "joint angles (kernel ridge regression on random Fourier "
              "features, docs/accuracy.md), written into --model_out and "
              "applied by activecal_evaluate and activecal_compensate. "
              "auto keeps it only when nested cross-validation over the "
              "poses shows a held-out gain of more than "
              "--learned_standard_errors standard errors; on keeps it.");
DEFINE_int32(learned_features, 300,
             "--learned_residual: random Fourier features, in [1, 5000].");
DEFINE_double(learned_standard_errors, 2.0,
              "--learned_residual=auto keeps the correction when its paired "
              "held-out gain exceeds this many standard errors.");

namespace activecal {
namespace {

int Main() {
  const RobotDescription robot = app::LoadRobotOrDie();
  const bool simulated = FLAGS_measurements.empty();
  std::vector<int64_t> simulated_poses;
  std::vector<Measurement> all;
  std::string error, notes;
  if (simulated) {
    const bool ok = SimulateCalibrationMeasurements(
        robot,
        {FLAGS_levels, FLAGS_num_poses, FLAGS_noise_m, FLAGS_seed,
         !FLAGS_points.empty()},
        OptionSpelling::kFlags, &simulated_poses, &all, &notes, &error);
    std::printf("%s", notes.c_str());
    if (!ok) app::Fail(error);
  } else {
    all = app::WithPointsFileOrDie(
        FLAGS_points,
        app::ReadMeasurementsOrDie(FLAGS_measurements, robot.model));
  }
  CalibrationOptions options;
  const bool urdf_robot = IsUrdfPath(FLAGS_robot);
  options.parameter_set = app::ParameterSetOrDie(urdf_robot);
  options.auto_fix = FLAGS_auto_fix;
  options.register_base = FLAGS_register_base;
  options.validation_fraction = FLAGS_validation_fraction;
  options.seed = FLAGS_seed;
  // The named choices and the values checked with them, in this order.
  CalibrationChoices choices{FLAGS_model_selection,     FLAGS_selection_rule,
                             FLAGS_selection_ranking,   {},
                             FLAGS_robust_loss,         FLAGS_robust_scale_m,
                             FLAGS_outlier_probability, FLAGS_rotation_weight,
                             FLAGS_learned_residual};
  choices.terms = {FLAGS_compliance,    FLAGS_harmonics, FLAGS_payload_kg,
                   FLAGS_payload_com_m, FLAGS_gravity,   FLAGS_robot,
                   urdf_robot,          app::Chain()};
  if (!SetCalibrationChoices(robot.model, choices, OptionSpelling::kFlags,
                             &options, &error)) {
    app::Fail(error);
  }
  options.num_folds = FLAGS_folds;
  options.num_threads = FLAGS_threads;
  options.identification.default_sigma_m = FLAGS_default_sigma_m;
  options.identification.default_sigma_rad = FLAGS_default_sigma_rad;
  options.identification.prior_std_m = FLAGS_prior_std_m;
  options.identification.prior_std_rad = FLAGS_prior_std_rad;
  options.term_standard_errors = FLAGS_term_standard_errors;
  options.learned_residual.num_features = FLAGS_learned_features;
  options.learned_residual.num_standard_errors = FLAGS_learned_standard_errors;
  // The outputs' paths (each checked before the work), how the texts name
  // the options, and the robot file the reports name.
  CalibrationOutputOptions out;
  out.model_out = FLAGS_model_out;
  out.urdf_out = FLAGS_urdf_out;
  out.ur_calibration_out = FLAGS_ur_calibration_out;
  out.frames_out = FLAGS_frames_out;
  out.text = {OptionSpelling::kFlags, app::ProgramName(), robot.angle_unit,
              robot.true_parameters, !FLAGS_model_out.empty()};
  out.json_out = FLAGS_json_out;
  out.report_html = FLAGS_report_html;
  out.robot_file = FLAGS_robot;
  // Before the file is read: the flags' own messages.
  if (!CheckOptionsBeforeReading(options, !FLAGS_validation.empty(), out.text,
                                 &error)) {
    app::Fail(error);
  }
  if (!FLAGS_validation.empty()) {
    options.selection_validation =
        app::ReadMeasurementsOrDie(FLAGS_validation, robot.model, "validation");
  }
  for (const auto& [path, flag] : out.Paths()) {
    app::CheckWritableOrDie(path, flag);
  }

  CalibrationSummary summary;
  {
    // The model selection's splits (training set and folds) as they
    // finish, once it has run 2 s.
    app::ProgressLine splits(
        "model selection: splits fitted (the training set and each fold)");
    options.selection_progress = splits.callback();
    Calibrate(robot.model, all, options, &summary);
  }
  // Every output is made and checked before any is written: a run that
  // fails writes nothing (each file then atomically).
  out.source =
      simulated ? std::string("simulated measurements") : FLAGS_measurements;
  if (urdf_robot) out.urdf.source_path = FLAGS_robot;
  out.urdf.chain = app::Chain();
  out.json = {FLAGS_measurements, FLAGS_validation, robot.true_parameters,
              simulated_poses,    FLAGS_noise_m,    simulated};
  CalibrationRunOptions run_options;
  run_options.outputs = out;
  // The columns read (no file read, no column map, when simulated).
  if (!simulated) run_options.column_map = app::ColumnMapOrDie();
  run_options.rotation_weight_note =
      !app::Quiet() && app::IsDefault("rotation_weight");
  run_options.selection_plot = FLAGS_selection_plot;
  CalibrationRunOutputs run;
  MakeCalibrationRunOutputs(robot.model, all, summary, run_options, &run);
  std::printf("%s", run.printed.c_str());
  if (!run.failure.empty()) app::Fail(run.failure);
  // One set with --selection_plot's figure: all written, or none.
  app::WriteFilesOrDie(run.files, {{FLAGS_selection_plot, "--selection_plot"}});
  app::CommitOutputsOrDie();
  std::printf("%s", run.notes_after.c_str());
  app::PrintResult(app::ProgramName() + ": " + CalibrationResultLine(summary));
  return 0;
}

}  // namespace
}  // namespace activecal

ACTIVECAL_APP_MAIN(kUsage, activecal::Main)
