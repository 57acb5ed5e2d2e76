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
    // sim_cell has no --levels: the lattice is its own ("levels=3: ...").
    if (!MakeLatticePool(model, nullptr, 3, MeasurementType::kPosition, "",
                         &lattice, &setup->log, &error)) {
      setup->message =
          "the joint lattice the free set is reduced over: " + error;
      return false;
    }
    ParameterSet set;
    if (!ParseParameterSet(options.parameter_set, urdf, &set, &error)) {
      setup->message = "--" + error;
      return false;
    }
    const Eigen::MatrixXd joints = lattice.AllJointValues();
    // Several markers: the truth is every marker's, each measured at every
    // pose (marker 0's alone held the others' offsets).
    std::vector<uint32_t> every_marker;
    if (model.num_markers() > 1) {
      every_marker.assign(joints.rows(), EveryMarkerMask(model));
    }
    if (!ReduceModelForPool(set, joints,
                            every_marker.empty() ? nullptr : &every_marker,
                            &model, &setup->log, &setup->message)) {
      return false;
    }
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
