// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// What a program needs for --cell, in one call: the cell file, the robot's
// collision geometry (from the robot's own file), the cell's targets as the
// robot's markers when no frames file gives them, and the checker.
//
//   CellSetupOptions options;
//   options.cell_path = "data/cells/ur10e_table.yaml";
//   options.robot_path = "data/ur10e.urdf";
//   options.chain.tip_link = "tool0";
//   options.targets_as_markers = frames_path.empty();
//   CellSetup cell;
//   if (!SetUpCell(options, &robot, &cell, &error)) { ... }
//   FilterPool(*cell.checker, joints, filter_options, &summary);

#ifndef ACTIVECAL_CELL_CELL_SETUP_H_
#define ACTIVECAL_CELL_CELL_SETUP_H_

#include <memory>
#include <string>
#include <vector>

#include "activecal/cell/cell_checker.h"
#include "activecal/cell/cell_file.h"
#include "activecal/cell/robot_collision.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

struct CellSetupOptions {
  std::string cell_path;
  // The robot's file (URDF or robot YAML); empty: a built-in robot without
  // collision geometry.
  std::string robot_path;
  UrdfChainOptions chain;
  // Another file of the same chain (URDF or robot YAML) whose collision
  // geometry is used when robot_path has none (a calibrated robot YAML
  // written by activecal_identify --model_out carries none; the nominal
  // URDF it was calibrated from does). Empty: none.
  std::string collision_fallback_path;
  // Replace the robot's markers by the cell's targets (their points, zero
  // orientation; names and count the targets'): what to do when no frames
  // file gives the markers.
  bool targets_as_markers = true;
};

struct CellSetup {
  Cell cell;
  RobotCollisionModel collision;
  // The file the collision geometry came from: robot_path, or
  // collision_fallback_path when robot_path had none; empty when there is
  // no collision geometry (self-collision and obstacles are not checked).
  std::string collision_source;
  std::unique_ptr<CellChecker> checker;
  // Lines worth printing: "the robot has no collision geometry: ...",
  // "self_clearance_m 0.05: links forearm_link and wrist_2_link are never
  // that far apart ...".
  std::vector<std::string> notes;
};

// Loads everything; the checker is built on robot->model after the markers
// are replaced, at its nominal values. False with a message naming the
// file ("<file>:<line>:<col>: <field>: ...").
bool SetUpCell(const CellSetupOptions& options, RobotDescription* robot,
               CellSetup* setup, std::string* error);

// The pairs of links checked for self-collision that are closer than the
// cell's self_clearance_m at every one of `samples` configurations drawn
// uniformly inside the joint margins (a fixed seed; unbounded joints over
// one turn), each with the largest distance seen: pairs that reject every
// pose, e.g. two links next but one whose gap the intermediate joint does
// not change. SetUpCell notes them.
std::vector<PairDistance> SelfPairsAlwaysTooClose(const CellChecker& checker,
                                                  int samples = 64);

// The cell's targets as the robot's markers (see targets_as_markers); the
// free flags of every new marker are those of the robot's first marker.
bool UseTargetsAsMarkers(const Cell& cell, RobotDescription* robot,
                         std::string* error);

// `model` with every finite joint range narrowed by the checker's joint
// margin at both ends ([min + m, max - m]): the ranges a pool (a lattice,
// Sobol or random draws) is built in with a cell, so that its end levels
// sit at the margins (which the check passes: exactly at a margin is
// inside) rather than on the stops the margin rejects. An infinite end is
// kept. The checker must be for `model`'s joints.
RobotModel WithinJointMargins(const CellChecker& checker,
                              const RobotModel& model);

// The velocity limits of the robot's joints (rad/s, m/s) from its URDF's
// <limit velocity>; zeros when the file gives none (robot files, a
// built-in robot).
std::vector<double> RobotVelocityLimits(const std::string& robot_path,
                                        const UrdfChainOptions& chain,
                                        const RobotModel& model);

}  // namespace activecal

#endif  // ACTIVECAL_CELL_CELL_SETUP_H_
