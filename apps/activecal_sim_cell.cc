// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_sim_cell: a simulated robot cell (driver/simulated_cell.h) on
// stdin/stdout, or TCP with --listen, for trying activecal_active --driver
// without hardware and testing the loop end to end through a real pipe. Its
// robot: --robot's true values, or perturbed (--perturb_m, --perturb_rad;
// --truth_out writes that robot file, for the true error).

#include <gflags/gflags.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>

#include "activecal/calibration/simulated_cell_setup.h"
#include "activecal/driver/simulated_cell.h"
#include "activecal/io/robot_loader.h"
#include "app_common.h"

DEFINE_double(noise_m, 1e-4, "Tracker noise per axis (m), >= 0.");
DEFINE_bool(rotations, false,
            "Report the marker frame's orientation too (a 6D probe): "
            "\"rotations\" in the reply.");
DEFINE_double(rotation_noise_rad, 1e-4,
              "With --rotations: noise of each rotation-vector component "
              "(rad).");
DEFINE_bool(report_sigma, false, "Send sigma_m (= --noise_m) in replies.");
DEFINE_double(joint_noise_rad, 0.0,
              "Servo error: the robot stops this far (Gaussian per joint, "
              "rad or m) from the commanded joints; the encoders read where "
              "it stopped (the reply's joints_rad).");
DEFINE_double(perturb_m, 0.0,
              "Move every free length parameter of --robot by a Gaussian of "
              "this sigma (m) to make the cell's true robot (on top of the "
              "file's true values, if any).");
DEFINE_double(perturb_rad, 0.0,
              "The same for every free angle parameter (rad).");
DEFINE_string(truth_out, "",
              "Write the cell's robot (nominal values and true values) as "
              "an activecal robot file here.");
DEFINE_double(not_visible_fraction, 0.0,
              "Fraction of poses the tracker cannot see (status "
              "not_visible), drawn per pose.");
DEFINE_double(unreachable_fraction, 0.0,
              "Fraction of poses the robot refuses (status unreachable), "
              "drawn per pose.");
DEFINE_double(drift_m_per_measurement, 0.0,
              "Tracker drift: every point moves by this much (m, along x) "
              "per measurement served.");
DEFINE_int64(die_after, -1,
             "Exit (status 3, no reply) at the measure request after this "
             "many measurements were served; < 0: never.");
DEFINE_double(measure_delay_s, 0.0,
              "Wait this long before each reply (the robot moving).");
DEFINE_string(listen, "",
              "Serve TCP on PORT or HOST:PORT (HOST default 127.0.0.1; PORT "
              "0: any free one, printed on stderr) instead of stdin/stdout, "
              "one client after another.");
DEFINE_string(served_log, "",
              "Append every reply sent to this file (one JSON line each).");
DEFINE_string(garbage, "",
              "Answer measure request --garbage_at with bad output, to test "
              "activecal: not_json, nan, wrong_id, wrong_joints, "
              "wrong_markers, unknown_status, hang (no reply), exit.");
DEFINE_int64(garbage_at, 1, "Which measure request (1-based) --garbage hits.");
DEFINE_uint64(seed, 1, "Seed of the perturbation and of every answer.");

namespace activecal {
namespace {

// The protocol's output: the real stdout, kept aside so that nothing else
// the program prints (robot notes) reaches activecal.
int g_protocol_out = -1;

DEFINE_string(cell, "",
              "A cell file (docs/formats.md): its targets are the robot's "
              "markers (unless --frames gives them), and a marker is "
              "reported only where the cell's checks see it (a pose where "
              "none is seen is answered not_visible), as activecal_active "
              "--cell plans.");

int Main() {
  SimulatedCellOptions options;
  options.program_name = "activecal_sim_cell";
  options.noise_m = FLAGS_noise_m;
  options.rotations = FLAGS_rotations;
  options.rotation_noise_rad = FLAGS_rotation_noise_rad;
  options.report_sigma = FLAGS_report_sigma;
  options.joint_noise_rad = FLAGS_joint_noise_rad;
  options.not_visible_fraction = FLAGS_not_visible_fraction;
  options.unreachable_fraction = FLAGS_unreachable_fraction;
  options.drift_m_per_measurement = FLAGS_drift_m_per_measurement;
  options.die_after = FLAGS_die_after;
  options.measure_delay_s = FLAGS_measure_delay_s;
  options.served_log = FLAGS_served_log;
  if (!FLAGS_garbage.empty() &&
      !StringToDriverGarbage(FLAGS_garbage, &options.garbage)) {
    options.garbage = DriverGarbage::kLine;  // sent as it is, at garbage_at
    options.garbage_line = "garbage kind '" + FLAGS_garbage + "' unknown";
  }
  options.garbage_at = FLAGS_garbage_at;
  options.seed = FLAGS_seed;
  options.perturb_m = FLAGS_perturb_m;
  options.perturb_rad = FLAGS_perturb_rad;
  std::string error;
  if (!options.IsValid(&error)) app::Fail("--" + error);
  RobotDescription robot = app::LoadRobotOrDie();
  // The cell (its targets as the markers; its notes on stderr, not stdout),
  // the free set and the truth.
  SimulatedCellSetupOptions setup_options;
  setup_options.cell_path = FLAGS_cell;
  setup_options.robot_path = FLAGS_robot;
  setup_options.chain = app::Chain();
  setup_options.targets_as_markers = FLAGS_frames.empty();
  setup_options.parameter_set = FLAGS_parameter_set;
  setup_options.cell = options;
  SimulatedCellSetup setup;
  const bool set_up = SetUpSimulatedCell(setup_options, &robot, &setup);
  for (const std::string& note : setup.cell.notes) {
    std::fprintf(stderr, "activecal_sim_cell: --cell: note: %s\n",
                 note.c_str());
  }
  std::printf("%s", setup.log.c_str());
  if (!set_up) app::Fail(setup.message);
  const RobotModel& model = robot.model;
  const Eigen::VectorXd& truth = setup.truth;
  // --listen's socket before --truth_out: a run that fails writes nothing.
  options.listen = FLAGS_listen;
  SimulatedCell cell(model, truth, options, setup.cell.checker.get());
  int status = 0;
  if (!cell.Run(
          STDIN_FILENO, g_protocol_out,
          [&] {
            if (FLAGS_truth_out.empty()) return;
            app::WriteTextOrDie(FLAGS_truth_out, SimulatedCellTruthText(
                                                     model, truth, FLAGS_seed));
            app::CommitOutputsOrDie();  // read while the cell serves
          },
          &status, &error)) {
    app::Fail(error);
  }
  return status;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  // The protocol owns the real stdout; everything else goes to stderr.
  activecal::g_protocol_out = dup(STDOUT_FILENO);
  dup2(STDERR_FILENO, STDOUT_FILENO);
  activecal::app::Init(
      &argc, &argv,
      "A simulated robot cell speaking activecal's driver protocol "
      "(docs/driver_protocol.md) on stdin/stdout, or TCP with --listen: the "
      "robot of --robot with its true values (or perturbed: --perturb_m, "
      "--perturb_rad), tracker noise, occlusions, refused poses, drift, and "
      "a crash on demand (--die_after).\n"
      "  activecal_active --driver=\"activecal_sim_cell --seed=3 "
      "--not_visible_fraction=0.1\" --session=run1");
  return activecal::app::Finish(activecal::Main());
}
