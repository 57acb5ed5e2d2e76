// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// SimulateAtPoses: the measurements a device would report at the poses of
// a poses CSV, from the robot's true values (or its nominal values
// perturbed: PerturbParameters) plus Gaussian noise (what
// activecal_simulate runs). With a cell only the poses it allows are
// measured, each of the targets it sees; the ISO 9283 cycle columns of the
// poses CSV are carried to each measurement row.
//
//   SimulateOptions options;
//   options.poses_csv = "poses.csv";
//   options.out = "measurements.csv";  // named in the texts
//   SimulateSummary summary;
//   const bool ok = SimulateAtPoses(robot, options, &summary);
//   std::printf("%s", summary.report.c_str());  // also on a failure
//   if (!ok) LOG(ERROR) << summary.message;
//   // summary.measurements_csv, summary.true_model_text: the files.

#ifndef ACTIVECAL_CALIBRATION_SIMULATE_WORKFLOW_H_
#define ACTIVECAL_CALIBRATION_SIMULATE_WORKFLOW_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/cell/cell_checker.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/simulation.h"
#include "activecal/core/types.h"
#include "activecal/io/robot_file.h"

namespace activecal {

struct SimulateOptions {
  std::string poses_csv;  // the poses to measure (required)
  MeasurementType type = MeasurementType::kPosition;
  SimulationNoise noise = {0.001, 0.001};
  uint64_t seed = 1;  // of the noise and (its own stream) the perturbation
  // Move every parameter to identify by N(0, perturb_m^2) (lengths, m) and
  // N(0, perturb_rad^2) (angles, rad) from the true values (the nominal
  // ones when the robot has none).
  double perturb_m = 0.0;
  double perturb_rad = 0.0;
  // With a perturbation and reduce_parameter_set: the parameters moved are
  // parameter_set's, reduced to what the poses separate (ReduceForPool).
  bool reduce_parameter_set = false;
  ParameterSet parameter_set = ParameterSet::kFile;
  // The cell's checker (may be null): only the poses it allows are
  // measured.
  const CellChecker* cell = nullptr;
  // Make the true model's robot file (true_model_text).
  bool true_model = false;
  // Named in the texts: the measurements file and the true model's file,
  // the robot's file (empty: the built-in PUMA 560), the flags of the
  // perturbation as given ("--perturb_m=0.001 --perturb_rad=0 --seed=1").
  std::string out;
  std::string true_model_out;
  std::string robot_path;
  std::string perturbation_flags;
  std::string type_name = "position";  // in the result line
  std::string program_name = "activecal_simulate";
};

struct SimulateSummary {
  // CONVERGENCE when the measurements were made; FAILURE with message (one
  // line, naming the flag) otherwise.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  // What the program prints on stdout before it writes the files: the
  // cell's counts, the parameters held; on a failure, what was printed
  // before it.
  std::string report;
  RobotModel model;       // the model simulated (its free set reduced)
  Eigen::VectorXd truth;  // the values the measurements come from
  std::vector<Measurement> measurements;
  std::string measurements_csv;  // with the commanded poses' columns
  std::string true_model_text;   // options.true_model: the robot file
  // After the files are written: "wrote the true model (...) to ...\n"
  // (options.true_model) and the one-line result (what --quiet prints).
  std::string written_report;
  std::string result_line;
};

// `robot` is the robot as loaded (with a cell, its targets as the markers
// when the cell set them up so); it needs true values unless perturbed.
bool SimulateAtPoses(const RobotDescription& robot,
                     const SimulateOptions& options, SimulateSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SIMULATE_WORKFLOW_H_
