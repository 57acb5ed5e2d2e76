// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Closed-form registration of a robot's base frame to measured points, so
// that an identification needs no initial guess of where the measuring
// device (a laser tracker, a mocap system) stands relative to the robot.
//
// With the base at the identity, the model predicts each measured point in
// the robot's own frame; the rigid transform that best maps those points
// onto the measured ones in the least-squares sense (Umeyama 1991, no
// scale; the same as Horn's quaternion method) is the base frame. The
// markers stay at their stated values, so a guess of them (a frames file,
// the nominal values) is all that is needed.
//
//   RegistrationSummary summary;
//   if (RegisterBaseFrame(model, measurements, &initial, &summary)) ...
//   // initial's base block now holds x, y, z, rx, ry, rz of the fit.

#ifndef ACTIVECAL_ESTIMATION_REGISTRATION_H_
#define ACTIVECAL_ESTIMATION_REGISTRATION_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

struct RegistrationSummary {
  bool success = false;
  std::string message;
  int num_points = 0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  // RMS distance between the registered predictions and the measured
  // points (m): the error of the nominal geometry once placed.
  double rms_m = 0.0;
};

// The rigid transform (R, t) minimising sum |R from_i + t - to_i|^2. Needs
// three points that are not on one line; false (with a message) otherwise.
bool RigidTransformBetween(const std::vector<Eigen::Vector3d>& from,
                           const std::vector<Eigen::Vector3d>& to,
                           Eigen::Matrix3d* rotation,
                           Eigen::Vector3d* translation, std::string* error);

// Registers the base of `model` (its base must be a 6-DOF frame, convention
// kFrame) to the points of the position and pose measurements (distances
// carry no position) at the full parameter vector *parameters, whose base
// block it overwrites with the fit. Returns false with a message when the
// base is not a frame or the points cannot fix a frame.
bool RegisterBaseFrame(const RobotModel& model,
                       const std::vector<Measurement>& measurements,
                       Eigen::VectorXd* parameters,
                       RegistrationSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_REGISTRATION_H_
