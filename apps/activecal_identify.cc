// activecal_identify: identify a robot's kinematic parameters from
// measurements (a CSV file from the device, or simulated ones), validate on
// held-out measurements, and write the calibrated model and a report.

#include <gflags/gflags.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "activecal/core/lattice.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/estimate_warnings.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/model_selection.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/estimation/registration.h"
#include "activecal/estimation/registration_fit.h"
#include "activecal/estimation/residual_scale.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/frames_file.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/urdf_export.h"
#include "activecal/residuals/jacobians.h"
#include "app_common.h"
#include "gnuplot.h"

DEFINE_string(measurements, "",
              "Measurements CSV (docs/formats.md): position, pose and "
              "distance rows, mixed freely. Empty: simulate --num_poses "
              "position measurements at random lattice poses from the "
              "robot's true values.");
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
DEFINE_string(robust_loss, "none",
              "none, huber or cauchy: a robust loss on each measurement's "
              "residual norm, for data with outliers.");
DEFINE_double(robust_scale_m, 0.0,
              "Scale of the robust loss (m): residual norms below it count "
              "as in least squares. Required with --robust_loss; about 3 "
              "times the device's noise is a good start.");
DEFINE_double(outlier_threshold, 4.0,
              "Flag a measurement as an outlier when a residual row exceeds "
              "this many robust standard deviations.");
DEFINE_double(rotation_weight, 1.0,
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
DEFINE_uint64(seed, 1,
              "Seed of the validation split, of the cross-validation folds "
              "and of the simulation (pose draw and noise).");
DEFINE_string(model_selection, "auto",
              "auto (default), cv, validation or none. none identifies "
              "every identifiable parameter of the set; cv and validation "
              "rank them and keep the number --selection_rule chooses from "
              "the RMS error on held-out measurements: --folds-fold "
              "cross-validation over the poses, or --validation (a separate "
              "file, e.g. another session; base frame and markers refitted "
              "to it). auto: none when the robot file names the free set "
              "(--parameter_set=file, the default for YAML robots) or with "
              "a prior, cv for a named set (docs/accuracy.md).");
DEFINE_string(selection_rule, "1se_most",
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
DEFINE_int32(folds, 5,
             "Folds of --model_selection=cv (all rows of one pose in one "
             "fold; assigned from --seed); at most the number of poses.");
DEFINE_string(selection_ranking, "significance",
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

namespace activecal {
namespace {

std::vector<Measurement> SimulateOrDie(const RobotDescription& robot,
                                       std::vector<int64_t>* poses) {
  const RobotModel& model = robot.model;
  if (robot.true_parameters.size() != model.num_parameters()) {
    app::Fail(
        "no --measurements given and --robot has no true values to simulate "
        "from (add 'true:' entries, see docs/formats.md)");
  }
  const JointLattice lattice = app::MakeLatticeOrDie(model, FLAGS_levels);
  if (FLAGS_num_poses <= 0 || FLAGS_num_poses > lattice.size()) {
    app::Fail("--num_poses must be in [1, " + std::to_string(lattice.size()) +
              "], got " + std::to_string(FLAGS_num_poses));
  }
  Random random(Random::StreamSeed(FLAGS_seed, 0));
  *poses = random.SampleWithoutReplacement(lattice.size(), FLAGS_num_poses);
  std::vector<Measurement> plan(poses->size());
  for (size_t i = 0; i < poses->size(); ++i) {
    plan[i].joints = lattice.JointValues((*poses)[i]);
  }
  SimulationNoise noise;
  noise.position_m = FLAGS_noise_m;
  std::vector<Measurement> measurements;
  std::string error;
  if (!SimulateMeasurements(model, robot.true_parameters, plan, noise,
                            Random::StreamSeed(FLAGS_seed, 1), &measurements,
                            &error)) {
    app::Fail(error);
  }
  return measurements;
}

// A matrix as a JSON array of its rows (element by element: Eigen matrices
// are column-major, so a row is not contiguous in memory).
nlohmann::json MatrixJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < m.rows(); ++r) {
    std::vector<double> row(m.cols());
    for (int c = 0; c < m.cols(); ++c) row[c] = m(r, c);
    rows.push_back(row);
  }
  return rows;
}

struct ValidationErrors {
  int count = 0;
  double rms_nominal_m = 0, rms_calibrated_m = 0;
  double max_nominal_m = 0, max_calibrated_m = 0;
};

ValidationErrors Validate(const RobotModel& model,
                          const Eigen::VectorXd& nominal,
                          const Eigen::VectorXd& calibrated,
                          const std::vector<Measurement>& held_out) {
  ValidationErrors v;
  v.count = static_cast<int>(held_out.size());
  if (held_out.empty()) return v;
  Eigen::VectorXd before, after;
  std::string error;
  if (!MeasurementErrors(model, nominal, held_out, FLAGS_rotation_weight,
                         &before, &error) ||
      !MeasurementErrors(model, calibrated, held_out, FLAGS_rotation_weight,
                         &after, &error)) {
    app::Fail("validation: " + error);
  }
  v.rms_nominal_m = std::sqrt(before.squaredNorm() / before.size());
  v.rms_calibrated_m = std::sqrt(after.squaredNorm() / after.size());
  v.max_nominal_m = before.maxCoeff();
  v.max_calibrated_m = after.maxCoeff();
  return v;
}

// Writes every (path, text): all to temporary files beside their paths
// first, then each renamed over its path, so that a failure to write one
// leaves none of them (and no temporary file) behind.
void WriteAllOrDie(
    const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (const auto& [path, text] : outputs) {
    struct stat info;
    if (stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
      app::Fail("cannot write '" + path + "': it is a directory");
    }
  }
  std::vector<std::string> written;
  auto remove_written = [&] {
    for (const std::string& tmp : written) std::remove(tmp.c_str());
  };
  for (const auto& [path, text] : outputs) {
    const std::string tmp = path + ".tmp";
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (out) {
      written.push_back(tmp);
      out << text;
      out.flush();
    }
    if (!out) {
      remove_written();
      app::Fail("cannot write '" + path + "'");
    }
  }
  for (size_t k = 0; k < outputs.size(); ++k) {
    if (std::rename(written[k].c_str(), outputs[k].first.c_str()) != 0) {
      remove_written();
      app::Fail("cannot rename '" + written[k] + "' to '" + outputs[k].first +
                "'");
    }
  }
}

int Main() {
  const RobotDescription robot = app::LoadRobotOrDie();
  RobotModel model = robot.model;
  const bool simulated = FLAGS_measurements.empty();
  std::vector<int64_t> simulated_poses;
  std::vector<Measurement> all;
  if (simulated) {
    all = SimulateOrDie(robot, &simulated_poses);
  } else {
    all = app::ReadMeasurementsOrDie(FLAGS_measurements, model);
  }
  if (!(FLAGS_validation_fraction >= 0 && FLAGS_validation_fraction <= 0.9)) {
    app::Fail("--validation_fraction must be in [0, 0.9], got " +
              std::to_string(FLAGS_validation_fraction));
  }
  IdentificationOptions options;
  if (!ParseRobustLoss(FLAGS_robust_loss, &options.robust_loss)) {
    app::Fail("--robust_loss must be none, huber or cauchy, got '" +
              FLAGS_robust_loss + "'");
  }
  options.robust_scale_m = FLAGS_robust_scale_m;
  options.outlier_threshold = FLAGS_outlier_threshold;
  options.rotation_weight_m_per_rad = FLAGS_rotation_weight;
  options.default_sigma_m = FLAGS_default_sigma_m;
  options.default_sigma_rad = FLAGS_default_sigma_rad;
  if (!(FLAGS_prior_std_m >= 0 && std::isfinite(FLAGS_prior_std_m) &&
        FLAGS_prior_std_rad >= 0 && std::isfinite(FLAGS_prior_std_rad))) {
    app::Fail("--prior_std_m and --prior_std_rad must be finite and >= 0");
  }
  const bool map_fit = FLAGS_prior_std_m > 0 || FLAGS_prior_std_rad > 0;
  // The parameters to identify.
  const bool urdf_robot = IsUrdfPath(FLAGS_robot);
  const ParameterSet set = app::ParameterSetOrDie(urdf_robot);
  // auto: the free set the robot file names is identified as listed.
  const std::string selection_name =
      FLAGS_model_selection != "auto"         ? FLAGS_model_selection
      : set == ParameterSet::kFile || map_fit ? "none"
                                              : "cv";
  ModelSelectionOptions selection_options;
  if (!ParseModelSelectionMethod(selection_name, &selection_options.method)) {
    app::Fail("--model_selection must be auto, none, validation or cv, got '" +
              FLAGS_model_selection + "'");
  }
  if (!ParseSelectionRule(FLAGS_selection_rule, &selection_options.rule)) {
    app::Fail("--selection_rule must be 1se_most, min, 1se or ftest, got '" +
              FLAGS_selection_rule + "'");
  }
  if (selection_options.method == ModelSelectionMethod::kValidation &&
      FLAGS_validation.empty()) {
    app::Fail("--model_selection=validation needs --validation=FILE");
  }
  if (!FLAGS_validation.empty() &&
      selection_options.method != ModelSelectionMethod::kValidation) {
    app::Fail("--validation is used by --model_selection=validation only");
  }
  if (FLAGS_folds < 2) {
    app::Fail("--folds must be >= 2, got " + std::to_string(FLAGS_folds));
  }
  if (map_fit && selection_options.method != ModelSelectionMethod::kNone) {
    app::Fail(
        "--prior_std_m/--prior_std_rad (a MAP fit) and --model_selection are "
        "two answers to the same question: choose one");
  }
  for (const auto& [path, flag] :
       {std::pair<std::string, std::string>{FLAGS_model_out, "model_out"},
        {FLAGS_urdf_out, "urdf_out"},
        {FLAGS_frames_out, "frames_out"},
        {FLAGS_json_out, "json_out"}}) {
    app::CheckWritableOrDie(path, flag);
  }
  {
    std::string error;
    if (!options.IsValid(&error)) app::Fail(error);
  }

  // Split: a seeded random subset held out for validation.
  const int n = static_cast<int>(all.size());
  const int num_validation =
      static_cast<int>(std::lround(FLAGS_validation_fraction * n));
  std::vector<bool> held(n, false);
  if (num_validation > 0) {
    Random random(Random::StreamSeed(FLAGS_seed, 2));
    for (int64_t i : random.SampleWithoutReplacement(n, num_validation)) {
      held[i] = true;
    }
  }
  std::vector<Measurement> training, validation;
  std::vector<int> training_index;
  for (int i = 0; i < n; ++i) {
    if (held[i]) {
      validation.push_back(all[i]);
    } else {
      training.push_back(all[i]);
      training_index.push_back(i);
    }
  }

  // Where the device sees the robot: closed-form registration of a 6-DOF
  // base, so that no initial guess of the device's frame is needed.
  Eigen::VectorXd initial = model.nominal;
  bool registered = false;
  if (FLAGS_register_base && model.base.convention == LinkConvention::kFrame) {
    RegistrationSummary registration;
    registered = RegisterBaseFrame(model, training, &initial, &registration);
    if (!registered) {
      app::Fail(registration.message +
                " (or give the base in a --frames file and pass "
                "--register_base=false)");
    }
    std::printf("  %s\n", registration.message.c_str());
  }
  const Eigen::VectorXd registered_start = initial;

  // Identifiability before solving. A named set is reduced to what the
  // data separate, in a stated priority order, analysed at a generic point
  // near the start (parameter_reduction.h).
  std::vector<std::string> auto_fixed;
  std::string fix_label = "--auto_fix";
  std::vector<DroppedParameter> dropped;
  {
    Eigen::MatrixXd J;
    std::string error;
    const bool reduce = set != ParameterSet::kFile;
    if (!ApplyAndReduceParameterSet(set, training, FLAGS_rotation_weight,
                                    &model, &initial, &dropped, &error)) {
      app::Fail("--parameter_set=" + std::string(ParameterSetName(set)) + ": " +
                error);
    }
    if (!StackedJacobian(model, initial, training, FLAGS_rotation_weight, &J,
                         &error)) {
      app::Fail("--measurements: " + error);
    }
    const std::string what =
        "the " + std::to_string(training.size()) + " measurements";
    const int num_free_before =
        model.num_free() + static_cast<int>(dropped.size());
    IdentifiabilityReport report;
    std::vector<int> fixed_columns;
    if (reduce) {
      fix_label = std::string("--parameter_set=") + ParameterSetName(set);
      for (const DroppedParameter& d : dropped) {
        auto_fixed.push_back(d.name);
        std::printf("  %s: %s held fixed: %s\n", fix_label.c_str(),
                    d.name.c_str(), d.reason.c_str());
      }
      report = AnalyzeIdentifiability(model, J, options.rank_tolerance);
      if (!report.identifiable()) app::FailUnidentifiable(report, what, true);
      app::NoteAutoFixed(auto_fixed, num_free_before, what, fix_label);
    } else if (FLAGS_auto_fix) {
      if (!FixUnidentifiableParameters(&model, J, options.rank_tolerance,
                                       &report, &fixed_columns, &auto_fixed)) {
        app::FailUnidentifiable(report, what, true);
      }
      app::NoteAutoFixed(auto_fixed, num_free_before, what, fix_label);
    } else {
      report = AnalyzeIdentifiability(model, J, options.rank_tolerance);
      if (!report.identifiable()) app::FailUnidentifiable(report, what, false);
    }
  }

  // The honest baseline: the nominal geometry with only the base frame and
  // the markers fitted (registration_fit.h), those of them free in the
  // model to calibrate (model selection keeps every one of them): it never
  // has a parameter the calibration holds fixed.
  RegistrationFitSummary baseline;
  {
    IdentificationOptions baseline_options = options;
    baseline_options.prior_std_m = baseline_options.prior_std_rad = 0.0;
    FitRegistrationOfFreeSet(model, robot.model.nominal, training,
                             baseline_options, &baseline);
  }
  // Data that cannot fit the registration alone (e.g. too few rows for
  // the base and markers) get the calibration without a baseline, said.
  const bool have_baseline =
      baseline.termination_type == TerminationType::kConvergence;
  // Values in the wrong unit (millimetres in metre columns) leave
  // residuals beyond the robot's size (residual_scale.h). Also when the
  // fit stopped at its iteration cap: so far from the data, it does.
  if (have_baseline ||
      baseline.termination_type == TerminationType::kNoConvergence) {
    std::string error;
    if (!ResidualWithinReach(model, robot.model.nominal, training,
                             baseline.rms_m, &error)) {
      app::Fail("--measurements: " + error);
    }
  }

  // The number of parameters the data support (model_selection.h).
  std::vector<Measurement> selection_validation;
  if (!FLAGS_validation.empty()) {
    selection_validation =
        app::ReadMeasurementsOrDie(FLAGS_validation, model, "validation");
  }
  selection_options.num_folds = FLAGS_folds;
  selection_options.num_threads = FLAGS_threads;
  if (!ParseParameterRanking(FLAGS_selection_ranking,
                             &selection_options.ranking)) {
    app::Fail("--selection_ranking must be significance or jacobian, got '" +
              FLAGS_selection_ranking + "'");
  }
  selection_options.seed = Random::StreamSeed(FLAGS_seed, 3);
  selection_options.identification = options;
  ModelSelectionSummary selection;
  SelectModel(&model, initial, training, selection_validation,
              selection_options, &selection);
  if (selection.termination_type != TerminationType::kConvergence) {
    app::Fail(
        (FLAGS_validation.empty() ? "--model_selection: " : "--validation: ") +
        selection.message);
  }
  if (selection_options.method != ModelSelectionMethod::kNone) {
    std::printf("%s", selection.BriefReport().c_str());
    if (!FLAGS_selection_plot.empty()) {
      if (!app::GnuplotAvailable()) {
        std::printf("  --selection_plot: gnuplot is not installed; no plot\n");
      } else {
        std::vector<std::vector<double>> rows;
        for (const ModelSelectionPoint& pt : selection.curve) {
          if (!pt.ok) continue;
          rows.push_back({static_cast<double>(pt.num_kept),
                          pt.training_rms_m * 1e3, pt.held_out_rms_m * 1e3});
        }
        const std::string script =
            app::GnuplotData("curve", rows) + "set title 'Model selection (" +
            selection_name +
            "): RMS against parameters kept'\n"
            "set xlabel 'free parameters kept'\nset ylabel 'RMS error (mm)'\n"
            "set logscale y\nset grid\nset key top right\n"
            "set arrow from " +
            std::to_string(selection.best_num_kept) + ", graph 0 to " +
            std::to_string(selection.best_num_kept) +
            ", graph 1 nohead dt 2 lc rgb 'gray40'\n"
            "plot $curve using 1:2 with linespoints pt 7 title 'training', "
            "$curve using 1:3 with linespoints pt 5 title 'held out'\n";
        std::string error;
        if (!app::RunGnuplot(script, FLAGS_selection_plot, &error)) {
          app::Fail("--selection_plot: " + error);
        }
        std::printf("  --selection_plot: wrote %s\n",
                    FLAGS_selection_plot.c_str());
      }
    }
    for (const std::string& name : selection.dropped) {
      auto_fixed.push_back(name);
    }
    if (!selection.dropped.empty()) {
      const std::string label = "--model_selection=" + selection_name;
      fix_label = auto_fixed.size() > selection.dropped.size()
                      ? fix_label + " and " + label
                      : label;
    }
  }

  IdentificationSummary summary;
  if (map_fit) {
    // The prior rows need the noise of one row: from the fit without a
    // prior when the measurements state no sigma.
    IdentificationSummary plain;
    Identify(model, training, initial, options, &plain);
    if (plain.termination_type != TerminationType::kConvergence) {
      app::Fail("identification failed: " + plain.message);
    }
    options.prior_std_m = FLAGS_prior_std_m;
    options.prior_std_rad = FLAGS_prior_std_rad;
    options.prior_reference_sigma_m = plain.weighted ? 0.0 : plain.sigma_m;
  }
  Identify(model, training, initial, options, &summary);
  if (summary.termination_type != TerminationType::kConvergence) {
    app::Fail("identification failed: " + summary.message);
  }
  // "Nominal" errors are those of the nominal geometry, registered to the
  // device when the base was registered.
  const ValidationErrors validation_errors =
      Validate(model, registered_start, summary.parameters, validation);
  const ValidationErrors validation_baseline =
      have_baseline
          ? Validate(model, baseline.parameters, summary.parameters, validation)
          : ValidationErrors();
  const std::vector<std::string> warnings =
      EstimateWarnings(model, summary, EstimateWarningOptions());

  const bool has_truth = robot.true_parameters.size() == model.num_parameters();
  const std::vector<int> free = model.FreeParameterIndices();
  // The table is in the robot file's units (angles in deg when its
  // angle_unit is deg), as --model_out writes them; the JSON stays SI.
  // Stated sigmas the residuals contradict: the std the implied noise
  // gives, beside the stated ones (identification.h).
  const bool scaled = !summary.chi_square_plausible;
  std::printf("%-10s %-4s %12s %12s %12s", "parameter", "unit", "nominal",
              "estimate", "std");
  if (scaled) std::printf(" %12s", "std_scaled");
  if (has_truth) std::printf(" %12s %12s %8s", "true", "error", "err/std");
  std::printf("\n");
  int outside = 0;
  nlohmann::json params = nlohmann::json::array();
  for (size_t k = 0; k < free.size(); ++k) {
    const int i = free[k];
    const double sd = summary.standard_deviations[k];
    const bool degrees = std::string(model.ParameterUnit(i)) == "rad" &&
                         robot.angle_unit == AngleUnit::kDegree;
    const double u = degrees ? 180.0 / M_PI : 1.0;
    std::printf("%-10s %-4s %12.6f %12.6f %12.6f", summary.names[k].c_str(),
                degrees ? "deg" : model.ParameterUnit(i), u * model.nominal[i],
                u * summary.estimates[k], u * sd);
    nlohmann::json entry = {{"name", summary.names[k]},
                            {"nominal", model.nominal[i]},
                            {"estimate", summary.estimates[k]},
                            {"std", sd}};
    if (scaled) {
      const double sds = summary.scaled_standard_deviations[k];
      std::printf(" %12.6f", u * sds);
      entry["std_scaled"] = sds;
    }
    if (has_truth) {
      const double truth = robot.true_parameters[i];
      const double err = summary.estimates[k] - truth;
      if (std::abs(err) > 4 * sd) ++outside;
      std::printf(" %12.6f %12.6f %8.2f", u * truth, u * err, err / sd);
      entry["true"] = truth;
    }
    std::printf("\n");
    params.push_back(entry);
  }
  std::printf("\n%s", summary.BriefReport().c_str());
  if (has_truth) {
    std::printf("  %d of %zu estimates lie more than 4 std from the truth\n",
                outside, free.size());
    if (!auto_fixed.empty()) {
      std::printf(
          "  (parameters held fixed keep their nominal values, so the kept "
          "ones that explain them also take up their true errors: compare "
          "those with care)\n");
    }
  }
  if (have_baseline) {
    std::printf(
        "  registration only (nominal geometry, the %zu base and marker "
        "parameters of the calibrated set fitted): RMS residual %.6f m -> "
        "%.6f m calibrated (%.1f%% lower)\n",
        baseline.names.size(), baseline.rms_m, summary.rms_m,
        baseline.rms_m > 0 ? 100.0 * (1.0 - summary.rms_m / baseline.rms_m)
                           : 0.0);
  } else {
    std::printf("  no registration-only baseline: %s\n",
                baseline.message.c_str());
  }
  if (!validation.empty()) {
    std::printf(
        "  validation on %d held-out measurements: RMS error %.6f m with the "
        "nominal model -> %.6f m calibrated (max %.6f -> %.6f m)",
        validation_errors.count, validation_errors.rms_nominal_m,
        validation_errors.rms_calibrated_m, validation_errors.max_nominal_m,
        validation_errors.max_calibrated_m);
    if (have_baseline) {
      std::printf("; %.6f m registration only",
                  validation_baseline.rms_nominal_m);
    }
    std::printf("\n");
  }
  for (const std::string& w : warnings) {
    std::printf("  warning: %s\n", w.c_str());
  }
  std::string fixed_note;
  if (!auto_fixed.empty()) {
    fixed_note = fix_label +
                 ": held fixed at their nominal values (not in "
                 "'free'";
    fixed_note += FLAGS_model_out.empty() ? "" : " of --model_out";
    fixed_note += "):";
    for (const std::string& name : auto_fixed) fixed_note += " " + name;
    std::printf("  %s\n", fixed_note.c_str());
  }
  if (!summary.outliers.empty()) {
    std::printf("  outliers (measurement index in the input):");
    for (int o : summary.outliers) std::printf(" %d", training_index[o]);
    std::printf("\n");
  }

  // Every output is made and checked before any is written: a run that
  // fails writes nothing (each file then atomically).
  std::vector<std::pair<std::string, std::string>> outputs;
  std::string urdf_note;
  if (!FLAGS_model_out.empty()) {
    RobotFileOptions file_options;
    file_options.angle_unit = robot.angle_unit;
    file_options.comment = "Calibrated by activecal_identify from " +
                           (simulated ? std::string("simulated measurements")
                                      : FLAGS_measurements) +
                           "\n" + std::to_string(summary.num_measurements) +
                           " measurements, RMS residual " +
                           std::to_string(summary.rms_m) + " m" +
                           (fixed_note.empty() ? "" : "\n" + fixed_note);
    outputs.push_back({FLAGS_model_out,
                       RobotFileText(model, summary.parameters, file_options)});
  }
  if (!FLAGS_urdf_out.empty()) {
    std::vector<std::string> warnings;
    std::string text, error;
    UrdfChainOptions chain;
    if (urdf_robot) {
      chain.base_link = FLAGS_base_link;
      chain.tip_link = FLAGS_tip_link;
      std::string xml;
      if (!ReadTextFile(FLAGS_robot, &xml, &error) ||
          !CalibratedUrdfText(xml, FLAGS_robot, chain, model,
                              summary.parameters, &text, &warnings, &error)) {
        app::Fail("--urdf_out: " + error);
      }
    } else {
      text = UrdfFromModel(model, summary.parameters, &warnings);
      chain.base_link = "base_link";
      chain.tip_link = "tip";
    }
    for (const std::string& w : warnings) {
      std::printf("  --urdf_out: %s\n", w.c_str());
    }
    // Reload what is written: it must predict every measured point.
    double worst = 0.0;
    if (!CheckUrdfAgainstModel(text, FLAGS_urdf_out, chain, model,
                               summary.parameters, all, &worst, &error)) {
      app::Fail("--urdf_out: the written URDF does not reload: " + error);
    }
    if (!(worst <= 1e-9)) {
      app::Fail(
          "--urdf_out: the written URDF predicts the measurements up to " +
          std::to_string(worst) +
          " m away from the calibrated model (more than 1e-9 m)" +
          (warnings.empty() ? "" : ": " + warnings[0]));
    }
    outputs.push_back({FLAGS_urdf_out, text});
    char line[256];
    std::snprintf(line, sizeof(line),
                  "  --urdf_out: wrote %s; reloaded, it predicts every "
                  "measured point within %.1e m of the calibrated model\n",
                  FLAGS_urdf_out.c_str(), worst);
    urdf_note = line;
  }
  if (!FLAGS_frames_out.empty()) {
    outputs.push_back(
        {FLAGS_frames_out,
         FramesFileText(model, summary.parameters,
                        "Metrology frames identified by activecal_identify "
                        "from " +
                            (simulated ? std::string("simulated measurements")
                                       : FLAGS_measurements))});
  }
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j;
    j["parameter_set"] = ParameterSetName(set);
    nlohmann::json held = nlohmann::json::array();
    for (const DroppedParameter& d : dropped) {
      held.push_back({{"name", d.name}, {"reason", d.reason}});
    }
    j["held_fixed"] = held;
    j["registered_base"] = registered;
    j["robot"] = model.name;
    j["measurements"] = simulated ? "simulated" : FLAGS_measurements;
    j["parameters"] = params;
    j["correlation"] = MatrixJson(summary.correlation);
    j["covariance"] = MatrixJson(summary.covariance);
    nlohmann::json residuals = nlohmann::json::array();
    std::vector<int> outlier_inputs;
    for (int o : summary.outliers) outlier_inputs.push_back(training_index[o]);
    for (size_t k = 0; k < training.size(); ++k) {
      residuals.push_back(
          {{"index", training_index[k]},
           {"type", MeasurementTypeName(training[k].type)},
           {"initial_norm_m", summary.initial_residual_norms[k]},
           {"norm_m", summary.residual_norms[k]},
           {"outlier",
            std::binary_search(summary.outliers.begin(), summary.outliers.end(),
                               static_cast<int>(k))}});
    }
    j["residuals"] = residuals;
    j["outliers"] = outlier_inputs;
    j["initial_rms_residual_m"] = summary.initial_rms_m;
    j["rms_residual_m"] = summary.rms_m;
    j["sigma_m"] = summary.sigma_m;
    j["iterations"] = summary.iterations;
    j["converged"] = summary.termination_type == TerminationType::kConvergence;
    j["termination_type"] = TerminationTypeToString(summary.termination_type);
    j["num_measurements"] = summary.num_measurements;
    j["auto_fixed"] = auto_fixed;
    j["robust_loss"] = FLAGS_robust_loss;
    j["validation"] = {
        {"count", validation_errors.count},
        {"fraction", FLAGS_validation_fraction},
        {"rms_error_nominal_m", validation_errors.rms_nominal_m},
        {"rms_error_calibrated_m", validation_errors.rms_calibrated_m},
        {"max_error_nominal_m", validation_errors.max_nominal_m},
        {"max_error_calibrated_m", validation_errors.max_calibrated_m}};
    if (have_baseline) {
      j["validation"]["rms_error_registration_only_m"] =
          validation_baseline.rms_nominal_m;
      j["validation"]["max_error_registration_only_m"] =
          validation_baseline.max_nominal_m;
      j["registration_only"] = {
          {"rms_residual_m", baseline.rms_m},
          {"parameters", baseline.names},
          {"improvement_percent",
           baseline.rms_m > 0 ? 100.0 * (1.0 - summary.rms_m / baseline.rms_m)
                              : 0.0}};
    } else {
      j["registration_only"] = nullptr;
    }
    j["weighted"] = summary.weighted;
    j["degrees_of_freedom"] = summary.degrees_of_freedom;
    j["chi_square"] = summary.chi_square;
    j["chi_square_per_dof"] = summary.chi_square_per_dof;
    j["implied_sigma_m"] = summary.implied_sigma_m;
    if (summary.weighted) {
      j["chi_square_per_dof_interval"] = {summary.chi_square_per_dof_low,
                                          summary.chi_square_per_dof_high};
    }
    j["chi_square_plausible"] = summary.chi_square_plausible;
    j["prior"] = {{"std_m", FLAGS_prior_std_m},
                  {"std_rad", FLAGS_prior_std_rad},
                  {"reference_sigma_m", options.prior_reference_sigma_m}};
    j["warnings"] = warnings;
    {
      nlohmann::json ms;
      ms["method"] = selection_name;
      ms["requested"] = FLAGS_model_selection;
      ms["rule"] = FLAGS_selection_rule;
      ms["minimum_kept"] = selection.minimum_num_kept;
      ms["ranking"] = selection.ranking;
      ms["ranked_by"] = FLAGS_selection_ranking;
      ms["num_registration"] = selection.num_registration;
      ms["kept"] = selection.best_num_kept;
      ms["dropped"] = selection.dropped;
      if (selection_options.method == ModelSelectionMethod::kCrossValidation) {
        ms["folds"] = FLAGS_folds;
        ms["num_poses"] = selection.num_poses;
      }
      if (!FLAGS_validation.empty()) ms["validation"] = FLAGS_validation;
      nlohmann::json curve = nlohmann::json::array();
      for (const ModelSelectionPoint& pt : selection.curve) {
        nlohmann::json c = {{"num_kept", pt.num_kept},
                            {"added", pt.added},
                            {"ok", pt.ok},
                            {"training_rms_m", pt.training_rms_m},
                            {"f_test_p_value", pt.f_test_p_value}};
        // NaN is not JSON: a failed point has null.
        if (pt.ok) {
          c["held_out_rms_m"] = pt.held_out_rms_m;
          c["held_out_se_m"] = pt.held_out_se_m;
          c["within_one_se"] = pt.within_one_se;
        } else {
          c["held_out_rms_m"] = nullptr;
        }
        curve.push_back(c);
      }
      ms["curve"] = curve;
      j["model_selection"] = ms;
    }
    j["seed"] = FLAGS_seed;
    if (simulated) {
      j["pose_indices"] = simulated_poses;
      j["noise_m"] = FLAGS_noise_m;
    }
    outputs.push_back({FLAGS_json_out, j.dump(2) + "\n"});
  }
  WriteAllOrDie(outputs);
  std::printf("%s", urdf_note.c_str());
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
  return activecal::Main();
}
