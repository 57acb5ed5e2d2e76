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
#include <sstream>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_export.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/calibration/defaults.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/learned_residual.h"
#include "activecal/estimation/orientation_check.h"
#include "activecal/io/frames_file.h"
#include "activecal/io/output_files.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/urdf_inertials.h"
#include "activecal/report/html_report.h"
#include "app_common.h"
#include "gnuplot.h"

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

// "x,y,z" into *v; false when the text is not three finite numbers.
bool ParseVector3(const std::string& text, Eigen::Vector3d* v) {
  std::istringstream in(text);
  char c1 = 0, c2 = 0;
  double x, y, z;
  if (!(in >> x >> c1 >> y >> c2 >> z) || c1 != ',' || c2 != ',') return false;
  std::string rest;
  if (in >> rest) return false;
  *v = Eigen::Vector3d(x, y, z);
  return v->allFinite();
}

// The joint error families the flags offer (term_selection.h).
std::vector<TermFamily> TermFamiliesOrDie(const RobotModel& model,
                                          bool urdf_robot) {
  std::vector<TermFamily> families;
  if (!FLAGS_payload_com_m.empty() && !(FLAGS_payload_kg > 0)) {
    app::Fail(
        "--payload_com_m needs --payload_kg > 0 (a payload without "
        "mass)");
  }
  if (!(FLAGS_payload_kg >= 0) || !std::isfinite(FLAGS_payload_kg)) {
    app::Fail("--payload_kg must be finite and >= 0");
  }
  if (FLAGS_harmonics < 0 || FLAGS_harmonics > 8) {
    app::Fail("--harmonics must be in [0, 8], got " +
              std::to_string(FLAGS_harmonics));
  }
  if (FLAGS_compliance) {
    GravityModel gravity;
    if (!ParseVector3(FLAGS_gravity, &gravity.gravity)) {
      app::Fail("--gravity: expected 'x,y,z' in m/s^2, got '" + FLAGS_gravity +
                "'");
    }
    gravity.payload_kg = FLAGS_payload_kg;
    if (!FLAGS_payload_com_m.empty() &&
        !ParseVector3(FLAGS_payload_com_m, &gravity.payload_com_m)) {
      app::Fail("--payload_com_m: expected 'x,y,z' in m, got '" +
                FLAGS_payload_com_m + "'");
    }
    std::string error;
    if (urdf_robot) {
      UrdfChainOptions chain;
      chain.base_link = FLAGS_base_link;
      chain.tip_link = FLAGS_tip_link;
      if (!LoadUrdfInertials(FLAGS_robot, chain, &gravity, &error)) {
        app::Fail("--compliance: " + error);
      }
    } else if (!(FLAGS_payload_kg > 0)) {
      app::Fail("--compliance needs link masses: --robot " + FLAGS_robot +
                " is not a URDF with <inertial> elements; give a URDF or "
                "--payload_kg");
    }
    families.push_back({"compliance", ComplianceTerms(model, gravity)});
  } else if (FLAGS_payload_kg > 0) {
    app::Fail("--payload_kg is used by --compliance only");
  }
  if (FLAGS_harmonics > 0) {
    families.push_back({"periodic", HarmonicTerms(model, FLAGS_harmonics)});
  }
  return families;
}

std::vector<Measurement> SimulateOrDie(const RobotDescription& robot,
                                       std::vector<int64_t>* poses) {
  if (robot.true_parameters.size() != robot.model.num_parameters()) {
    app::Fail(
        "no --measurements given and --robot has no true values to simulate "
        "from (add 'true:' entries, see docs/formats.md)");
  }
  std::vector<Measurement> measurements;
  std::string error;
  if (!SimulateAtRandomLatticePoses(
          robot.model, robot.true_parameters,
          app::MakeLatticeOrDie(robot.model, FLAGS_levels), FLAGS_num_poses,
          FLAGS_noise_m, FLAGS_seed, poses, &measurements, &error)) {
    app::Fail("--" + error);
  }
  return measurements;
}

// The curve of model selection: parameters kept -> training and held-out
// RMS (mm), the kept count marked.
void PlotSelection(const CalibrationSummary& summary) {
  std::vector<std::vector<double>> rows;
  for (const ModelSelectionPoint& pt : summary.selection.curve) {
    if (!pt.ok) continue;
    rows.push_back({static_cast<double>(pt.num_kept), pt.training_rms_m * 1e3,
                    pt.held_out_rms_m * 1e3});
  }
  const std::string kept = std::to_string(summary.selection.best_num_kept);
  app::PlotOrNote(
      app::GnuplotData("curve", rows) + "set title 'Model selection (" +
          ModelSelectionMethodToString(summary.model_selection) +
          "): RMS against parameters kept'\n"
          "set xlabel 'free parameters kept'\nset ylabel 'RMS error (mm)'\n"
          "set logscale y\nset grid\nset key top right\n"
          "set arrow from " +
          kept + ", graph 0 to " + kept +
          ", graph 1 nohead dt 2 lc rgb 'gray40'\n"
          "plot $curve using 1:2 with linespoints pt 7 title 'training', "
          "$curve using 1:3 with linespoints pt 5 title 'held out'\n",
      FLAGS_selection_plot, "selection_plot");
}

// The orientation hint (orientation_check.h) at the fit, or at the
// registration baseline when the calibration stopped after it.
void PrintOrientationHint(const CalibrationSummary& summary,
                          const std::vector<Measurement>& all) {
  const Eigen::VectorXd& parameters = summary.stage == CalibrationStage::kDone
                                          ? summary.identification.parameters
                                          : summary.baseline.parameters;
  if (parameters.size() != summary.model.num_parameters()) return;
  const PoseFit fit = PoseFitOf(summary.model, parameters, all);
  if (!OrientationFitsBadly(fit)) return;
  const std::optional<ColumnMap>& map = app::ColumnMapOrDie();
  const std::string what =
      map && map->has_orientation
          ? ColumnMapOrientationText(*map)
          : "the file's rx_rad,ry_rad,rz_rad are a rotation vector, "
            "roll/pitch/yaw are R = Rz(yaw) Ry(pitch) Rx(roll); a device's "
            "Euler angles need --column_map";
  std::printf("%s: warning: %s\n", app::ProgramName().c_str(),
              OrientationHint(fit, what).c_str());
}

// 6D data fitted without --rotation_weight: a note saying what was
// assumed (1 m/rad), the weight the fit's own residuals suggest (pose
// pairs' distance mismatch over their angle mismatch, orientation_check.h)
// and the parameters model selection keeps with it: forgetting the flag
// can change the kept set (the README's UR10e: 13 against 21).
void PrintRotationWeightNote(const CalibrationSummary& summary,
                             const std::vector<Measurement>& all,
                             const RobotModel& model,
                             const CalibrationOptions& options) {
  if (!gflags::GetCommandLineFlagInfoOrDie("rotation_weight").is_default) {
    return;
  }
  const PoseFit fit =
      PoseFitOf(summary.model, summary.identification.parameters, all);
  if (fit.num_poses < 2 || !(fit.rotation_rms_rad > 0) ||
      !(fit.position_rms_m > 0)) {
    return;
  }
  const double weight = fit.position_rms_m / fit.rotation_rms_rad;
  char rounded[32];
  std::snprintf(rounded, sizeof(rounded), "%.2g", weight);
  CalibrationOptions with = options;
  with.identification.rotation_weight_m_per_rad = std::stod(rounded);
  CalibrationSummary other;
  Calibrate(model, all, with, &other);
  const int kept = summary.identification.estimates.size();
  std::string effect = "the fit with it failed";
  if (other.stage == CalibrationStage::kDone) {
    effect = "keeps " + std::to_string(other.identification.estimates.size()) +
             " parameters";
  }
  std::printf(
      "%s: note: --rotation_weight not given: the orientations of the pose "
      "rows were weighted %g m/rad and %d parameters kept; their residuals "
      "(between %d poses: distances %.3f mm, angles %.3f mrad RMS) have the "
      "ratio %s m/rad, with which the calibration %s; set it to "
      "sigma_position / sigma_rotation of the device\n",
      app::ProgramName().c_str(), defaults::kRotationWeightMPerRad, kept,
      fit.num_poses, fit.position_rms_m * 1e3, fit.rotation_rms_rad * 1e3,
      rounded, effect.c_str());
}

// --learned_residual and its options, checked before any fit.
LearnedResidualOptions LearnedResidualOptionsOrDie(
    const CalibrationOptions& calibration) {
  LearnedResidualOptions options;
  app::EnumFlagOrDie(StringToLearnedResidualMode, "learned_residual",
                     FLAGS_learned_residual, "off, on or auto", &options.mode);
  if (options.mode == LearnedResidualMode::kOff) return options;
  if (!calibration.term_families.empty()) {
    app::Fail(
        "--learned_residual with --compliance or --harmonics: not supported "
        "(the correction is learned on the geometry's residuals alone; use "
        "one or the other)");
  }
  options.num_features = FLAGS_learned_features;
  options.num_folds = FLAGS_folds;
  options.seed = FLAGS_seed;
  options.num_standard_errors = FLAGS_learned_standard_errors;
  options.num_threads = FLAGS_threads;
  std::string why;
  if (!options.IsValid(&why)) app::Fail("--learned_residual: " + why);
  return options;
}

// The learned residual on the calibrated geometry, fitted on the training
// measurements, its report printed; with held-out measurements
// (--validation_fraction) their RMS without and with it.
LearnedResidualSummary FitLearnedResidualOrDie(
    const CalibrationSummary& summary, const LearnedResidualOptions& options) {
  LearnedResidualSummary learned;
  FitLearnedResidual(summary.model, summary.identification.parameters,
                     summary.training, options, &learned);
  if (learned.termination_type != TerminationType::kConvergence) {
    app::Fail("--learned_residual: " + learned.message);
  }
  std::printf("%s", learned.BriefReport().c_str());
  if (learned.kept && !summary.validation.empty()) {
    EvaluationSummary without, with;
    if (EvaluateModel(summary.model, summary.identification.parameters,
                      summary.validation, &without) &&
        EvaluateCorrectedModel(summary.model, summary.identification.parameters,
                               learned.correction, summary.validation, &with) &&
        with.position.count > 0) {
      std::printf(
          "  validation (%d held-out position measurements): RMS %.4f mm "
          "parametric, %.4f mm with the correction\n",
          with.position.count, without.position.rms * 1e3,
          with.position.rms * 1e3);
    }
  }
  return learned;
}

int Main() {
  const RobotDescription robot = app::LoadRobotOrDie();
  const RobotModel& model = robot.model;
  const bool simulated = FLAGS_measurements.empty();
  std::vector<int64_t> simulated_poses;
  const std::vector<Measurement> all =
      simulated ? SimulateOrDie(robot, &simulated_poses)
                : app::WithPointsFileOrDie(
                      FLAGS_points,
                      app::ReadMeasurementsOrDie(FLAGS_measurements, model));
  if (simulated && !FLAGS_points.empty()) {
    app::Fail("--points needs --measurements with type=point rows");
  }
  CalibrationOptions options;
  const bool urdf_robot = IsUrdfPath(FLAGS_robot);
  options.parameter_set = app::ParameterSetOrDie(urdf_robot);
  options.auto_fix = FLAGS_auto_fix;
  options.register_base = FLAGS_register_base;
  options.validation_fraction = FLAGS_validation_fraction;
  options.seed = FLAGS_seed;
  app::EnumFlagOrDie(StringToModelSelectionMethod, "model_selection",
                     FLAGS_model_selection, "auto, none, validation or cv",
                     &options.model_selection);
  app::EnumFlagOrDie(StringToSelectionRule, "selection_rule",
                     FLAGS_selection_rule, "1se_most, min, 1se or ftest",
                     &options.selection_rule);
  app::EnumFlagOrDie(StringToParameterRanking, "selection_ranking",
                     FLAGS_selection_ranking, "significance or jacobian",
                     &options.selection_ranking);
  options.num_folds = FLAGS_folds;
  options.num_threads = FLAGS_threads;
  options.term_families = TermFamiliesOrDie(model, urdf_robot);
  options.term_standard_errors = FLAGS_term_standard_errors;
  IdentificationOptions& fit = options.identification;
  app::EnumFlagOrDie(StringToRobustLoss, "robust_loss", FLAGS_robust_loss,
                     "none, huber or cauchy", &fit.robust_loss);
  fit.robust_scale_m = FLAGS_robust_scale_m;
  fit.outlier_probability = FLAGS_outlier_probability;
  if (!(FLAGS_rotation_weight > 0) || !std::isfinite(FLAGS_rotation_weight)) {
    app::Fail("--rotation_weight must be finite and > 0 (m per rad), got " +
              std::to_string(FLAGS_rotation_weight));
  }
  fit.rotation_weight_m_per_rad = FLAGS_rotation_weight;
  fit.default_sigma_m = FLAGS_default_sigma_m;
  fit.default_sigma_rad = FLAGS_default_sigma_rad;
  fit.prior_std_m = FLAGS_prior_std_m;
  fit.prior_std_rad = FLAGS_prior_std_rad;
  const LearnedResidualOptions learned_options =
      LearnedResidualOptionsOrDie(options);
  // Before the file is read: the flags' own messages.
  const bool by_validation =
      options.ResolvedModelSelection() == ModelSelectionMethod::kValidation;
  if (by_validation && FLAGS_validation.empty()) {
    app::Fail("--model_selection=validation needs --validation=FILE");
  }
  if (!by_validation && !FLAGS_validation.empty()) {
    app::Fail("--validation is used by --model_selection=validation only");
  }
  if (!FLAGS_validation.empty()) {
    options.selection_validation =
        app::ReadMeasurementsOrDie(FLAGS_validation, model, "validation");
  }
  for (const auto& [path, flag] :
       {std::pair<std::string, std::string>{FLAGS_model_out, "model_out"},
        {FLAGS_urdf_out, "urdf_out"},
        {FLAGS_frames_out, "frames_out"},
        {FLAGS_ur_calibration_out, "ur_calibration_out"},
        {FLAGS_json_out, "json_out"},
        {FLAGS_report_html, "report_html"}}) {
    app::CheckWritableOrDie(path, flag);
  }

  CalibrationSummary summary;
  {
    // The model selection's splits (training set and folds) as they
    // finish, once it has run 2 s.
    app::ProgressLine splits(
        "model selection: splits fitted (the training set and each fold)");
    options.selection_progress = splits.callback();
    Calibrate(model, all, options, &summary);
    // Later fits (the --rotation_weight note's) outlive the line.
    options.selection_progress = nullptr;
  }
  CalibrationTextOptions text;
  text.program = app::ProgramName();
  text.angle_unit = robot.angle_unit;
  text.true_parameters = robot.true_parameters;
  text.model_out = !FLAGS_model_out.empty();
  std::printf("%s", CalibrationStagesText(summary, text).c_str());
  if (!FLAGS_selection_plot.empty() &&
      summary.Passed(CalibrationStage::kModelSelection) &&
      summary.model_selection != ModelSelectionMethod::kNone) {
    PlotSelection(summary);
  }
  PrintOrientationHint(summary, all);
  if (summary.stage != CalibrationStage::kDone) {
    app::Fail(CalibrationFailureText(summary, text));
  }
  std::printf("%s", CalibrationResultText(summary, text).c_str());
  if (!app::Quiet()) PrintRotationWeightNote(summary, all, model, options);
  LearnedResidualSummary learned;
  if (learned_options.mode != LearnedResidualMode::kOff) {
    learned = FitLearnedResidualOrDie(summary, learned_options);
  }

  // Every output is made and checked before any is written: a run that
  // fails writes nothing (each file then atomically).
  const Eigen::VectorXd& calibrated = summary.identification.parameters;
  const std::string source =
      simulated ? std::string("simulated measurements") : FLAGS_measurements;
  std::vector<OutputFile> outputs;
  std::string error;
  if (!FLAGS_model_out.empty()) {
    RobotFileOptions file_options;
    file_options.angle_unit = robot.angle_unit;
    const std::string note = HeldFixedNote(summary, text);
    file_options.comment =
        "Calibrated by activecal_identify from " + source + "\n" +
        std::to_string(summary.identification.num_measurements) +
        " measurements, RMS residual " +
        std::to_string(summary.identification.rms_m) + " m" +
        (note.empty() ? "" : "\n" + note);
    if (learned.kept) {
      file_options.learned_correction = &learned.correction;
      file_options.comment +=
          "\nWith its learned residual (" +
          std::string(LearnedResidualModeToString(learned_options.mode)) +
          "): applied by activecal_evaluate and "
          "activecal_compensate";
    }
    outputs.push_back({FLAGS_model_out,
                       RobotFileText(summary.model, calibrated, file_options)});
  }
  std::string urdf_note;
  if (!FLAGS_urdf_out.empty()) {
    CalibratedUrdfOptions urdf_options;
    if (urdf_robot) urdf_options.source_path = FLAGS_robot;
    urdf_options.chain.base_link = FLAGS_base_link;
    urdf_options.chain.tip_link = FLAGS_tip_link;
    urdf_options.output_path = FLAGS_urdf_out;
    CalibratedUrdf urdf;
    const bool ok = MakeCalibratedUrdf(summary.model, calibrated, all,
                                       urdf_options, &urdf, &error);
    if (!urdf.text.empty()) {
      for (const std::string& w : urdf.warnings) {
        std::printf("  --urdf_out: %s\n", w.c_str());
      }
    }
    if (!ok) app::Fail("--urdf_out: " + error);
    outputs.push_back({FLAGS_urdf_out, urdf.text});
    char line[256];
    std::snprintf(line, sizeof(line),
                  "  --urdf_out: wrote %s; reloaded, it predicts every "
                  "measured point within %.1e m of the calibrated model\n",
                  FLAGS_urdf_out.c_str(), urdf.worst_m);
    urdf_note = line;
    if (learned.kept) {
      std::snprintf(line, sizeof(line),
                    "  --urdf_out: the URDF holds the geometry only, not the "
                    "learned correction (--model_out has it): alone it "
                    "predicts held-out poses with RMS %.4f mm (nested CV), "
                    "%.4f mm with the correction\n",
                    learned.held_out_rms_parametric_m * 1e3,
                    learned.held_out_rms_hybrid_m * 1e3);
      urdf_note += line;
    }
  }
  if (!FLAGS_ur_calibration_out.empty()) {
    UrCalibration ur;
    if (!MakeUrCalibration(summary.model, calibrated, all,
                           "Calibrated by activecal_identify from " + source,
                           &ur, &error)) {
      app::Fail("--ur_calibration_out: " + error);
    }
    outputs.push_back({FLAGS_ur_calibration_out, ur.text});
    char line[256];
    std::snprintf(line, sizeof(line),
                  "  --ur_calibration_out: wrote %s; rebuilt as "
                  "ur_description does, tool0 is within %.1e m and %.1e rad "
                  "of the calibrated model\n",
                  FLAGS_ur_calibration_out.c_str(), ur.worst_m, ur.worst_rad);
    urdf_note += line;
  }
  if (!FLAGS_frames_out.empty()) {
    outputs.push_back(
        {FLAGS_frames_out,
         FramesFileText(summary.model, calibrated,
                        "Metrology frames identified by activecal_identify "
                        "from " +
                            source)});
  }
  if (!FLAGS_json_out.empty()) {
    CalibrationJsonOptions json;
    json.simulated = simulated;
    json.measurements = FLAGS_measurements;
    json.validation = FLAGS_validation;
    json.true_parameters = robot.true_parameters;
    json.simulated_poses = simulated_poses;
    json.noise_m = FLAGS_noise_m;
    outputs.push_back({FLAGS_json_out, CalibrationJson(summary, json)});
  }
  if (!FLAGS_report_html.empty()) {
    CalibrationHtmlOptions html;
    html.robot_file = FLAGS_robot.empty() ? "built-in PUMA 560" : FLAGS_robot;
    html.measurements_file = source;
    HtmlReport report;
    if (!CalibrationHtmlReport(summary, html, &report, &error)) {
      app::Fail("--report_html: " + error);
    }
    outputs.push_back({FLAGS_report_html, RenderHtml(report)});
  }
  // One set with --selection_plot's figure: all written, or none.
  for (const OutputFile& file : outputs)
    app::WriteTextOrDie(file.path, file.text);
  app::CommitOutputsOrDie();
  std::printf("%s", urdf_note.c_str());
  app::PrintResult(app::ProgramName() + ": " + CalibrationResultLine(summary));
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Identifies the free kinematic parameters of --robot (default: the Sun "
      "& Hollerbach PUMA 560) from a measurements CSV, or from simulated "
      "position measurements when none is given (Ceres, "
      "Levenberg-Marquardt). Checks identifiability first, validates on "
      "held-out measurements, and writes the calibrated model and a JSON "
      "report.\n  activecal_identify --robot=data/puma560.yaml "
      "--measurements=measurements.csv --validation_fraction=0.2 "
      "--model_out=calibrated.yaml --json_out=report.json");
  return activecal::app::Finish(activecal::Main());
}
