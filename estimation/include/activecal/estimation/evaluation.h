// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// How well a model predicts measurements, with no fitting at all: the
// honest test of a calibration on poses it has not seen.
//
//   EvaluationSummary summary;
//   if (!EvaluateModel(model, parameters, measurements, &summary)) ...
//   summary.rmse_m;  // norm RMSE of the 3D point errors
//
// Position errors come from the position rows of position and 6D pose
// measurements (predicted minus measured point, m); orientation errors from
// 6D pose measurements (the angle of R_measured^T R_predicted, rad);
// distance errors from distance measurements (m). The three are reported
// separately, never mixed into one weighted number.

#ifndef ACTIVECAL_ESTIMATION_EVALUATION_H_
#define ACTIVECAL_ESTIMATION_EVALUATION_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/learned_correction.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// Statistics of a set of error magnitudes.
struct ErrorStatistics {
  int count = 0;
  double rms = 0.0;
  double mean = 0.0;
  double p95 = 0.0;  // 95th percentile (nearest rank)
  double max = 0.0;
};

struct EvaluationSummary {
  bool success = false;
  std::string message;
  int num_measurements = 0;
  // Per measurement: predicted minus measured point (m; zero for a
  // distance), orientation error angle (rad; pose only, else 0), distance
  // error (m; distance only, else 0).
  std::vector<Eigen::Vector3d> position_errors;
  std::vector<double> rotation_errors_rad;
  std::vector<double> distance_errors_m;
  // Over the measurements with a measured point.
  ErrorStatistics position;                              // of |error| (m)
  Eigen::Vector3d rmse_xyz_m = Eigen::Vector3d::Zero();  // per axis
  Eigen::Vector3d mean_xyz_m = Eigen::Vector3d::Zero();  // signed bias
  ErrorStatistics rotation;  // rad, 6D pose measurements
  ErrorStatistics distance;  // |error| (m), distance measurements
  // Fixed points (type=point rows, point_constraints.h): their coordinates
  // are refitted to these measurements (each point the mean of its rows'
  // predicted points, the least-squares fit), so a point row's position
  // error is its predicted point minus that mean, and `position` includes
  // them; a known distance's error is that of the distance between the
  // means (in `distance`). Per label (PointLabels order): the refitted
  // coordinates and the spread of its rows about them (mean distance, RMS).
  std::vector<std::string> point_labels;
  std::vector<Eigen::Vector3d> point_coordinates;
  std::vector<ErrorStatistics> point_spread;
  // Planes (type=plane rows, plane_constraints.h): refitted to these
  // measurements alone (FitPlane: the least-squares plane of the predicted
  // probe centres at their radii), the model's parameters as given. Per
  // measurement: a plane row's signed distance from its refitted plane
  // minus its probe radius (m; else 0). Per label (PlaneLabels order): the
  // refitted plane (n, d) and the flatness, the statistics of |distance|
  // of its rows (RMS, max); `plane` over all plane rows. Not in `position`
  // nor `distance`.
  std::vector<double> plane_errors_m;
  std::vector<std::string> plane_labels;
  std::vector<Eigen::Vector4d> plane_parameters;
  std::vector<ErrorStatistics> plane_flatness;
  ErrorStatistics plane;

  std::string BriefReport() const;
  // One line per fixed point (its rows, refitted coordinates, the spread
  // about its mean) and per plane (refitted normal and offset, flatness),
  // each starting "  point <label>" or "  plane <label>"; empty without.
  std::string PointSpreadText() const;
};

ErrorStatistics ComputeErrorStatistics(std::vector<double> magnitudes);

// Predicts every measurement with `parameters` (full vector) and reports the
// errors. Returns false with a message naming the first bad measurement.
bool EvaluateModel(const RobotModel& model, const Eigen::VectorXd& parameters,
                   const std::vector<Measurement>& measurements,
                   EvaluationSummary* summary);
// The same with the hybrid model: each predicted point moved by the learned
// correction (PredictCorrectedMeasurement, core/learned_correction.h); an
// empty correction gives EvaluateModel's numbers exactly.
bool EvaluateCorrectedModel(const RobotModel& model,
                            const Eigen::VectorXd& parameters,
                            const LearnedCorrection& correction,
                            const std::vector<Measurement>& measurements,
                            EvaluationSummary* summary);

// Where a posture lies relative to the poses a model was calibrated on.
// Error grows from one group to the next, so each gets its own RMSE.
enum class PostureGroup {
  kRepeated,    // every joint within the tolerance of one training pose
  kNew,         // not repeated, every joint inside the training range
  kOutOfRange,  // some joint outside the training range (extrapolation)
};
const char* PostureGroupName(PostureGroup group);  // "repeated", ...

struct PostureGroupOptions {
  double revolute_tolerance_rad = 0.01;
  double prismatic_tolerance_m = 0.001;
};

// The group of each measurement's posture relative to the postures of
// `training` (a distance: the worse group of its two poses). The training
// range of a joint is [min, max] of its training values.
std::vector<PostureGroup> ClassifyPostures(
    const RobotModel& model, const std::vector<Measurement>& training,
    const std::vector<Measurement>& measurements,
    const PostureGroupOptions& options = PostureGroupOptions());

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_EVALUATION_H_
