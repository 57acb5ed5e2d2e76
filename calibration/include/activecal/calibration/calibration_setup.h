// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Parts of CalibrationOptions made from plain values (what the program's
// flags and the Python module's keywords give): the joint error families
// offered on top of the geometry (term_selection.h).
//
//   TermFamilyOptions terms;
//   terms.compliance = true;
//   terms.robot_path = "ur10e.urdf";  // its <inertial> masses
//   terms.urdf_robot = true;
//   if (!MakeTermFamilies(model, terms, OptionSpelling::kFlags,
//                         &options.term_families, &error)) ...

#ifndef ACTIVECAL_CALIBRATION_CALIBRATION_SETUP_H_
#define ACTIVECAL_CALIBRATION_CALIBRATION_SETUP_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/estimation/term_selection.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

struct TermFamilyOptions {
  // Joint compliance under gravity (one per joint, rad/(N m)): needs link
  // masses, the URDF's <inertial> elements or a payload.
  bool compliance = false;
  // sin/cos k q, k = 1..harmonics, of every revolute joint; in [0, 8].
  int harmonics = 0;
  // Payload at the tip (compliance only): mass (kg, finite, >= 0) and
  // centre of mass in the tip frame, "x,y,z" (m; empty: the tip's origin).
  double payload_kg = 0.0;
  std::string payload_com_m;
  // Gravity in the robot's base frame, "x,y,z" (m/s^2).
  std::string gravity = "0,0,-9.80665";
  // The robot file (named in messages); a URDF robot's inertials are read
  // from it on `chain`.
  std::string robot_path;
  bool urdf_robot = false;
  UrdfChainOptions chain;
};

// "x,y,z" into *v; false when the text is not three finite numbers.
bool ParseVector3(const std::string& text, Eigen::Vector3d* v);

// The families `options` offer, in order: "compliance", "periodic". False
// with one line in *error naming the options in `spelling`
// ("--payload_kg must be finite and >= 0", "--harmonics must be in [0, 8],
// got 9", "--gravity: expected 'x,y,z' in m/s^2, got '0,0'", "--compliance:
// <the URDF's error>", "--compliance needs link masses: ...",
// "--payload_kg is used by --compliance only").
bool MakeTermFamilies(const RobotModel& model, const TermFamilyOptions& options,
                      OptionSpelling spelling,
                      std::vector<TermFamily>* families, std::string* error);

// The checks of `options` a program makes before it reads a file, in
// order: the learned residual (CalibrationOptions::LearnedResidualIsValid,
// as OptionsErrorText), then a validation file given (`validation_file`,
// not read yet) exactly when the model selection resolves to kValidation
// ("--model_selection=validation needs --validation=FILE", "--validation
// is used by --model_selection=validation only"). One line naming the
// options in text.option_spelling.
bool CheckOptionsBeforeReading(const CalibrationOptions& options,
                               bool validation_file,
                               const CalibrationTextOptions& text,
                               std::string* error);

// A run without measurements (activecal_identify without --measurements):
// num_poses position measurements at distinct random poses of the lattice
// with `levels` values per joint, simulated from the robot's true values
// with noise_m per axis (SimulateAtRandomLatticePoses, seeded by seed).
struct CalibrationSimulationOptions {
  int levels = 5;
  int num_poses = 30;
  double noise_m = 0.01;
  uint64_t seed = 1;
  // A points file was given (--points): refused, the simulation having no
  // type=point rows for its distances.
  bool points = false;
};

// The simulated measurements into *measurements and their lattice poses
// into *poses. *notes: the lattice's one-turn joints ("note: ...\n" lines;
// to print also when false). False with *error naming the options in
// `spelling`: "no --measurements given and --robot has no true values to
// simulate from (...)", "--levels=1: <the lattice's error>", "--num_poses
// must be in [1, N], got k", "--points needs --measurements with
// type=point rows" (once simulated).
bool SimulateCalibrationMeasurements(
    const RobotDescription& robot, const CalibrationSimulationOptions& options,
    OptionSpelling spelling, std::vector<int64_t>* poses,
    std::vector<Measurement>* measurements, std::string* notes,
    std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_CALIBRATION_SETUP_H_
