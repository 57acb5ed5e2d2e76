// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Calibrate: the whole identification corridor, from a robot model and its
// measurements to the calibrated parameters, what was held fixed and why,
// the registration-only baseline, validation errors and warnings. What
// activecal_identify and the Python module's identify call (one call each).
//
//   CalibrationOptions options;
//   options.parameter_set = ParameterSet::kFull;  // a URDF robot
//   options.validation_fraction = 0.2;
//   CalibrationSummary summary;
//   Calibrate(model, measurements, options, &summary);
//   if (summary.termination_type != TerminationType::kConvergence) {
//     ...summary.message (summary.stage says which step failed)...
//   }
//   std::cout << summary.BriefReport();
//   summary.identification.parameters  // the full calibrated vector
//   summary.held                       // name, reason, stage
//
// The stages, in order (CalibrationStage):
//   kOptions           options.IsValid
//   kSplit             a seeded random validation_fraction of the
//                      measurements held out (Random stream (seed, 2)); the
//                      rest is the training set every later step sees
//   kRegistration      register_base and a 'frame' base: the base frame in
//                      closed form (registration.h), the start of the fit
//   kParameterSet      the named set, reduced (unless kFile) to what the
//                      training Jacobian separates (parameter_reduction.h);
//                      the start moves to the reduction's point
//   kIdentifiability   the free set's Jacobian analysed; with auto_fix (a
//                      kFile set) the parameters it cannot identify held
//                      (identification.h: FixUnidentifiableParameters)
//   kBaseline          the registration-only fit of the nominal geometry
//                      (registration_fit.h: FitRegistrationOfFreeSet) and
//                      the unit check of its residual (residual_scale.h)
//   kModelSelection    model_selection (model_selection.h); kAuto is kNone
//                      for a kFile set or a MAP fit, kCrossValidation
//                      otherwise; folds seeded by Random stream (seed, 3)
//   kTermSelection     with term_families: the joint error terms
//                      (compliance, periodic; joint_errors.h) chosen by
//                      held-out error on the chosen geometric free set
//                      (term_selection.h), folds seeded by Random stream
//                      (seed, 4); the chosen terms are identified with the
//                      geometry
//   kFit               Identify; with a prior (identification.prior_std_m
//                      or _rad > 0) first the plain fit, whose sigma
//                      (unless the rows are weighted) scales the prior rows
//   kValidation        errors of the nominal (registered) and calibrated
//                      parameters, and of the baseline, on the held-out
//                      measurements; EstimateWarnings
//   kLearnedResidual   with learned_residual.mode on or auto: the learned
//                      residual (learned_residual.h) on the calibrated
//                      geometry, fitted on the training measurements; when
//                      kept, the held-out position RMS without and with it
// Every parameter a stage holds fixed keeps its value at the start (the
// nominal, or the registration for the base frame) and is listed in
// summary.held with its stage. The free set is a value (free_set.h): the
// input model is never changed; summary.model is the model fitted.
//
// Deterministic for a seed whatever num_threads (model_selection.h).

#ifndef ACTIVECAL_CALIBRATION_CALIBRATE_H_
#define ACTIVECAL_CALIBRATION_CALIBRATE_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/free_set.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/learned_residual.h"
#include "activecal/estimation/model_selection.h"
#include "activecal/estimation/registration_fit.h"
#include "activecal/estimation/term_selection.h"

namespace activecal {

struct CalibrationOptions {
  // The parameters to identify: a named set (reduced to what the data
  // separate) or kFile, the robot file's free flags as given.
  ParameterSet parameter_set = ParameterSet::kFile;
  // kFile only: hold the parameters the measurements cannot identify at
  // their nominal values instead of failing.
  bool auto_fix = false;
  // Register a 'frame' base in closed form before the fit (no initial guess
  // of the device's frame needed).
  bool register_base = true;
  // Fraction of the measurements held out for validation, in [0, 0.9].
  double validation_fraction = 0.0;
  // Of the validation split and of the cross-validation folds.
  uint64_t seed = 1;

  ModelSelectionMethod model_selection = ModelSelectionMethod::kAuto;
  SelectionRule selection_rule = SelectionRule::kMostWithinOneSe;
  ParameterRanking selection_ranking = ParameterRanking::kSignificance;
  int num_folds = 5;  // kCrossValidation, >= 2
  // The model selection's progress (ModelSelectionOptions::progress: the
  // splits fitted). Empty: none.
  ProgressCallback selection_progress;
  int num_threads = 0;  // of model selection; <= 0: all hardware threads
  // kValidation's held-out poses (e.g. another session); with no other
  // method.
  std::vector<Measurement> selection_validation;

  // Joint error terms offered on top of the geometry (term_selection.h),
  // each family kept only when the cross-validated held-out error shows it
  // predicts better by more than term_standard_errors standard errors
  // (paired by pose). Empty: the geometric model only. Not with a MAP fit
  // or distance measurements.
  std::vector<TermFamily> term_families;
  double term_standard_errors = 2.0;

  // Of every fit: robust loss, outliers, rotation weight, default sigmas,
  // the MAP prior (prior_std_m, prior_std_rad; prior_reference_sigma_m is
  // set by Calibrate). A prior and model selection exclude each other.
  IdentificationOptions identification;

  // After the fit: the learned residual of the calibrated geometry. Its
  // mode (kOff here: none), num_features, num_standard_errors and grid are
  // used; its num_folds, seed and num_threads are those above
  // (ResolvedLearnedResidual). Not with term_families.
  LearnedResidualOptions learned_residual = LearnedResidualOff();

  // One-line messages naming the options (the program prefixes "--").
  bool IsValid(std::string* error) const;
  // The learned residual's part of IsValid alone ("learned_residual with
  // compliance or harmonics: not supported ...", "learned_residual:
  // <LearnedResidualOptions::IsValid's message>"), for a caller that checks
  // it before any work.
  bool LearnedResidualIsValid(std::string* error) const;
  // learned_residual with num_folds, seed and num_threads set from above.
  LearnedResidualOptions ResolvedLearnedResidual() const;
  static LearnedResidualOptions LearnedResidualOff() {
    LearnedResidualOptions off;
    off.mode = LearnedResidualMode::kOff;
    return off;
  }
  // The prior of a MAP fit is set.
  bool map_fit() const;
  // model_selection with kAuto resolved for parameter_set and the prior.
  ModelSelectionMethod ResolvedModelSelection() const;
};

enum class CalibrationStage {
  kOptions,
  kSplit,
  kRegistration,
  kParameterSet,
  kIdentifiability,
  kBaseline,
  kModelSelection,
  kTermSelection,
  kFit,
  kValidation,
  kLearnedResidual,
  kDone,
};
// "options", "split", "registration", "parameter_set", "identifiability",
// "baseline", "model_selection", "term_selection", "fit", "validation",
// "learned_residual", "done".
const char* CalibrationStageToString(CalibrationStage stage);
bool StringToCalibrationStage(const std::string& text, CalibrationStage* stage);

// Errors of a parameter vector on held-out measurements (m, the norm of
// each measurement's residual rows, a pose's rotation rows weighted).
struct ValidationErrors {
  int count = 0;
  double rms_nominal_m = 0, rms_calibrated_m = 0;
  double max_nominal_m = 0, max_calibrated_m = 0;
};

struct CalibrationSummary {
  // kConvergence: calibrated. kUserFailure: bad options or data (message
  // says which); the fit's own termination type when it failed (kFailure,
  // kNoConvergence).
  TerminationType termination_type = TerminationType::kFailure;
  // Names the options as their fields ("parameter_set=full: ...",
  // "measurements: ...", "model_selection: ...", "identification failed:
  // ..."); see stage for the step.
  std::string message;
  // The stage that failed, or kDone.
  CalibrationStage stage = CalibrationStage::kOptions;
  // The failure is an identifiability failure that auto_fix would resolve
  // (a kFile set without auto_fix, enough rows).
  bool auto_fix_would_help = false;

  CalibrationOptions options;  // as given
  ModelSelectionMethod model_selection = ModelSelectionMethod::kNone;

  // The split: training and held-out measurements, and each training
  // measurement's index in the input.
  std::vector<Measurement> training, validation;
  std::vector<int> training_index;

  // The registration (when a 'frame' base was registered): its message
  // ("registered the base frame ..."); registered_start is the nominal
  // vector with the registered base (the 'nominal' of validation errors).
  bool registered_base = false;
  std::string registration_message;
  Eigen::VectorXd registered_start;
  // The start of the fit (the reduction moves guessed markers).
  Eigen::VectorXd start;

  // Every parameter held fixed, in stage order (the parameter set's
  // reduction or auto-fix, then model selection).
  std::vector<HeldParameter> held;
  // Free parameters before the reduction or the auto-fix (the set's).
  int num_free_in_set = 0;
  // The model of the fit: the input's with the free set identified.
  RobotModel model;
  FreeSet free;

  // The registration-only baseline (nominal geometry, base and markers of
  // the free set fitted); have_baseline when it converged.
  bool have_baseline = false;
  RegistrationFitSummary baseline;

  ModelSelectionSummary selection;  // also for kNone (nothing fitted)
  // With term_families: the choice of joint error terms (the chosen terms,
  // identified, are identification.joint_errors).
  TermSelectionSummary term_selection;

  IdentificationSummary identification;
  double prior_reference_sigma_m = 0;  // of the MAP fit's prior rows

  // On the held-out measurements: nominal (registered) against calibrated,
  // and the baseline against calibrated (when have_baseline).
  ValidationErrors validation_errors;
  ValidationErrors validation_baseline;
  std::vector<std::string> warnings;  // estimate_warnings.h

  // The learned residual (options.learned_residual.mode not kOff): its
  // fit and decision; when kept and measurements were held out, their
  // position RMS (m) with the calibrated geometry alone and with the
  // correction (learned_validation_count 0: not computed).
  LearnedResidualSummary learned;
  int learned_validation_count = 0;
  double learned_validation_rms_parametric_m = 0;
  double learned_validation_rms_hybrid_m = 0;

  // The calibration got past `stage` (stage < this->stage).
  bool Passed(CalibrationStage stage) const {
    return static_cast<int>(this->stage) > static_cast<int>(stage);
  }
  // The parameters held at `stage`, in order.
  std::vector<std::string> HeldAt(HoldStage stage) const;
  // 100 (1 - rms / baseline rms): the calibration's gain over
  // registration only (0 without a baseline RMS).
  double ImprovementPercent() const;
  // The fit's report, the baseline and validation lines, warnings (then
  // the learned residual's failure, if it failed).
  std::string BriefReport() const;
  // BriefReport after the fit's own report: the joint error terms, the
  // baseline and validation lines, the warnings.
  std::string FitReportTail() const;
};

void Calibrate(const RobotModel& model,
               const std::vector<Measurement>& measurements,
               const CalibrationOptions& options, CalibrationSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_CALIBRATE_H_
