// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A learned correction of the measured point on top of the parametric model
// (the "hybrid" model): a smooth function of the joint readings, fitted to
// what the calibrated geometry leaves (estimation/learned_residual.h fits
// it; the robot file holds it, io/robot_file.h).
//
//   point(q) = MeasuredPoint(model, parameters, q, marker)
//            + R_B * (W_m^T z(x(q)) + b_m)
//
// R_B the rotation of the model's base block (the correction lives in the
// robot's base frame, so it survives a new registration of the device),
// x(q) the inputs (sin q_j and cos q_j of a revolute joint, so a whole turn
// is continuous; q_j / scale_j of a prismatic one), z the random Fourier
// features z_k(x) = sqrt(2 / D) cos(omega_k . x + phase_k), k = 1..D (they
// approximate a Gaussian kernel on x), W_m (D x 3) and b_m (3) the weights
// and bias of marker m. Everything that decides a prediction is stored
// (the frequencies already divided by the length scale): the file
// reproduces the predictions exactly, whatever random generator made them.

#ifndef ACTIVECAL_CORE_LEARNED_CORRECTION_H_
#define ACTIVECAL_CORE_LEARNED_CORRECTION_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

struct LearnedCorrection {
  // Per joint: true for sin/cos inputs (revolute), false for q / scale.
  std::vector<bool> periodic;
  Eigen::VectorXd scale;        // per joint (1 for a periodic joint)
  Eigen::MatrixXd frequencies;  // D x num_inputs()
  Eigen::VectorXd phases;       // D
  Eigen::MatrixXd weights;      // D x (3 * markers), marker m: cols 3m..3m+2
  Eigen::VectorXd bias;         // 3 * markers (m)

  // How it was made (written to the file, not needed to predict).
  double length_scale = 0.0;
  double ridge = 0.0;  // lambda per measurement
  uint64_t seed = 0;
  int num_training = 0;  // measurements fitted
  // Cross-validated held-out position RMS (m) of the parametric model
  // alone and with the correction (0 when not known).
  double held_out_rms_parametric_m = 0.0;
  double held_out_rms_hybrid_m = 0.0;

  bool empty() const { return weights.size() == 0; }
  int num_features() const { return static_cast<int>(phases.size()); }
  int num_joints() const { return static_cast<int>(periodic.size()); }
  int num_markers() const { return static_cast<int>(bias.size()) / 3; }
  // 2 per periodic joint, 1 per other.
  int num_inputs() const;

  // The inputs x(q) and the features z(x(q)) (D).
  Eigen::VectorXd Inputs(const Eigen::VectorXd& q) const;
  Eigen::VectorXd Features(const Eigen::VectorXd& q) const;
  // The correction of marker `marker` in the robot's base frame (m).
  Eigen::Vector3d Correction(const Eigen::VectorXd& q, int marker) const;

  // Consistent sizes, finite values, and (when `model` is given) the
  // model's joint count, joint types and marker count. One line in *error.
  bool Validate(const RobotModel* model, std::string* error) const;
};

// The periodic flags and scales of `model`'s joints: revolute joints
// periodic; a prismatic joint scaled by its range (1 m when unbounded).
void SetCorrectionInputs(const RobotModel& model, LearnedCorrection* c);

// The rotation of the base block at `parameters` (full vector).
Eigen::Matrix3d BaseRotation(const RobotModel& model,
                             const Eigen::VectorXd& parameters);

// The measurement the hybrid model predicts for the joints (and type) of
// `like`: PredictMeasurement with each measured point moved by its
// correction (a distance: between the two corrected points). An empty
// correction predicts as PredictMeasurement.
Measurement PredictCorrectedMeasurement(const RobotModel& model,
                                        const Eigen::VectorXd& parameters,
                                        const LearnedCorrection& correction,
                                        const Measurement& like);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_LEARNED_CORRECTION_H_
