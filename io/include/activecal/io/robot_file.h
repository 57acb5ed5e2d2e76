// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Robot description files (YAML): the structure, nominal values, free
// parameters, joint limits and gains of a serial arm, and optionally the
// true values a simulation should use. docs/formats.md documents the format;
// data/puma560.yaml is the paper's PUMA 560.
//
//   RobotDescription robot;
//   std::string error;
//   if (!LoadRobotFile("data/puma560.yaml", &robot, &error)) {
//     std::cerr << error << "\n";  // "data/puma560.yaml:12:5: links[1].alpha:
//   }                              //  expected a number, got 'abc'"
//
// A calibrated model is written back in the same format with
// RobotFileText().

#ifndef ACTIVECAL_IO_ROBOT_FILE_H_
#define ACTIVECAL_IO_ROBOT_FILE_H_

#include <Eigen/Core>
#include <string>

#include "activecal/core/learned_correction.h"
#include "activecal/core/robot_model.h"

namespace activecal {

enum class AngleUnit { kRadian, kDegree };

struct RobotDescription {
  RobotModel model;
  // True values for simulation (full vector), from the file's optional
  // "true:" entries, the nominal value where a block gives none. Size 0
  // when the file has no "true:" entry at all.
  Eigen::VectorXd true_parameters;
  // The unit the file used for angles, kept when writing it back.
  AngleUnit angle_unit = AngleUnit::kRadian;
  // The learned correction of the hybrid model (the optional
  // "learned_residual:" block, core/learned_correction.h); empty when the
  // file has none.
  LearnedCorrection learned_correction;
};

// Reads and validates a robot file. On failure returns false and *error
// reads "<path>:<line>:<column>: <field>: <what is wrong>".
bool LoadRobotFile(const std::string& path, RobotDescription* robot,
                   std::string* error);

// The same from text; `source` names it in messages.
bool ParseRobotDescription(const std::string& text, const std::string& source,
                           RobotDescription* robot, std::string* error);

struct RobotFileOptions {
  AngleUnit angle_unit = AngleUnit::kRadian;
  // Written as "true:" entries when it has the model's size.
  Eigen::VectorXd true_parameters;
  // Lines written as a comment at the top (without "# ").
  std::string comment;
  // Written as the "learned_residual:" block when not null and not empty
  // (every number in its shortest exact form: read back, it predicts the
  // same to the last bit).
  const LearnedCorrection* learned_correction = nullptr;
};

// The robot file text of `model` with `values` (full vector) as its
// nominal values: the form to save a calibrated model in. Numbers are
// written in their shortest form that reads back to the same double.
std::string RobotFileText(const RobotModel& model,
                          const Eigen::VectorXd& values,
                          const RobotFileOptions& options = RobotFileOptions());

}  // namespace activecal

#endif  // ACTIVECAL_IO_ROBOT_FILE_H_
