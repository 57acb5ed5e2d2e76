// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Select: the whole corridor of activecal_select, from a robot model to a
// design ready to run: the candidate pool (a joint lattice, a Sobol or
// random draw, the poses a cell can measure, or a poses CSV), the cell's
// preprocess (its checks of every pose, the counts per reason), the pool's
// Jacobians and parameter set (selection_pool.h), the task and the poses
// already measured, the design (SelectDesign), the D-efficiency lost to the
// cell against an unconstrained pool, the tour, and the outputs: the text
// report, the poses CSV, the rejected poses, the target's curve and the
// JSON report. What activecal_select calls (one call).
//
//   SelectOptions options;
//   options.pool = SelectPool::kSobol;
//   options.pool_size = 4000;
//   options.design.algorithm = DesignAlgorithm::kFedorov;
//   SelectSummary summary;
//   if (!Select(model, options, &summary)) {
//     std::cout << summary.report;  // what was done before the failure
//     ...summary.message...
//   }
//   std::cout << summary.report;
//   summary.poses_csv, summary.json, summary.ResultLine()
//
// The messages name the options as the program's flags ("--pool_csv: ...")
// or, with option_spelling = kKeywords, as the Python module's keywords
// ("pool_size: ...", "pass auto_fix=True"). The Python module's select is
// the same call with the pool, the task poses and the measured poses given
// in memory (pool_poses, task_joints, measured).

#ifndef ACTIVECAL_CALIBRATION_SELECT_WORKFLOW_H_
#define ACTIVECAL_CALIBRATION_SELECT_WORKFLOW_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "activecal/calibration/calibration_report.h"
#include "activecal/calibration/defaults.h"
#include "activecal/calibration/select_design.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/cell/tour.h"
#include "activecal/core/candidate_pool.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/column_map.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

// Where the candidate poses come from.
enum class SelectPool {
  kLattice,     // levels values per joint
  kSobol,       // pool_size quasi-random poses inside the joint ranges
  kRandom,      // pool_size random poses, seeded
  kMeasurable,  // with a cell: pool_size poses the device can measure
  kCsv,         // the poses CSV pool_csv
  kPoses,       // the poses pool_poses, given in memory
};

// "lattice", "sobol", "random", "measurable", "csv", "poses".
const char* SelectPoolToString(SelectPool pool);
// The inverse of SelectPoolToString for the drawn pools and the lattice
// (not "csv" nor "poses": those pools are named by their path or given);
// false on any other text.
bool StringToSelectPool(const std::string& text, SelectPool* pool);

// A stage's progress: called when a stage that reports progress starts
// ("measurable poses", "cell checks", "Jacobians of the pool poses",
// "approximate design, rounds", "<algorithm> restarts"); the callback it
// returns gets the stage's updates, and is dropped (its last copy
// destroyed) when the stage ends.
using StageProgress = std::function<ProgressCallback(const std::string& stage)>;

struct SelectOptions {
  // The candidate pool.
  // A pool_csv given with kLattice is read as kCsv.
  SelectPool pool = SelectPool::kLattice;
  int levels = defaults::kLevels;  // kLattice
  // kSobol, kRandom, kMeasurable (unset: defaults::kPoolSize); set for
  // another pool, an error.
  std::optional<int64_t> pool_size;
  // kMeasurable (unset or 0: 10 x pool_size); set for another pool, an
  // error.
  std::optional<int64_t> max_draws;
  std::string pool_csv;  // kCsv
  // kPoses: the candidate poses (rows: poses, the model's joints) and
  // their labels (empty: the rows; else one per pose, unique, as
  // CheckPoseIndices takes them); given for another pool, an error.
  PoseList pool_poses;
  // The cell (may be null; kMeasurable needs one): the pool keeps the
  // poses it can run; cell_path names it in the JSON.
  const CellSetup* cell = nullptr;
  std::string cell_path;
  // The pool's rows: what is measured, the parameters, the storage.
  MeasurementType type = MeasurementType::kPosition;
  double rotation_weight_m_per_rad = defaults::kRotationWeightMPerRad;
  ParameterSet parameter_set = ParameterSet::kFile;
  bool auto_fix = false;
  PoolStorage storage = PoolStorage::kAuto;
  int64_t max_double_pool_mib = defaults::kMaxDoublePoolMib;
  // The design (seed, num_threads and noise_m serve every step).
  SelectDesignOptions design;
  // The task poses (poses CSV; empty: the pool) and the poses already
  // measured (measurements CSV read with column_map; task criterion).
  std::string task_poses_csv;
  std::string measured_csv;
  std::optional<ColumnMap> column_map;
  // The same in memory: the task poses (rows; used when it has any, instead
  // of task_poses_csv) and the measurements made (with measured_csv, read
  // after them).
  Eigen::MatrixXd task_joints;
  std::vector<Measurement> measured;
  // With a cell and the D criterion: the design of an unconstrained pool
  // of the feasible pool's size, and the D-efficiency lost to the cell.
  bool cell_efficiency = true;
  // The design as a short tour (moves checked with a cell), at the velocity
  // limits of robot_path's file (chain: its URDF chain).
  bool order_shortest = false;
  double order_resolution_deg = 1.0;
  std::string robot_path;
  UrdfChainOptions chain;
  // Make the rejected poses' CSV (with a cell).
  bool rejected_csv = false;
  // The program's name, in the --auto_fix note and the result line.
  std::string program_name = "activecal_select";
  StageProgress progress;  // may be empty
  // How the messages name the options: the flags (kFlags, "--levels=1:
  // ...") or the Python module's keywords (kKeywords, "levels=1: ...").
  OptionSpelling option_spelling = OptionSpelling::kFlags;

  // The pool's options: one source (pool_csv or a drawn pool), a cell for
  // kMeasurable, a size only for a drawn pool and in memory's reach (for
  // `model`, CheckSelectionPoolSize), max_draws only for kMeasurable and
  // >= 0. False with *error naming the first wrong one as the program's
  // flag ("--max_draws must be >= 0, got -1"). Select checks it first.
  bool IsValid(const RobotModel& model, std::string* error) const;
};

struct SelectSummary {
  // CONVERGENCE or NO_CONVERGENCE (the design's) when usable; FAILURE with
  // message (one line, naming the flag) otherwise.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  // What the program prints on stdout, in order: the pool's notes and
  // counts, the design's report, the tour, the table of the poses; on a
  // failure, what was printed before it.
  std::string report;
  // The feasible pool's joints and labels (pool_index or pose_index; empty:
  // the row), and the design (its indices in the tour's order).
  Eigen::MatrixXd pool_joints;
  std::vector<int64_t> labels;
  SelectDesignSummary design;
  // What the report prints as text, as data: the lattice's notes (one
  // line each), the pool's build (the parameters held and why, the rows a
  // cell kept, the storage) and, with a cell, its checks of every pose of
  // the pool listed (feasible: the kept rows; targets_seen, the counts).
  std::vector<std::string> lattice_notes;
  SelectionPoolSummary pool;
  PoolFilterSummary feasibility;
  // The design's poses, labelled (for the poses CSV and a program).
  PoseList chosen;
  std::string poses_csv;     // PosesCsvText (with the targets seen)
  std::string rejected_csv;  // options.rejected_csv with a cell
  std::string curve_csv;     // with a target: num_poses, predicted RMS
  nlohmann::json json;       // the JSON report
  double total_seconds = 0;

  bool IsSolutionUsable() const {
    return termination_type == TerminationType::kConvergence ||
           termination_type == TerminationType::kNoConvergence;
  }
  // "<program>: 12 poses of 4000 (fedorov), log10 det -12.3456[,
  // D-efficiency >= 0.9876]": what --quiet prints.
  std::string ResultLine(const std::string& program_name) const;
};

// Returns summary->IsSolutionUsable(). `model` is the robot as loaded (with
// a cell, its targets as the markers when the cell set them up so).
bool Select(const RobotModel& model, const SelectOptions& options,
            SelectSummary* summary);

// JSON for a selection result: algorithm, pool_size, num_parameters,
// pose_indices (labels of the chosen pool rows; empty labels: the rows),
// joint_angles_rad, log10_det, oi, history_log10_det.
nlohmann::json SelectionJson(const SelectionSummary& summary,
                             const Eigen::MatrixXd& pool_joints,
                             const std::vector<int64_t>& labels);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SELECT_WORKFLOW_H_
