// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_simulate: the measurements a device would report at the poses
// of a poses CSV, computed from the robot's true values with Gaussian noise,
// so the calibration workflow can be tried without hardware. A robot
// without true values (a URDF) is simulated from its nominal values
// perturbed (--perturb_m, --perturb_rad: PerturbParameters), the truth
// written with --true_model_out; with --cell only the poses the cell
// allows are measured, each of the targets it sees.

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "activecal/calibration/simulate_workflow.h"
#include "activecal/io/output_files.h"
#include "activecal/io/robot_loader.h"
#include "app_common.h"

constexpr char kUsage[] =
    "Writes the measurements a device would report at the poses of a "
    "poses CSV, from the true values of --robot (default: the Sun & "
    "Hollerbach PUMA 560, Table I) plus Gaussian noise.\n"
    "  activecal_simulate --robot=data/puma560.yaml --poses_csv=poses.csv "
    "--noise_m=0.01 --seed=1 --out=measurements.csv\n"
    "  activecal_simulate --robot=data/ur10e.urdf --tip_link=tool0 "
    "--poses_csv=poses.csv --perturb_m=0.001 --perturb_rad=0.001 "
    "--seed=1 --true_model_out=true.yaml --out=measurements.csv";

DEFINE_string(poses_csv, "",
              "Poses to measure (a poses CSV, e.g. from activecal_select "
              "--poses_csv). Required.");
DEFINE_string(out, "", "Measurements CSV to write. Required.");
DEFINE_string(type, "position",
              "position: the 3D point at each pose; pose: point and "
              "orientation (6D); distance: the distance between the points "
              "of consecutive poses (rows 1-2, 2-3, ...), as a ballbar.");
DEFINE_double(noise_m, 0.001,  // defaults::kSimulationNoiseM
              "Noise standard deviation on each axis of a point and on a "
              "distance (m).");
DEFINE_double(rotation_noise_rad, 0.001,
              "pose: noise standard deviation of each rotation component "
              "(rad).");
DEFINE_uint64(seed, 1,
              "Seed of the noise and of the perturbation (its own stream).");
DEFINE_double(perturb_m, 0.0,
              "Simulate from the robot's true values (its nominal values "
              "when it has none, e.g. a URDF) with every parameter to "
              "identify moved: lengths by N(0, perturb_m^2) (m). The "
              "parameters are --parameter_set's, reduced to what the poses "
              "separate.");
DEFINE_double(perturb_rad, 0.0,
              "As --perturb_m, angles by N(0, perturb_rad^2) (rad).");
DEFINE_string(true_model_out, "",
              "Robot file (YAML, docs/formats.md) to write: the model "
              "simulated, its 'true:' entries the values the measurements "
              "were computed from (activecal_identify --robot= reads it, and "
              "its JSON then gives each estimate's true value).");
DEFINE_string(cell, "",
              "Cell file (YAML, docs/formats.md): only the poses the cell "
              "allows are measured (the others are counted by reason, as "
              "activecal_select does), each of the targets it sees at that "
              "pose (a 'marker' column); without --frames the cell's "
              "targets are the markers.");

namespace activecal {
namespace {

// A flag's value as gflags holds it ("0.001", "-1").
std::string FlagText(const char* name) {
  gflags::CommandLineFlagInfo info;
  gflags::GetCommandLineFlagInfo(name, &info);
  return info.current_value;
}

int Main() {
  if (!FLAGS_parameter_set.empty()) {
    app::ParameterSetOrDie(!FLAGS_robot.empty() && IsUrdfPath(FLAGS_robot));
  }
  if (FLAGS_poses_csv.empty()) app::Fail("--poses_csv is required");
  if (FLAGS_out.empty()) app::Fail("--out is required");
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"perturb_m", FLAGS_perturb_m},
        {"perturb_rad", FLAGS_perturb_rad}}) {
    if (!(value >= 0) || !std::isfinite(value)) {
      app::Fail(std::string("--") + name + " must be >= 0, got " +
                FlagText(name));
    }
  }
  const bool perturbed = FLAGS_perturb_m > 0 || FLAGS_perturb_rad > 0;
  if (!FLAGS_parameter_set.empty() && !perturbed) {
    app::Fail(
        "--parameter_set chooses the parameters --perturb_m and "
        "--perturb_rad move: give one of them");
  }
  MeasurementType type;
  if (!ParseMeasurementType(FLAGS_type, &type)) {
    app::Fail("--type must be position, pose or distance, got '" + FLAGS_type +
              "'");
  }
  if (!FLAGS_cell.empty() && type == MeasurementType::kDistance) {
    app::Fail(
        "--cell plans what a tracker, cameras or mocap see: not with "
        "--type=distance (a ballbar)");
  }
  app::CheckWritableOrDie(FLAGS_out, "out");
  if (!FLAGS_true_model_out.empty()) {
    app::CheckWritableOrDie(FLAGS_true_model_out, "true_model_out");
  }
  RobotDescription robot = app::LoadRobotOrDie();
  CellSetup cell;
  if (!FLAGS_cell.empty()) {
    cell = app::SetUpCellOrDie(FLAGS_cell, FLAGS_frames.empty(), &robot);
  }
  const bool urdf = !FLAGS_robot.empty() && IsUrdfPath(FLAGS_robot);
  SimulateOptions options;
  options.poses_csv = FLAGS_poses_csv;
  options.type = type;
  options.noise.position_m = FLAGS_noise_m;
  options.noise.rotation_rad = FLAGS_rotation_noise_rad;
  options.seed = FLAGS_seed;
  options.perturb_m = FLAGS_perturb_m;
  options.perturb_rad = FLAGS_perturb_rad;
  options.reduce_parameter_set = urdf || !FLAGS_parameter_set.empty();
  if (perturbed && options.reduce_parameter_set) {
    options.parameter_set = app::ParameterSetOrDie(urdf);
  }
  options.cell = cell.checker.get();
  options.true_model = !FLAGS_true_model_out.empty();
  options.out = FLAGS_out;
  options.true_model_out = FLAGS_true_model_out;
  options.robot_path = FLAGS_robot;
  options.perturbation_flags = "--perturb_m=" + FlagText("perturb_m") +
                               " --perturb_rad=" + FlagText("perturb_rad") +
                               " --seed=" + FlagText("seed");
  options.type_name = FLAGS_type;
  options.program_name = app::ProgramName();
  SimulateSummary summary;
  const bool ok = SimulateAtPoses(robot, options, &summary);
  std::printf("%s", summary.report.c_str());
  if (!ok) app::Fail(summary.message);
  std::vector<OutputFile> outputs = {{FLAGS_out, summary.measurements_csv}};
  if (options.true_model) {
    outputs.push_back({FLAGS_true_model_out, summary.true_model_text});
  }
  std::string error;
  if (!WriteFilesAtomically(outputs, &error)) app::Fail(error);
  std::printf("%s", summary.written_report.c_str());
  // The one-line result (what --quiet prints), last.
  app::PrintResult(summary.result_line);
  return 0;
}

}  // namespace
}  // namespace activecal

ACTIVECAL_APP_MAIN(kUsage, activecal::Main)
