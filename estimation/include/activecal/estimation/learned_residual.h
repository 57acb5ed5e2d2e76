// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The learned residual (the "hybrid" model): after the parametric fit, a
// regression from the joint readings to the position error the calibrated
// model leaves, and the decision whether to keep it, by held-out error.
//
// The regression: kernel ridge regression with random Fourier features
// (core/learned_correction.h): D features z(x) = sqrt(2/D) cos(Omega x / l
// + phase) approximating the Gaussian kernel exp(-|x - x'|^2 / (2 l^2)) on
// the inputs x(q) (sin q and cos q of revolute joints), Omega standard
// normal and phase uniform in [0, 2 pi), drawn from Random(StreamSeed(seed,
// 0)) (core/random.h: the same numbers on every platform). Per marker, the
// targets are y = R_B^T (measured point - predicted point) of the position
// and 6D pose measurements (distances are not used); weights W and an
// unpenalised bias b solve
//     (Z^T Z + lambda n diag(1, .., 1, 0)) [W; b] = Z^T Y
// (one Cholesky solve of size D + 1; n the rows fitted, so lambda is per
// measurement).
//
// Hyperparameters (length scale l, ridge lambda) on the training data only:
// K-fold cross-validation by pose (AssignPoseFolds, seeded by
// Random::StreamSeed(seed, 1)) over the grid, the pair with the smallest
// pooled held-out squared error (ties: the first in grid order). Each
// fold's normal equations come from per-fold Gram matrices, so the whole
// grid costs one pass over the data per length scale.
//
// The rule (kAuto): the held-out error of the hybrid model is measured by
// nested cross-validation (each outer fold's hyperparameters chosen by CV
// over the other folds only, so the comparison never sees the held-out
// poses), against the parametric model alone (correction 0), paired by
// pose:
//     gain = (SSE_parametric - SSE_hybrid) / N    (m^2, N measurements)
//     SE   = sqrt(P var_pose(d)) / N               (d the per-pose
//                                                   difference, P poses)
// The correction is kept when gain > num_standard_errors * SE (default 2):
// only when the held-out poses show it predicts better by more than the
// noise of the comparison (the rule of term_selection.h).
//
// What is not refitted: the parametric parameters are those of the fit on
// all training measurements, so the residuals of the held-out folds are
// in-sample residuals of the geometry (slightly smaller than on new poses:
// the geometry's p parameters absorb about p/(rows) of the noise). Both
// sides of the comparison use the same residuals.
//
// Deterministic for a seed whatever num_threads: the length scales run in
// parallel, each into its own slots, reduced in grid order.

#ifndef ACTIVECAL_ESTIMATION_LEARNED_RESIDUAL_H_
#define ACTIVECAL_ESTIMATION_LEARNED_RESIDUAL_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/learned_correction.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"

namespace activecal {

enum class LearnedResidualMode {
  kOff,   // no correction
  kOn,    // fitted and kept
  kAuto,  // fitted, kept only by the rule above
};
// "off", "on", "auto".
const char* LearnedResidualModeToString(LearnedResidualMode mode);
bool StringToLearnedResidualMode(const std::string& text,
                                 LearnedResidualMode* mode);

struct LearnedResidualOptions {
  LearnedResidualMode mode = LearnedResidualMode::kAuto;
  int num_features = 300;  // D, in [1, 5000]
  // The grid: length scales of the Gaussian kernel on the sin/cos inputs
  // (about radians for small joint differences) and ridges per measurement.
  std::vector<double> length_scales = {0.5, 1.0, 2.0, 4.0, 8.0};
  std::vector<double> ridges = {1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1};
  int num_folds = 5;  // >= 3 (nested CV), <= the number of poses
  uint64_t seed = 1;
  double num_standard_errors = 2.0;
  int num_threads = 1;  // <= 0: all hardware threads

  bool IsValid(std::string* error) const;
};

// The pooled held-out RMS (m) of one grid point (all training folds).
struct LearnedResidualGridPoint {
  double length_scale = 0.0;
  double ridge = 0.0;
  double held_out_rms_m = 0.0;
};

struct LearnedResidualSummary {
  // kConvergence: fitted (kept or not). kUserFailure: bad options or data
  // (message says what).
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  LearnedResidualMode mode = LearnedResidualMode::kAuto;
  // The correction is part of the model (kOn, or kAuto by the rule).
  bool kept = false;
  // The fitted correction (also when not kept: what was tested).
  LearnedCorrection correction;
  int num_measurements = 0;  // rows fitted (position and pose)
  int num_skipped = 0;       // distance and fixed-point rows, not used
  int num_poses = 0;
  int num_folds = 0;
  // The chosen hyperparameters (CV on all training folds) and the grid.
  double length_scale = 0.0;
  double ridge = 0.0;
  std::vector<LearnedResidualGridPoint> grid;
  // Nested cross-validation: held-out position RMS (m) of the parametric
  // model and of the hybrid; the paired gain (m^2) and its SE.
  double held_out_rms_parametric_m = 0.0;
  double held_out_rms_hybrid_m = 0.0;
  double gain_m2 = 0.0;
  double gain_se_m2 = 0.0;
  double num_standard_errors = 0.0;
  // On the training measurements, parametric and with the correction.
  double training_rms_parametric_m = 0.0;
  double training_rms_hybrid_m = 0.0;
  double seconds = 0.0;  // wall time of the whole fit

  // A few lines: the decision and its numbers.
  std::string BriefReport() const;
};

// Fits the learned residual of `model` at `parameters` (full vector, the
// calibrated parametric model) on `measurements` (the training set) and
// decides whether to keep it (options.mode; kOff fits nothing and returns
// kConvergence with kept false).
void FitLearnedResidual(const RobotModel& model,
                        const Eigen::VectorXd& parameters,
                        const std::vector<Measurement>& measurements,
                        const LearnedResidualOptions& options,
                        LearnedResidualSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_LEARNED_RESIDUAL_H_
