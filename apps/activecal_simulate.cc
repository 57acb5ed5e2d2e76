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
#include <glog/logging.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "activecal/calibration/cell_planning.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/core/simulation.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/output_files.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/robot_loader.h"
#include "app_common.h"

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

// The ISO 9283 cycle columns of --poses_csv (activecal_select
// --iso9283_cube writes them), one entry per data row; empty without them.
std::vector<CommandedPose> CommandedPosesOrDie(const RobotModel& model) {
  std::string text, error;
  std::vector<CommandedPose> commanded;
  if (!ReadTextFile(FLAGS_poses_csv, &text, &error) ||
      !ParseCommandedPosesIfAny(text, FLAGS_poses_csv, model,
                                MeasurementsCsvOptions(), &commanded, &error)) {
    app::Fail("--poses_csv: " + error);
  }
  return commanded;
}

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
  RobotModel& model = robot.model;
  const bool truth_known =
      robot.true_parameters.size() == model.num_parameters();
  if (!truth_known && !perturbed) {
    app::Fail("--robot '" + FLAGS_robot +
              "' has no true values to simulate from: add 'true:' entries "
              "to its blocks (docs/formats.md) or perturb it (--perturb_m, "
              "--perturb_rad)");
  }
  PoseList poses;
  std::string error;
  if (!ReadPosesCsv(FLAGS_poses_csv, model, /*reject_duplicates=*/false, &poses,
                    &error)) {
    app::Fail("--poses_csv: " + error);
  }
  const std::vector<CommandedPose> commanded = CommandedPosesOrDie(model);
  if (!commanded.empty() && type == MeasurementType::kDistance) {
    app::Fail("--poses_csv " + FLAGS_poses_csv +
              " has ISO 9283 cycle columns (pose, commanded_*): cycles are "
              "measured as --type=position or pose, not distance");
  }
  // The cell: the poses it allows, and the targets each sees.
  Eigen::MatrixXd joints = poses.joints;
  // The --poses_csv data row of each row of joints.
  std::vector<int64_t> rows(poses.joints.rows());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<int64_t>(i);
  std::vector<uint32_t> seen;
  if (cell.checker) {
    PoolFilterSummary feasibility;
    if (!FilterPool(*cell.checker, poses.joints, PoolFilterOptions(),
                    &feasibility)) {
      app::Fail("--cell: " + feasibility.message);
    }
    if (feasibility.num_feasible() == 0) {
      app::Fail("--cell: no pose of --poses_csv is left: " +
                FeasibleNote(*cell.checker, feasibility));
    }
    std::printf("  %s", feasibility.BriefReport(*cell.checker).c_str());
    joints = feasibility.FeasibleJoints(poses.joints);
    rows = feasibility.feasible;
    if (CellTargetsAreMarkers(*cell.checker, model)) {
      seen = feasibility.targets_seen;
    }
  }
  // The truth: the file's, or its nominal values, moved.
  Eigen::VectorXd truth = truth_known ? robot.true_parameters : model.nominal;
  if (perturbed) {
    const bool urdf = !FLAGS_robot.empty() && IsUrdfPath(FLAGS_robot);
    if (urdf || !FLAGS_parameter_set.empty()) {
      // The parameters the poses separate, each measuring what it sees.
      model = WithFreeSet(
          model, app::ReducedParameterSetOrDie(model, urdf, joints,
                                               seen.empty() ? nullptr : &seen));
    }
    const Eigen::VectorXd unperturbed = truth;
    if (!PerturbParameters(model, unperturbed, FLAGS_perturb_m,
                           FLAGS_perturb_rad, FLAGS_seed, &truth, &error)) {
      app::Fail("--" + error);
    }
  }
  std::vector<Measurement> plan;
  std::vector<int> row_of;  // the --poses_csv data row of each of plan
  const int n = static_cast<int>(joints.rows());
  if (type == MeasurementType::kDistance) {
    if (n < 2) app::Fail("--type=distance needs at least 2 poses, got 1");
    for (int i = 0; i + 1 < n; ++i) {
      if (joints.row(i) == joints.row(i + 1)) {
        app::Fail("--type=distance: poses " + std::to_string(i + 1) + " and " +
                  std::to_string(i + 2) + " of " + FLAGS_poses_csv +
                  " (data rows) are identical: a distance between them "
                  "measures nothing; remove one");
      }
      Measurement m;
      m.type = type;
      m.joints = joints.row(i).transpose();
      m.joints2 = joints.row(i + 1).transpose();
      plan.push_back(m);
    }
  } else {
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < (seen.empty() ? 1 : model.num_markers()); ++k) {
        if (!seen.empty() && (k >= 32 || !(seen[i] & (1u << k)))) continue;
        Measurement m;
        m.type = type;
        m.joints = joints.row(i).transpose();
        m.marker = k;
        plan.push_back(m);
        row_of.push_back(static_cast<int>(rows[i]));
      }
    }
  }
  SimulationNoise noise;
  noise.position_m = FLAGS_noise_m;
  noise.rotation_rad = FLAGS_rotation_noise_rad;
  std::vector<Measurement> measurements;
  if (!SimulateMeasurements(model, truth, plan, noise, FLAGS_seed,
                            &measurements, &error)) {
    if (type == MeasurementType::kDistance) {
      error +=
          " (measurement i is the distance between poses i + 1 and "
          "i + 2 of " +
          FLAGS_poses_csv + ", data rows)";
    }
    app::Fail(error);
  }
  // ISO 9283 cycles: the poses' label and commanded pose carried to each
  // measurement row, so that activecal_evaluate --iso9283 reads the file.
  std::string text = MeasurementsCsvText(model, measurements);
  if (!commanded.empty()) {
    CHECK_EQ(commanded.size(), static_cast<size_t>(poses.joints.rows()));
    CHECK_EQ(row_of.size(), measurements.size());
    text = WithCommandedPoseColumns(text, commanded, row_of);
  }
  std::vector<OutputFile> outputs = {{FLAGS_out, text}};
  if (!FLAGS_true_model_out.empty()) {
    RobotFileOptions text;
    text.angle_unit = robot.angle_unit;
    text.true_parameters = truth;
    text.comment =
        "The robot activecal_simulate measured: its 'true:' "
        "entries are the values the measurements of " +
        FLAGS_out + " were computed from";
    if (perturbed) {
      text.comment +=
          " (" + std::string(truth_known ? "the true" : "the nominal") +
          " values of " +
          (FLAGS_robot.empty() ? std::string("the built-in PUMA 560")
                               : FLAGS_robot) +
          ", every free parameter perturbed: --perturb_m=" +
          FlagText("perturb_m") + " --perturb_rad=" + FlagText("perturb_rad") +
          " --seed=" + FlagText("seed") + ")";
    }
    outputs.push_back(
        {FLAGS_true_model_out, RobotFileText(model, model.nominal, text)});
  }
  if (!WriteFilesAtomically(outputs, &error)) app::Fail(error);
  if (!FLAGS_true_model_out.empty()) {
    std::printf("wrote the true model (%d free parameters%s) to %s\n",
                model.num_free(), perturbed ? ", perturbed" : "",
                FLAGS_true_model_out.c_str());
  }
  // The one-line result (what --quiet prints), last.
  app::PrintResult(app::ProgramName() + ": wrote " +
                   std::to_string(measurements.size()) + " " + FLAGS_type +
                   " measurements of '" + model.name + "' to " + FLAGS_out);
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Writes the measurements a device would report at the poses of a "
      "poses CSV, from the true values of --robot (default: the Sun & "
      "Hollerbach PUMA 560, Table I) plus Gaussian noise.\n"
      "  activecal_simulate --robot=data/puma560.yaml --poses_csv=poses.csv "
      "--noise_m=0.01 --seed=1 --out=measurements.csv\n"
      "  activecal_simulate --robot=data/ur10e.urdf --tip_link=tool0 "
      "--poses_csv=poses.csv --perturb_m=0.001 --perturb_rad=0.001 "
      "--seed=1 --true_model_out=true.yaml --out=measurements.csv");
  return activecal::app::Finish(activecal::Main());
}
