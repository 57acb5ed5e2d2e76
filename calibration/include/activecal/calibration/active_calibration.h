// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The active calibration workflow of activecal_active: the loop of
// active_loop.h with its batches designed (a D-optimal first batch, then
// task-optimal ones at each new estimate, optionally run as short tours),
// measured by a robot cell behind the driver protocol or simulated from the
// true values, kept in a session directory (resumable after a crash), the
// rounds printed as they complete, compared with one-shot designs, and
// reported as JSON.
//
//   ActiveCalibrationOptions options;
//   options.loop.sigma_m = 1e-4;
//   options.loop.target_rms_m = 5e-5;
//   options.driver = "python3 examples/driver_example.py";  // or simulate
//   options.session_dir = "run1";
//   ActiveCalibrationSummary summary;
//   if (!RunActiveCalibration(model, truth, joints, /*cell=*/nullptr,
//                             /*feasibility=*/nullptr, options, &summary)) {
//     // summary.message: nothing was reported
//   }
//   write summary.report; summary.loop_ok, summary.ResultLine()
//
// With options.log_to_stdout the workflow prints what activecal_active
// prints on stdout (the session's notes, the driver's hello with
// options.verbose, the rounds' table, one line per measurement with
// options.verbose, the termination, the tour's and the one-shot designs'
// lines). A round whose residuals exceed the noise is warned about in
// summary.warnings and through options.warning, as it completes (the
// library writes nothing to stderr).

#ifndef ACTIVECAL_CALIBRATION_ACTIVE_CALIBRATION_H_
#define ACTIVECAL_CALIBRATION_ACTIVE_CALIBRATION_H_

#include <Eigen/Core>
#include <chrono>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "activecal/calibration/active_loop.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/csv_files.h"

namespace activecal {

struct ActiveCalibrationOptions {
  // The loop's options (sigma_m, target_rms_m, batches, max_rounds, seed,
  // num_threads); the workflow sets true_parameters, the pool filter and
  // the marker masks (from the cell and the model's markers).
  ActiveLoopOptions loop;
  int restarts = 4;  // of each design (FedorovExchange, TaskExchange)
  // Recorded in the session's identity and the report: the lattice's
  // values per joint, and how far the start is from the truth.
  int levels = 4;
  double nominal_error_scale = 1.0;
  // Measure on a robot cell: the driver's command or tcp://HOST:PORT
  // (DriverClientOptions::driver); empty: simulate from the true values.
  std::string driver;
  double driver_timeout_s = 120.0;
  // The session directory (empty: none), and whether to continue it.
  std::string session_dir;
  bool resume = false;
  // The cell file's path and text (the session knows it by its content;
  // empty text: read from cell_path); used when RunActiveCalibration is
  // given a cell.
  std::string cell_path;
  std::string cell_text;
  // Each batch's new poses as a short tour in joint space (OrderTour), run
  // from the end nearer the last pose measured; with a cell every move
  // checked at joint steps of order_resolution_deg (deg; mm prismatic), at
  // the joints' velocity limits in the robot's file (RobotVelocityLimits of
  // robot_path and chain).
  bool order_shortest = false;
  double order_resolution_deg = 1.0;
  std::string robot_path;
  UrdfChainOptions chain;
  // Also measure one-shot designs of the loop's total size at the nominal
  // values: D-optimal, task-optimal, random (simulation only).
  bool compare = false;
  bool verbose = false;  // the driver's hello, one line per measurement
  bool log_to_stdout = false;
  // The start of the run: the rounds' seconds count from it.
  std::chrono::steady_clock::time_point start =
      std::chrono::steady_clock::now();
  // Called with a line after every round ("round 0 done: 12 poses,
  // predicted task RMS 0.000193 m (1.2 s)"); null: none.
  std::function<void(const std::string& line)> progress;
  // MakeActivePool: called when the cell's checks start ("cell checks");
  // the callback it returns gets their progress. May be empty.
  std::function<ProgressCallback(const std::string& stage)> stage_progress;
  // Called with each warning as it is made (also kept in
  // ActiveCalibrationSummary::warnings), one line without its newline:
  // "warning: round 2: the residual sigma 0.00031 m is 3.1 times --noise_m:
  // ..."; null: none.
  std::function<void(const std::string& line)> warning;

  // The run's options against what is known of the robot: a simulation
  // needs its true values, nominal_error_scale is >= 0 (and 1 without the
  // true values), compare simulates (not with a driver). False with
  // *error naming the first wrong one as the program's flag
  // ("--nominal_error_scale must be >= 0").
  bool IsValidFor(bool truth_known, std::string* error) const;
};

struct ActiveCalibrationSummary {
  // The loop's summary; loop_ok: it converged or ran out (not FAILURE /
  // USER_FAILURE).
  ActiveLoopSummary loop;
  bool loop_ok = false;
  // The per-round report (activecal_active --json_out): the options, the
  // rounds, the poses measured and excluded, the tour, the cell's
  // preprocess, the one-shot designs.
  nlohmann::json report;
  // The poses measured, in measuring order (pool indices in
  // pose_indices), e.g. for a controller program.
  PoseList measured_poses;
  // The warnings, in order (options.warning got each as it was made).
  std::vector<std::string> warnings;
  // Why the workflow or the loop failed, with the session's note ("(the
  // session in DIR keeps every answer: continue it with --resume)").
  std::string message;

  // "CONVERGENCE after 1 round, 12 poses measured, predicted task RMS
  // 0.1928 mm (target 0.5 mm)".
  std::string ResultLine(double target_rms_m) const;
};

// The pool the loop designs from, made before it (activecal_active; and
// activecal_sim_cell's reduction): the lattice of options.levels values per
// joint (with a cell, inside its joint margins) and the cell's checks of
// every pose, once (every batch and every repair is designed from the
// feasible ones), on options.loop.num_threads threads, the feasible poses
// holding options.loop.first_batch at least.
struct ActivePool {
  // The loop's start: the robot with its nominal values moved to
  // truth + nominal_error_scale (nominal - truth) when the truth is known;
  // ReduceForActivePool reduces its free set.
  RobotModel model;
  Eigen::MatrixXd joints;         // the lattice's poses, one per row
  PoolFilterSummary feasibility;  // with a cell: its verdict on each pose
  // What activecal_active prints, in order: the lattice's one-turn notes,
  // the cell's counts per reason, the parameters a reduction held.
  std::string report;
  std::string message;  // why it failed, naming the flag
};

// False with pool->message ("--levels=1: ...", "--cell: no pose of the pool
// is left: ...", "--first_batch=400: the feasible pool has only ...") when
// the lattice cannot be made, the checks fail or leave too few poses.
// `true_parameters`: full vector, else unknown. `cell` may be null.
bool MakeActivePool(const RobotModel& model,
                    const Eigen::VectorXd& true_parameters,
                    const CellSetup* cell,
                    const ActiveCalibrationOptions& options, ActivePool* pool);

// Reduces pool->model's free set `set` to what the pool's poses separate (with
// a cell its feasible ones, each measuring the targets it sees when they are
// the markers; several markers otherwise: each pose measures every one),
// with ReduceForPool at evenly spaced rows, and starts the model at the
// reduction's point (a marker at the tip frame's origin moved ~1 mm off
// the last axis, where the kept parameters are separated). Appends a line
// per parameter held to pool->report ("  --parameter_set=full: <name> held
// fixed: <reason>"); false with pool->message ("--parameter_set=full: ...").
bool ReduceForActivePool(ParameterSet set, const CellSetup* cell,
                         ActivePool* pool);

// Runs the workflow. `model` holds the start (nominal values) and the free
// parameters; `true_parameters` the truth (full vector; else unknown,
// then options.driver must be set); `joints` the pool, which is also the
// task. `cell` and `feasibility` (both null, or both set: FilterPool of
// `joints`) restrict every batch to the feasible poses and, when the
// cell's targets are the markers, each pose to the targets it sees.
// Returns false when there is nothing to report (bad options, a session
// or driver that cannot start, a loop that failed before its first round,
// a one-shot design that failed): summary->message says why. True: the
// report is made; summary->loop_ok says whether the loop itself ended well
// (else summary->message).
bool RunActiveCalibration(const RobotModel& model,
                          const Eigen::VectorXd& true_parameters,
                          const Eigen::MatrixXd& joints, const CellSetup* cell,
                          const PoolFilterSummary* feasibility,
                          const ActiveCalibrationOptions& options,
                          ActiveCalibrationSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_ACTIVE_CALIBRATION_H_
