// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Choosing the joint error terms (joint_errors.h) by held-out error.
//
// Families of terms ("compliance": one compliance per joint under gravity;
// "periodic": sin/cos k q of every revolute joint) are candidates on top of
// the geometric model. Each candidate is fitted with the geometry
// (Identify with options.joint_errors) by cross-validation by pose (the
// folds of model_selection.h: AssignPoseFolds, every measurement of a pose
// in the same fold, the held-out errors of all folds pooled), and compared
// with the model it extends, paired by pose:
//
//   gain  = (SSE_current - SSE_candidate) / N   (m^2; held-out squared
//           residual norms, N held-out measurements)
//   SE    = sqrt(P * var_pose(d)) / N, d the per-pose difference of the
//           two models' held-out squared norms, P poses (the standard
//           error model_selection.h uses for D_k)
//
// Forward selection: starting from the geometric model, the family with
// the largest gain is added while its gain exceeds num_standard_errors
// times its SE: a term is kept only where the held-out poses show that it
// predicts better (the mirror of kMostWithinOneSe for geometric parameters,
// which drops one only where the held-out poses show it predicts worse).
// Before any fit, terms the training Jacobian cannot separate from the
// geometry (IdentifiableTerms: e.g. the compliance of a vertical axis on an
// upright robot) are dropped and listed.
//
// Deterministic for a seed whatever num_threads (each fold's fit is
// single-threaded; folds run in parallel and are pooled in fold order).

#ifndef ACTIVECAL_ESTIMATION_TERM_SELECTION_H_
#define ACTIVECAL_ESTIMATION_TERM_SELECTION_H_

#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/joint_errors.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/estimation/identification.h"

namespace activecal {

struct TermFamily {
  std::string name;  // "compliance", "periodic"
  JointErrorModel terms;
};

struct TermSelectionOptions {
  int num_folds = 5;  // >= 2, <= the number of poses
  uint64_t seed = 1;  // of the fold assignment
  // A family is kept when its held-out gain exceeds this many standard
  // errors of the paired difference (see above).
  double num_standard_errors = 2.0;
  int num_threads = 1;  // <= 0: all hardware threads
  // Of every fit (the covariance is skipped).
  IdentificationOptions identification;

  bool IsValid(std::string* error) const;
};

struct TermCandidate {
  std::string name;           // "geometric", "geometric + compliance", ...
  std::vector<int> families;  // indices into the families given
  int num_terms = 0;
  bool ok = false;              // every fold's fit converged
  double training_rms_m = 0.0;  // the fit on all training measurements
  double held_out_rms_m = 0.0;
  double held_out_se_m = 0.0;  // delta method, SE(MSE) / (2 RMS)
  // Against the candidate it extends (0 for the geometric one).
  int extends = -1;  // index into candidates
  double gain_m2 = 0.0;
  double gain_se_m2 = 0.0;
  bool chosen = false;  // the selected model
};

struct TermSelectionSummary {
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  std::vector<TermCandidate> candidates;   // in the order evaluated
  std::vector<std::string> kept;           // family names, order added
  std::vector<std::string> dropped_terms;  // not identifiable: "name: why"
  JointErrorModel terms;                   // the chosen terms (values 0)
  int chosen = 0;                          // index into candidates
  int num_poses = 0;
  int num_held_out = 0;
  double num_standard_errors = 0.0;

  std::string BriefReport() const;
};

// Runs the selection for the free set of `model`, fits started at the full
// vector `start` (features at `start`). kConvergence: summary->terms holds
// the chosen terms (empty: the geometric model). Distance measurements are
// refused (joint_error_residual.h).
void SelectTerms(const RobotModel& model, const Eigen::VectorXd& start,
                 const std::vector<Measurement>& training,
                 const std::vector<TermFamily>& families,
                 const TermSelectionOptions& options,
                 TermSelectionSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_TERM_SELECTION_H_
