// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_active: the active calibration loop. A D-optimal first batch
// at the nominal values, then, round by round, measure, identify, and
// select the next task-optimal batch at the new estimate, until the
// predicted task RMS meets --target_rms_m. The measurements come from a
// robot cell behind the driver protocol (--driver, docs/driver_protocol.md)
// or from a robot simulated here (the robot file's true values). With
// --session every answer and the loop's state are kept on disk as they
// come, and --resume continues after a crash. With --compare (simulation),
// one-shot designs of the same total size (D-optimal and task-optimal at
// nominal, random) are measured and identified too. With --cell every
// batch is chosen from the poses the cell can run (joint margins,
// collisions, the device's range and view of the targets).

#include <gflags/gflags.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "activecal/calibration/active_calibration.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/io/robot_loader.h"
#include "app_common.h"

constexpr char kUsage[] =
    "The active calibration loop: a D-optimal first batch, then "
    "task-optimal batches designed at each new estimate, until the "
    "predicted task RMS meets --target_rms_m. Measured by a robot cell "
    "(--driver, docs/driver_protocol.md) or simulated (--robot with "
    "'true:' values; default the Sun & Hollerbach PUMA 560).\n"
    "  activecal_active --target_rms_m=5e-5 --compare --json_out=loop.json\n"
    "  activecal_active --driver=\"activecal_sim_cell --seed=7\" "
    "--session=run1   (then --resume after a crash)";

DEFINE_int32(levels, 4,
             "Lattice values per joint of the pool (and of the task: the "
             "robot works over the whole lattice).");
DEFINE_double(noise_m, 1e-4,
              "The tracker's noise per axis (m): simulated without --driver; "
              "with one, what the prediction and the residual check assume.");
DEFINE_double(target_rms_m, 5e-5,
              "Stop when the predicted task RMS position error is at most "
              "this (m).");
DEFINE_int32(first_batch, 12, "Poses of the first, D-optimal batch.");
DEFINE_int32(batch_size, 6, "Poses of each later, task-optimal batch.");
DEFINE_int32(max_rounds, 30, "Rounds at most.");
DEFINE_double(nominal_error_scale, 1.0,
              "Start from truth + s (nominal - truth): 1 is the robot file's "
              "nominal, 0.1 one ten times closer to the truth, 2 farther.");
DEFINE_bool(compare, false,
            "Also measure one-shot designs of the loop's total size at the "
            "nominal values: D-optimal, task-optimal, random (simulation "
            "only).");
DEFINE_int32(restarts, 4, "Restarts of each design.");
DEFINE_uint64(seed, 1, "Seed of the noise and the random choices.");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");
DEFINE_string(json_out, "", "If set, write the per-round report here.");
DEFINE_string(driver, "",
              "Measure on a robot cell: the driver's command (run without a "
              "shell, e.g. \"python3 examples/driver_example.py\") or "
              "tcp://HOST:PORT of a running one (docs/driver_protocol.md). "
              "Empty: simulate the robot file's true values.");
DEFINE_double(driver_timeout_s, 120.0,
              "The longest wait for any answer of the driver (s).");
DEFINE_string(session, "",
              "Keep the session in this directory: every measurement "
              "appended to DIR/measurements.csv and synced as it comes, the "
              "loop's state after every round (docs/driver_protocol.md).");
DEFINE_bool(resume, false,
            "Continue the session in --session after a crash (of activecal "
            "or of the driver), without measuring again what it holds.");
DEFINE_bool(verbose, false, "One line per measurement.");
DEFINE_string(cell, "",
              "Cell file (YAML, docs/formats.md): joint margins, clearance, "
              "obstacles, the device and the targets. Every batch is chosen "
              "from the pool poses the cell can run; without --frames the "
              "cell's targets are the markers.");
DEFINE_string(order, "none",
              "none: each batch's poses in the design's order; shortest: "
              "a short tour in joint space (time at the URDF's velocity "
              "limits, nearest neighbour + 2-opt, as activecal_select), "
              "run from the end nearer the last pose measured; with --cell "
              "every move of the tour checked for collisions.");
DEFINE_double(order_resolution_deg, 1.0,
              "--order=shortest with --cell: a move is checked at joint "
              "steps of at most this (deg; mm for prismatic joints).");
DEFINE_string(program_out, "",
              "Also write the measured poses, in measuring order, as a "
              "program for the controller (docs/driver_protocol.md).");
DEFINE_string(program_language, "urscript",
              "--program_out's language: urscript, krl or rapid.");
DEFINE_string(controller, "",
              "The controller's joint convention (YAML: sign and zero of "
              "each joint, data/controllers/); empty: activecal's.");

namespace activecal {
namespace {

int Main() {
  const int64_t start_ns = app::NowNs();
  RobotDescription robot = app::LoadRobotOrDie();
  // The cell: its checks, and its targets as the markers unless --frames
  // gives them (before the truth is read: the markers' true values come
  // with them).
  const bool with_cell = !FLAGS_cell.empty();
  const CellSetup cell =
      with_cell ? app::SetUpCellOrDie(FLAGS_cell, FLAGS_frames.empty(), &robot)
                : CellSetup();
  const bool truth_known =
      robot.true_parameters.size() == robot.model.num_parameters();
  ActiveCalibrationOptions options;
  options.loop.sigma_m = FLAGS_noise_m;
  options.loop.target_rms_m = FLAGS_target_rms_m;
  options.loop.first_batch = FLAGS_first_batch;
  options.loop.batch_size = FLAGS_batch_size;
  options.loop.max_rounds = FLAGS_max_rounds;
  options.loop.seed = FLAGS_seed;
  options.loop.num_threads = FLAGS_threads;
  options.restarts = FLAGS_restarts;
  options.levels = FLAGS_levels;
  options.nominal_error_scale = FLAGS_nominal_error_scale;
  options.driver = FLAGS_driver;
  options.driver_timeout_s = FLAGS_driver_timeout_s;
  options.session_dir = FLAGS_session;
  options.resume = FLAGS_resume;
  options.cell_path = FLAGS_cell;
  options.order_shortest = FLAGS_order == "shortest";
  options.order_resolution_deg = FLAGS_order_resolution_deg;
  options.robot_path = FLAGS_robot;
  options.chain = app::Chain();
  options.compare = FLAGS_compare;
  options.verbose = FLAGS_verbose;
  std::string error;
  if (!options.IsValidFor(truth_known, &error)) app::Fail(error);
  app::CheckTourFlagsOrDie(FLAGS_order, FLAGS_order_resolution_deg);
  if (FLAGS_resume && FLAGS_session.empty()) {
    app::Fail("--resume continues a --session: name its directory");
  }
  // The pool (with a cell its checks, once), and a named parameter set
  // reduced to what the poses the loop may design separate.
  options.stage_progress = app::StageProgressLines();
  ActivePool pool;
  const bool pool_ok =
      MakeActivePool(robot.model, robot.true_parameters,
                     with_cell ? &cell : nullptr, options, &pool);
  std::printf("%s", pool.report.c_str());
  if (!pool_ok) app::Fail(pool.message);
  const bool urdf = !FLAGS_robot.empty() && IsUrdfPath(FLAGS_robot);
  if (urdf || !FLAGS_parameter_set.empty()) {
    pool.report.clear();
    const bool reduced = ReduceForActivePool(
        app::ParameterSetOrDie(urdf), with_cell ? &cell : nullptr, &pool);
    std::printf("%s", pool.report.c_str());
    if (!reduced) app::Fail(pool.message);
  }
  const ProgramRequest program = app::ProgramRequestOrDie(
      pool.model, FLAGS_program_out, FLAGS_program_language, FLAGS_controller);
  app::CheckWritableOrDie(FLAGS_json_out, "json_out");
  options.log_to_stdout = true;
  options.start =
      std::chrono::steady_clock::time_point(std::chrono::nanoseconds(start_ns));
  options.progress = [](const std::string& line) { app::PrintProgress(line); };
  options.warning = [](const std::string& line) {
    std::fprintf(stderr, "%s\n", line.c_str());
  };
  ActiveCalibrationSummary summary;
  if (!RunActiveCalibration(pool.model, robot.true_parameters, pool.joints,
                            with_cell ? &cell : nullptr,
                            with_cell ? &pool.feasibility : nullptr, options,
                            &summary)) {
    app::Fail(summary.message);
  }
  if (!FLAGS_json_out.empty())
    app::WriteJsonOrDie(FLAGS_json_out, summary.report);
  if (!program.path.empty()) {
    app::WriteProgramOrDie(pool.model, program, summary.measured_poses,
                           "the poses activecal_active measured, in order");
  }
  if (!summary.loop_ok) app::Fail(summary.message);
  // The result line (all that --quiet prints).
  app::PrintResult("activecal_active: " +
                   summary.ResultLine(FLAGS_target_rms_m));
  return 0;
}

}  // namespace
}  // namespace activecal

ACTIVECAL_APP_MAIN(kUsage, activecal::Main)
