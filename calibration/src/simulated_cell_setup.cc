// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/simulated_cell_setup.h"

#include <string>
#include <vector>

#include "activecal/calibration/pool_builder.h"
#include "activecal/calibration/pool_reduction.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/io/robot_file.h"

namespace activecal {

bool SetUpSimulatedCell(const SimulatedCellSetupOptions& options,
                        RobotDescription* robot, SimulatedCellSetup* setup) {
  *setup = SimulatedCellSetup();
  std::string error;
  if (!options.cell_path.empty()) {
    CellSetupOptions cell;
    cell.cell_path = options.cell_path;
    cell.robot_path = options.robot_path;
    cell.chain = options.chain;
    cell.targets_as_markers = options.targets_as_markers;
    if (!SetUpCell(cell, robot, &setup->cell, &error)) {
      setup->message = "--cell: " + error;
      return false;
    }
  }
  RobotModel& model = robot->model;
  const bool urdf =
      !options.robot_path.empty() && IsUrdfPath(options.robot_path);
  if (urdf || !options.parameter_set.empty()) {
    // The free set reduced over a 3-level lattice.
    JointLattice lattice;
    if (!JointLattice::Create(model, 3, &lattice, &error) ||
        !CheckSelectionPoolSize(lattice.size(), model,
                                MeasurementType::kPosition, &error)) {
      // sim_cell has no --levels: the lattice is its own.
      setup->message =
          "the 3-level joint lattice the free set is reduced over: " + error;
      return false;
    }
    for (const std::string& note : lattice.OneTurnNotes(model)) {
      setup->log += "note: " + note + "\n";
    }
    ParameterSet set = urdf ? ParameterSet::kFull : ParameterSet::kFile;
    if (!options.parameter_set.empty() &&
        !StringToParameterSet(options.parameter_set, &set)) {
      setup->message =
          "--parameter_set must be registration, offsets, full or file, "
          "got '" +
          options.parameter_set + "'";
      return false;
    }
    const Eigen::MatrixXd joints = lattice.AllJointValues();
    // Several markers: the truth is every marker's, each measured at every
    // pose (marker 0's alone held the others' offsets).
    std::vector<uint32_t> every_marker;
    if (model.num_markers() > 1) {
      every_marker.assign(joints.rows(), EveryMarkerMask(model));
    }
    PoolReductionOptions reduce;
    reduce.evenly_spaced = true;
    PoolReduction reduction;
    if (!ReduceForPool(model, set, joints,
                       every_marker.empty() ? nullptr : &every_marker, reduce,
                       &reduction)) {
      setup->message =
          "--parameter_set=" + std::string(ParameterSetToString(set)) + ": " +
          reduction.message;
      return false;
    }
    for (const HeldParameter& d : reduction.held) {
      setup->log +=
          "  --parameter_set=" + std::string(ParameterSetToString(set)) + ": " +
          d.name + " held fixed: " + d.reason + "\n";
    }
    model = WithFreeSet(model, reduction.free);
  }
  if (!MakeSimulatedCellTruth(model, robot->true_parameters, options.cell,
                              &setup->truth, &error)) {
    setup->message = "--" + error;
    return false;
  }
  setup->ok = true;
  return true;
}

std::string SimulatedCellTruthText(const RobotModel& model,
                                   const Eigen::VectorXd& truth,
                                   uint64_t seed) {
  RobotFileOptions file;
  file.true_parameters = truth;
  file.comment =
      "The robot of activecal_sim_cell --seed=" + std::to_string(seed) +
      " (nominal values and the cell's true values)";
  return RobotFileText(model, model.nominal, file);
}

}  // namespace activecal
