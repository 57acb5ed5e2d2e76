// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The robot a simulated cell (driver/simulated_cell.h) serves, as
// activecal_sim_cell sets it up: the cell file's checks and targets, the
// free parameters of --parameter_set reduced to what a 3-level lattice
// separates, and the true parameters (perturbed as the options ask); and the
// robot file of that truth (--truth_out).
//
//   SimulatedCellSetupOptions options;
//   options.cell_path = "data/cells/ur10e_table.yaml";
//   SimulatedCellSetup setup;
//   if (!SetUpSimulatedCell(options, &robot, &setup)) ... setup.message
#ifndef ACTIVECAL_CALIBRATION_SIMULATED_CELL_SETUP_H_
#define ACTIVECAL_CALIBRATION_SIMULATED_CELL_SETUP_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "activecal/cell/cell_setup.h"
#include "activecal/core/robot_model.h"
#include "activecal/driver/simulated_cell.h"
#include "activecal/io/robot_loader.h"

namespace activecal {

struct SimulatedCellSetupOptions {
  std::string cell_path;   // empty: no cell
  std::string robot_path;  // empty: the PUMA 560
  UrdfChainOptions chain;
  bool targets_as_markers = true;  // the cell's targets are the markers
  // The --parameter_set value: "" (full for a URDF robot, the file's free
  // lists otherwise; a robot file's set is then not reduced), registration,
  // offsets, full or file.
  std::string parameter_set;
  // The perturbation and its seed (MakeSimulatedCellTruth).
  SimulatedCellOptions cell;
};

struct SimulatedCellSetup {
  bool ok = false;
  std::string message;  // why not, when !ok: one line naming the flag
  CellSetup cell;       // empty without a cell; its notes are for stderr
  // The lattice's notes and the parameters held fixed, one line each, for
  // stdout; kept when a later step fails.
  std::string log;
  Eigen::VectorXd truth;  // the cell's true parameters
};

// Sets up `robot` (its model's free set reduced, its markers the cell's
// targets) and the truth. False with the message at the first failure.
bool SetUpSimulatedCell(const SimulatedCellSetupOptions& options,
                        RobotDescription* robot, SimulatedCellSetup* setup);

// The robot file of the cell's robot: nominal values and `truth`, with a
// comment naming the seed.
std::string SimulatedCellTruthText(const RobotModel& model,
                                   const Eigen::VectorXd& truth, uint64_t seed);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SIMULATED_CELL_SETUP_H_
