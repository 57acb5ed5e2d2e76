// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/calibrate.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/point_constraints.h"
#include "activecal/core/random.h"
#include "activecal/estimation/estimate_warnings.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/estimation/registration.h"
#include "activecal/estimation/residual_scale.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/residuals/joint_error_jacobian.h"

namespace activecal {
namespace {

// The held-out errors of `nominal` and `calibrated`; false with *error
// when a measurement cannot be evaluated.
// The calibrated errors with the joint error terms `terms` (features at
// `feature_parameters`).
bool Validate(const RobotModel& model, const Eigen::VectorXd& nominal,
              const Eigen::VectorXd& calibrated, const JointErrorModel& terms,
              const Eigen::VectorXd& feature_parameters,
              const std::vector<Measurement>& held_out, double rotation_weight,
              ValidationErrors* v, std::string* error) {
  *v = ValidationErrors();
  v->count = static_cast<int>(held_out.size());
  if (held_out.empty()) return true;
  Eigen::VectorXd before, after;
  if (!MeasurementErrors(model, nominal, held_out, rotation_weight, &before,
                         error) ||
      !(terms.empty() ? MeasurementErrors(model, calibrated, held_out,
                                          rotation_weight, &after, error)
                      : JointErrorResidualNorms(
                            model, calibrated, terms, held_out,
                            MeasurementTermFeatures(model, feature_parameters,
                                                    terms, held_out),
                            rotation_weight, &after, error))) {
    return false;
  }
  v->rms_nominal_m = std::sqrt(before.squaredNorm() / before.size());
  v->rms_calibrated_m = std::sqrt(after.squaredNorm() / after.size());
  v->max_nominal_m = before.maxCoeff();
  v->max_calibrated_m = after.maxCoeff();
  return true;
}

}  // namespace

constexpr const char* kCalibrationStageNames[] = {"options",
                                                  "split",
                                                  "registration",
                                                  "parameter_set",
                                                  "identifiability",
                                                  "baseline",
                                                  "model_selection",
                                                  "term_selection",
                                                  "fit",
                                                  "validation",
                                                  "learned_residual",
                                                  "done"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(CalibrationStage, kCalibrationStageNames)

bool CalibrationOptions::map_fit() const {
  return identification.prior_std_m > 0 || identification.prior_std_rad > 0;
}

ModelSelectionMethod CalibrationOptions::ResolvedModelSelection() const {
  if (model_selection != ModelSelectionMethod::kAuto) return model_selection;
  // The free set the robot file names is identified as listed.
  return parameter_set == ParameterSet::kFile || map_fit()
             ? ModelSelectionMethod::kNone
             : ModelSelectionMethod::kCrossValidation;
}

bool CalibrationOptions::IsValid(std::string* error) const {
  const IdentificationOptions& id = identification;
  const ModelSelectionMethod method = ResolvedModelSelection();
  std::string e;
  if (!(validation_fraction >= 0 && validation_fraction <= 0.9)) {
    e = "validation_fraction must be in [0, 0.9], got " +
        std::to_string(validation_fraction);
  } else if (!(id.prior_std_m >= 0 && std::isfinite(id.prior_std_m) &&
               id.prior_std_rad >= 0 && std::isfinite(id.prior_std_rad))) {
    e = "prior_std_m and prior_std_rad must be finite and >= 0";
  } else if (method == ModelSelectionMethod::kValidation &&
             selection_validation.empty()) {
    e = "model_selection=validation needs validation measurements";
  } else if (!selection_validation.empty() &&
             method != ModelSelectionMethod::kValidation) {
    e = "validation measurements are used by model_selection=validation "
        "only";
  } else if (num_folds < 2) {
    e = "folds must be >= 2, got " + std::to_string(num_folds);
  } else if (map_fit() && method != ModelSelectionMethod::kNone) {
    e = "prior_std_m/prior_std_rad (a MAP fit) and model_selection are two "
        "answers to the same question: choose one";
  } else if (map_fit() && !term_families.empty()) {
    e = "joint error terms (compliance, harmonics) are chosen by held-out "
        "error, not with a MAP fit (prior_std_m/prior_std_rad): choose one";
  } else if (!(term_standard_errors >= 0) ||
             !std::isfinite(term_standard_errors)) {
    e = "term_standard_errors must be finite and >= 0";
  } else {
    IdentificationOptions plain = id;
    plain.prior_std_m = plain.prior_std_rad = 0.0;
    if (plain.IsValid(&e)) LearnedResidualIsValid(&e);
  }
  if (e.empty()) return true;
  if (error) *error = e;
  return false;
}

LearnedResidualOptions CalibrationOptions::ResolvedLearnedResidual() const {
  LearnedResidualOptions resolved = learned_residual;
  resolved.num_folds = num_folds;
  resolved.seed = seed;
  resolved.num_threads = num_threads;
  return resolved;
}

bool CalibrationOptions::LearnedResidualIsValid(std::string* error) const {
  if (learned_residual.mode == LearnedResidualMode::kOff) return true;
  std::string e;
  if (!term_families.empty()) {
    e = "learned_residual with compliance or harmonics: not supported (the "
        "correction is learned on the geometry's residuals alone; use one or "
        "the other)";
  } else if (ResolvedLearnedResidual().IsValid(&e)) {
    return true;
  } else {
    e = "learned_residual: " + e;
  }
  if (error) *error = e;
  return false;
}

std::vector<std::string> CalibrationSummary::HeldAt(HoldStage stage) const {
  std::vector<std::string> names;
  for (const HeldParameter& h : held) {
    if (h.stage == stage) names.push_back(h.name);
  }
  return names;
}

double CalibrationSummary::ImprovementPercent() const {
  return baseline.rms_m > 0
             ? 100.0 * (1.0 - identification.rms_m / baseline.rms_m)
             : 0.0;
}

std::string CalibrationSummary::BriefReport() const {
  const std::string failed = std::string("calibration failed (") +
                             CalibrationStageToString(stage) + "): " + message +
                             "\n";
  if (!Passed(CalibrationStage::kValidation)) return failed;
  return identification.BriefReport() + FitReportTail() +
         (stage == CalibrationStage::kDone ? "" : failed);
}

std::string CalibrationSummary::FitReportTail() const {
  std::string report;
  char line[512];
  if (!options.term_families.empty()) {
    const IdentificationSummary& id = identification;
    for (int t = 0; t < id.joint_errors.size(); ++t) {
      std::snprintf(line, sizeof(line), "    %s = %.6g +- %.2g %s\n",
                    id.term_names[t].c_str(), id.joint_errors.values[t],
                    id.term_standard_deviations.size() > t
                        ? id.term_standard_deviations[t]
                        : 0.0,
                    id.joint_errors.Unit(model, t));
      report += line;
    }
  }
  if (have_baseline) {
    std::snprintf(line, sizeof(line),
                  "  registration only (nominal geometry, the %zu base and "
                  "marker parameters of the calibrated set fitted): RMS "
                  "residual %.6f m -> %.6f m calibrated (%.1f%% lower)\n",
                  baseline.names.size(), baseline.rms_m, identification.rms_m,
                  ImprovementPercent());
    report += line;
  } else {
    report += "  no registration-only baseline: " + baseline.message + "\n";
  }
  if (!validation.empty()) {
    std::snprintf(line, sizeof(line),
                  "  validation on %d held-out measurements: RMS error %.6f "
                  "m with the nominal model -> %.6f m calibrated (max %.6f "
                  "-> %.6f m)",
                  validation_errors.count, validation_errors.rms_nominal_m,
                  validation_errors.rms_calibrated_m,
                  validation_errors.max_nominal_m,
                  validation_errors.max_calibrated_m);
    report += line;
    if (have_baseline) {
      std::snprintf(line, sizeof(line), "; %.6f m registration only",
                    validation_baseline.rms_nominal_m);
      report += line;
    }
    report += "\n";
  }
  for (const std::string& w : warnings) report += "  warning: " + w + "\n";
  return report;
}

void Calibrate(const RobotModel& input,
               const std::vector<Measurement>& measurements,
               const CalibrationOptions& options, CalibrationSummary* summary) {
  CHECK(summary != nullptr);
  *summary = CalibrationSummary();
  CalibrationSummary& s = *summary;
  s.options = options;
  auto fail = [&](CalibrationStage stage, TerminationType type,
                  std::string message) {
    s.stage = stage;
    s.termination_type = type;
    s.message = std::move(message);
  };
  std::string error;
  s.stage = CalibrationStage::kOptions;
  if (!options.IsValid(&error)) {
    return fail(CalibrationStage::kOptions, TerminationType::kUserFailure,
                error);
  }
  if (measurements.empty()) {
    return fail(CalibrationStage::kOptions, TerminationType::kUserFailure,
                "measurements: none");
  }
  s.model_selection = options.ResolvedModelSelection();
  // Fixed points (type=point rows): held-out rows would need the points'
  // coordinates of the training fit; not done yet, so no model selection.
  const bool with_points = HasPointRows(measurements);
  if (with_points && s.model_selection != ModelSelectionMethod::kNone) {
    if (options.model_selection != ModelSelectionMethod::kAuto) {
      return fail(CalibrationStage::kOptions, TerminationType::kUserFailure,
                  std::string("model_selection=") +
                      ModelSelectionMethodToString(s.model_selection) +
                      " is not supported with fixed-point (type=point) rows; "
                      "use model_selection=none");
    }
    s.model_selection = ModelSelectionMethod::kNone;
  }
  const double w = options.identification.rotation_weight_m_per_rad;
  IdentificationOptions fit_options = options.identification;
  fit_options.prior_std_m = fit_options.prior_std_rad = 0.0;
  fit_options.prior_reference_sigma_m = 0.0;

  // Split: a seeded random subset held out for validation.
  const int n = static_cast<int>(measurements.size());
  const int num_validation =
      static_cast<int>(std::lround(options.validation_fraction * n));
  std::vector<bool> held_out(n, false);
  if (num_validation > 0) {
    Random random(Random::StreamSeed(options.seed, 2));
    for (int64_t i : random.SampleWithoutReplacement(n, num_validation)) {
      held_out[i] = true;
    }
  }
  for (int i = 0; i < n; ++i) {
    // A known distance between fixed points stays with the training rows
    // (it relates the points' coordinates, which the training fit has).
    if (held_out[i] &&
        measurements[i].type != MeasurementType::kPointDistance) {
      s.validation.push_back(measurements[i]);
    } else {
      s.training.push_back(measurements[i]);
      s.training_index.push_back(i);
    }
  }
  const std::vector<Measurement>& training = s.training;

  // Where the device sees the robot: closed-form registration of a 6-DOF
  // base, so that no initial guess of the device's frame is needed.
  s.stage = CalibrationStage::kRegistration;
  Eigen::VectorXd start = input.nominal;
  // Fixed points only: nothing in the device frame to register to (the
  // base frame is then held, parameter_reduction.h).
  const bool any_coordinates =
      std::any_of(training.begin(), training.end(), [](const Measurement& m) {
        return m.type == MeasurementType::kPosition ||
               m.type == MeasurementType::kPose;
      });
  if (options.register_base && (any_coordinates || !with_points) &&
      input.base.convention == LinkConvention::kFrame) {
    RegistrationSummary registration;
    s.registered_base =
        RegisterBaseFrame(input, training, &start, &registration);
    s.registration_message = registration.message;
    if (!s.registered_base) {
      return fail(CalibrationStage::kRegistration,
                  TerminationType::kUserFailure, registration.message);
    }
  }
  s.registered_start = start;

  // Identifiability before solving. A named set is reduced to what the
  // data separate, in a stated priority order, analysed at a generic point
  // near the start (parameter_reduction.h).
  s.stage = CalibrationStage::kParameterSet;
  const ParameterSet set = options.parameter_set;
  const bool reduce = set != ParameterSet::kFile;
  std::vector<HeldParameter> reduced;
  if (!ReduceParameterSet(input, set, training, w, &start, &s.free, &reduced,
                          &error)) {
    return fail(CalibrationStage::kParameterSet, TerminationType::kUserFailure,
                std::string("parameter_set=") + ParameterSetToString(set) +
                    ": " + error);
  }
  s.model = WithFreeSet(input, s.free);
  s.num_free_in_set = s.free.size() + static_cast<int>(reduced.size());
  s.held = reduced;

  s.stage = CalibrationStage::kIdentifiability;
  Eigen::MatrixXd J;
  if (!StackedJacobian(s.model, start, training, w, &J, &error)) {
    return fail(CalibrationStage::kIdentifiability,
                TerminationType::kUserFailure, "measurements: " + error);
  }
  const std::string what =
      "the " + std::to_string(training.size()) + " measurements";
  IdentifiabilityReport report;
  if (!reduce && options.auto_fix) {
    std::vector<HeldParameter> fixed;
    if (!FixUnidentifiableParameters(s.model, J, fit_options.rank_tolerance,
                                     &report, &s.free, &fixed)) {
      return fail(CalibrationStage::kIdentifiability,
                  TerminationType::kUserFailure,
                  what + ": " + report.Message());
    }
    s.model = WithFreeSet(input, s.free);
    s.held.insert(s.held.end(), fixed.begin(), fixed.end());
  } else {
    report = AnalyzeIdentifiability(s.model, J, fit_options.rank_tolerance);
    if (!report.identifiable()) {
      s.auto_fix_would_help =
          !reduce && report.num_equations >= report.num_free;
      return fail(CalibrationStage::kIdentifiability,
                  TerminationType::kUserFailure,
                  what + ": " + report.Message());
    }
  }

  // The honest baseline: the nominal geometry with only the base frame and
  // the markers fitted (registration_fit.h), those of them free in the
  // model to calibrate (model selection keeps every one of them): it never
  // has a parameter the calibration holds fixed.
  s.stage = CalibrationStage::kBaseline;
  FitRegistrationOfFreeSet(s.model, input.nominal, training, fit_options,
                           &s.baseline);
  // Data that cannot fit the registration alone (e.g. too few rows for
  // the base and markers) get the calibration without a baseline, said.
  s.have_baseline =
      s.baseline.termination_type == TerminationType::kConvergence;
  // Values in the wrong unit (millimetres in metre columns) leave
  // residuals beyond the robot's size (residual_scale.h). Also when the
  // fit stopped at its iteration cap: so far from the data, it does.
  if ((s.have_baseline ||
       s.baseline.termination_type == TerminationType::kNoConvergence) &&
      !ResidualWithinReach(s.model, input.nominal, training, s.baseline.rms_m,
                           &error)) {
    return fail(CalibrationStage::kBaseline, TerminationType::kUserFailure,
                "measurements: " + error);
  }

  // The number of parameters the data support (model_selection.h).
  s.stage = CalibrationStage::kModelSelection;
  ModelSelectionOptions selection_options;
  selection_options.method = s.model_selection;
  selection_options.rule = options.selection_rule;
  selection_options.ranking = options.selection_ranking;
  selection_options.num_folds = options.num_folds;
  selection_options.num_threads = options.num_threads;
  selection_options.seed = Random::StreamSeed(options.seed, 3);
  selection_options.identification = fit_options;
  selection_options.progress = options.selection_progress;
  SelectModel(s.model, start, training, options.selection_validation,
              selection_options, &s.selection);
  if (s.selection.termination_type != TerminationType::kConvergence) {
    return fail(CalibrationStage::kModelSelection, s.selection.termination_type,
                (options.selection_validation.empty() ? "model_selection: "
                                                      : "validation: ") +
                    s.selection.message);
  }
  if (s.model_selection != ModelSelectionMethod::kNone) {
    s.free = s.selection.free;
    s.model = WithFreeSet(input, s.free);
    for (const std::string& name : s.selection.dropped) {
      std::ostringstream reason;
      reason << "model selection ("
             << ModelSelectionMethodToString(s.model_selection)
             << "): " << s.selection.best_num_kept << " of "
             << s.selection.ranking.size()
             << " free parameters kept by the held-out error";
      s.held.push_back({name, reason.str(), HoldStage::kModelSelection});
    }
  }

  // Joint error terms by held-out error (term_selection.h).
  s.stage = CalibrationStage::kTermSelection;
  IdentificationOptions final_options = fit_options;
  if (!options.term_families.empty()) {
    TermSelectionOptions term_options;
    term_options.num_folds = options.num_folds;
    term_options.seed = Random::StreamSeed(options.seed, 4);
    term_options.num_standard_errors = options.term_standard_errors;
    term_options.num_threads = options.num_threads;
    term_options.identification = fit_options;
    SelectTerms(s.model, start, training, options.term_families, term_options,
                &s.term_selection);
    if (s.term_selection.termination_type != TerminationType::kConvergence) {
      return fail(CalibrationStage::kTermSelection,
                  s.term_selection.termination_type, s.term_selection.message);
    }
    final_options.joint_errors = s.term_selection.terms;
  }

  s.stage = CalibrationStage::kFit;
  if (options.map_fit()) {
    // The prior rows need the noise of one row: from the fit without a
    // prior when the measurements state no sigma.
    IdentificationSummary plain;
    Identify(s.model, training, start, fit_options, &plain);
    if (plain.termination_type != TerminationType::kConvergence) {
      return fail(CalibrationStage::kFit, plain.termination_type,
                  "identification failed: " + plain.message);
    }
    final_options.prior_std_m = options.identification.prior_std_m;
    final_options.prior_std_rad = options.identification.prior_std_rad;
    final_options.prior_reference_sigma_m =
        plain.weighted ? 0.0 : plain.sigma_m;
    s.prior_reference_sigma_m = final_options.prior_reference_sigma_m;
  }
  Identify(s.model, training, start, final_options, &s.identification);
  s.start = start;
  if (s.identification.termination_type != TerminationType::kConvergence) {
    return fail(CalibrationStage::kFit, s.identification.termination_type,
                "identification failed: " + s.identification.message);
  }

  // "Nominal" errors are those of the nominal geometry, registered to the
  // device when the base was registered.
  s.stage = CalibrationStage::kValidation;
  const Eigen::VectorXd& calibrated = s.identification.parameters;
  const JointErrorModel& terms = s.identification.joint_errors;
  if (!Validate(s.model, s.registered_start, calibrated, terms, start,
                s.validation, w, &s.validation_errors, &error) ||
      (s.have_baseline &&
       !Validate(s.model, s.baseline.parameters, calibrated, terms, start,
                 s.validation, w, &s.validation_baseline, &error))) {
    return fail(CalibrationStage::kValidation, TerminationType::kUserFailure,
                "validation: " + error);
  }
  if (!s.have_baseline) s.validation_baseline = ValidationErrors();
  s.warnings =
      EstimateWarnings(s.model, s.identification, EstimateWarningOptions());

  // The learned residual on the calibrated geometry (learned_residual.h).
  s.stage = CalibrationStage::kLearnedResidual;
  const LearnedResidualOptions learned = options.ResolvedLearnedResidual();
  if (learned.mode != LearnedResidualMode::kOff) {
    FitLearnedResidual(s.model, calibrated, training, learned, &s.learned);
    if (s.learned.termination_type != TerminationType::kConvergence) {
      return fail(CalibrationStage::kLearnedResidual,
                  s.learned.termination_type,
                  "learned_residual: " + s.learned.message);
    }
    EvaluationSummary without, with;
    if (s.learned.kept && !s.validation.empty() &&
        EvaluateModel(s.model, calibrated, s.validation, &without) &&
        EvaluateCorrectedModel(s.model, calibrated, s.learned.correction,
                               s.validation, &with) &&
        with.position.count > 0) {
      s.learned_validation_count = with.position.count;
      s.learned_validation_rms_parametric_m = without.position.rms;
      s.learned_validation_rms_hybrid_m = with.position.rms;
    }
  }
  s.stage = CalibrationStage::kDone;
  s.termination_type = TerminationType::kConvergence;
  s.message = "calibrated";
}

}  // namespace activecal
