// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Choosing how many parameters the data support, from held-out error.
//
// A full kinematic model with every identifiable parameter fits its
// training poses best but can predict new poses worse than one without its
// weakest combinations. SelectModel ranks the free parameters and keeps
// the number of them that minimises the RMS error on held-out
// measurements:
//
//   ranking  the registration parameters (base frame, markers) always come
//            first and are always kept; the link parameters follow, by
//            kSignificance (default): |estimate - start| / std of the fit
//            with every free parameter, largest first; or by kJacobian: QR
//            with column pivoting on the unit-norm Jacobian columns with
//            the registration columns projected out (at each step the
//            parameter adding the largest new direction), which depends on
//            the poses only. Ties go to the earlier parameter. With
//            cross-validation each fold ranks from its own training part,
//            so the held-out error measures the whole procedure, ranking
//            included, and never sees the held-out values (a fold whose
//            fit of every parameter fails keeps the kJacobian order).
//   curve    for k = registration count .. all free: the fit with the
//            first k ranked parameters (the rest held at `start`) on the
//            training measurements (training RMS), and its error on the
//            held-out ones (held-out RMS). RMS of the residual norms (m,
//            a pose's rotation rows weighted as in the identification).
//   held out kValidation: a separate measurements file (e.g. another
//            session). With register_held_out (default), the base frame and
//            markers are refitted to it before the error is taken (the
//            device may have moved between sessions); the geometry is what
//            is tested. kCrossValidation: k folds over the poses of the
//            training measurements (every row of one pose in the same fold;
//            poses assigned by a seeded shuffle, round robin), the held-out
//            errors of all folds pooled. Deterministic for a seed.
//   choice   by `rule` (SelectionRule):
//            kMinimum     the k with the smallest held-out RMS (the smaller
//                         k on a tie);
//            kFewestWithinOneSe  the smallest k whose held-out error is
//                         within one standard error of the minimum's;
//            kMostWithinOneSe    the largest such k: a parameter is dropped
//                         only when the held-out poses show that keeping
//                         it predicts worse, by more than one standard
//                         error;
//            kFTest       the smallest k whose training fit is not worse
//                         than the fit of every parameter by an F test at
//                         the 1 % level (the dropped parameters jointly not
//                         significant; training data only, held-out errors
//                         still shown).
//            "Within one standard error": D_k = MSE_k - MSE_min, the paired
//            difference of the held-out mean squared residual norms
//            (per held-out pose: the same poses for every k), is at most
//            its standard error, sqrt(P * var_pose(d)) / N for P held-out
//            poses and N held-out measurements.
//
//   ModelSelectionOptions options;
//   options.method = ModelSelectionMethod::kCrossValidation;
//   ModelSelectionSummary summary;
//   SelectModel(model, start, training, {}, options, &summary);
//   // summary.free: the chosen set (free_set.h); summary.curve the curve.

#ifndef ACTIVECAL_ESTIMATION_MODEL_SELECTION_H_
#define ACTIVECAL_ESTIMATION_MODEL_SELECTION_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/free_set.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/estimation/identification.h"

namespace activecal {

// kAuto is a request resolved by the caller (calibration/calibrate.h:
// kNone for the robot file's free set or a MAP fit, kCrossValidation
// otherwise); SelectModel refuses it.
enum class ModelSelectionMethod { kNone, kValidation, kCrossValidation, kAuto };
enum class ParameterRanking { kSignificance, kJacobian };
enum class SelectionRule {
  kMinimum,
  kFewestWithinOneSe,
  kMostWithinOneSe,
  kFTest
};
// "min", "1se", "1se_most", "ftest".
const char* SelectionRuleToString(SelectionRule rule);
bool StringToSelectionRule(const std::string& text, SelectionRule* rule);
// "significance" or "jacobian".
const char* ParameterRankingToString(ParameterRanking ranking);
bool StringToParameterRanking(const std::string& text,
                              ParameterRanking* ranking);
// "none", "validation", "cv" or "auto".
const char* ModelSelectionMethodToString(ModelSelectionMethod method);
bool StringToModelSelectionMethod(const std::string& text,
                                  ModelSelectionMethod* method);

struct ModelSelectionOptions {
  ModelSelectionMethod method = ModelSelectionMethod::kCrossValidation;
  int num_folds = 5;  // kCrossValidation: >= 2, <= the number of poses
  uint64_t seed = 1;  // of the fold assignment
  bool register_held_out = true;  // kValidation, see above
  ParameterRanking ranking = ParameterRanking::kSignificance;
  // kMostWithinOneSe: the comparison in docs/accuracy.md.
  SelectionRule rule = SelectionRule::kMostWithinOneSe;
  // The splits (whole training set, folds) run in parallel, each walking
  // up the curve with every fit started from the previous one; each fit is
  // single-threaded, so the result is the same for every thread count. <= 0:
  // all hardware threads.
  int num_threads = 1;
  // Of every fit. The curve's fits skip the covariance and stop at
  // relative tolerances of at most 1e-9 (the RMS needs no more).
  IdentificationOptions identification;
  // Called as each split (the whole training set, then each fold, in the
  // order they finish) has fitted the whole curve: done of total splits,
  // done counting up 1, 2, ... (calls are serialized). Empty: none.
  ProgressCallback progress;

  bool IsValid(std::string* error) const;
};

struct ModelSelectionPoint {
  int num_kept = 0;   // free parameters of the fit, registration included
  std::string added;  // the parameter this point adds ("" for the first)
  bool ok = false;    // every fit of this point converged
  double training_rms_m = 0.0;
  double held_out_rms_m = 0.0;
  // Standard error of held_out_rms_m over the held-out poses (delta
  // method: SE(MSE) / (2 RMS)).
  double held_out_se_m = 0.0;
  // Held-out MSE minus the minimum point's (m^2, paired by pose) and its
  // standard error; within_one_se: the excess is at most its SE.
  double excess_m2 = 0.0;
  double excess_se_m2 = 0.0;
  bool within_one_se = false;
  // Sum of the squared (weighted) residual rows of the training fit and
  // the p-value of the F test of this point against the last one.
  double training_cost = 0.0;
  double f_test_p_value = 0.0;
};

struct ModelSelectionSummary {
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  int num_registration = 0;  // always kept, first in the ranking
  // Every free parameter, kept first (from the whole training set).
  std::vector<std::string> ranking;
  std::vector<ModelSelectionPoint> curve;
  SelectionRule rule = SelectionRule::kMinimum;
  int best_num_kept = 0;             // chosen by `rule`
  int minimum_num_kept = 0;          // the smallest held-out RMS
  std::vector<std::string> dropped;  // held at `start`, ranking order
  FreeSet free;                      // the chosen set (kConvergence)
  int num_poses = 0;                 // distinct training poses
  int num_held_out = 0;              // held-out measurements (all folds)

  std::string BriefReport() const;
};

// Free parameters of `model` (positions among them, 0-based) in the
// kJacobian order above; *num_registration of them are base and markers.
// `jacobian`: m x num_free, columns in free-parameter order.
std::vector<int> RankFreeParameters(const RobotModel& model,
                                    const Eigen::MatrixXd& jacobian,
                                    int* num_registration);

// The kSignificance order: registration parameters first (free order), then
// the link parameters by |estimates - start| / standard deviations
// (free-parameter vectors of a fit of every free parameter), largest first.
std::vector<int> RankBySignificance(const RobotModel& model,
                                    const Eigen::VectorXd& moved,
                                    const Eigen::VectorXd& standard_deviations,
                                    int* num_registration);

// Cross-validation folds by pose: (*fold)[i] in [0, num_folds) for each
// measurement, equal for equal joint values (a distance by both poses).
// False with *error when there are fewer distinct poses than folds.
bool AssignPoseFolds(const std::vector<Measurement>& measurements,
                     int num_folds, uint64_t seed, std::vector<int>* fold,
                     int* num_poses, std::string* error);

// Runs the selection on the free parameters of `model`, fits started at
// the full vector `start`; `validation` is used with kValidation only. On
// kConvergence, summary->free holds the chosen set. With kNone, nothing is
// fitted and every free parameter is kept.
void SelectModel(const RobotModel& model, const Eigen::VectorXd& start,
                 const std::vector<Measurement>& training,
                 const std::vector<Measurement>& validation,
                 const ModelSelectionOptions& options,
                 ModelSelectionSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_MODEL_SELECTION_H_
