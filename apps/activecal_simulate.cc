// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_simulate: the measurements a device would report at the poses
// of a poses CSV, computed from the robot's true values with Gaussian noise,
// so the calibration workflow can be tried without hardware.

#include <gflags/gflags.h>

#include <cstdio>

#include "activecal/io/csv_files.h"
#include "activecal/core/simulation.h"
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
DEFINE_uint64(seed, 1, "Seed of the noise.");

namespace activecal {
namespace {

int Main() {
  if (FLAGS_poses_csv.empty()) app::Fail("--poses_csv is required");
  if (FLAGS_out.empty()) app::Fail("--out is required");
  const RobotDescription robot = app::LoadRobotOrDie();
  const RobotModel& model = robot.model;
  if (robot.true_parameters.size() != model.num_parameters()) {
    app::Fail("--robot '" + FLAGS_robot +
              "' has no true values to simulate from: add 'true:' entries "
              "to its blocks (docs/formats.md)");
  }
  MeasurementType type;
  if (!ParseMeasurementType(FLAGS_type, &type)) {
    app::Fail("--type must be position, pose or distance, got '" + FLAGS_type +
              "'");
  }
  PoseList poses;
  std::string error;
  if (!ReadPosesCsv(FLAGS_poses_csv, model, /*reject_duplicates=*/false, &poses,
                    &error)) {
    app::Fail("--poses_csv: " + error);
  }
  std::vector<Measurement> plan;
  const int n = static_cast<int>(poses.joints.rows());
  if (type == MeasurementType::kDistance) {
    if (n < 2) app::Fail("--type=distance needs at least 2 poses, got 1");
    for (int i = 0; i + 1 < n; ++i) {
      if (poses.joints.row(i) == poses.joints.row(i + 1)) {
        app::Fail("--type=distance: poses " + std::to_string(i + 1) + " and " +
                  std::to_string(i + 2) + " of " + FLAGS_poses_csv +
                  " (data rows) are identical: a distance between them "
                  "measures nothing; remove one");
      }
      Measurement m;
      m.type = type;
      m.joints = poses.joints.row(i).transpose();
      m.joints2 = poses.joints.row(i + 1).transpose();
      plan.push_back(m);
    }
  } else {
    for (int i = 0; i < n; ++i) {
      Measurement m;
      m.type = type;
      m.joints = poses.joints.row(i).transpose();
      plan.push_back(m);
    }
  }
  SimulationNoise noise;
  noise.position_m = FLAGS_noise_m;
  noise.rotation_rad = FLAGS_rotation_noise_rad;
  std::vector<Measurement> measurements;
  if (!SimulateMeasurements(model, robot.true_parameters, plan, noise,
                            FLAGS_seed, &measurements, &error)) {
    if (type == MeasurementType::kDistance) {
      error +=
          " (measurement i is the distance between poses i + 1 and "
          "i + 2 of " +
          FLAGS_poses_csv + ", data rows)";
    }
    app::Fail(error);
  }
  app::WriteTextOrDie(FLAGS_out, MeasurementsCsvText(model, measurements));
  std::printf("wrote %zu %s measurements of '%s' to %s\n", measurements.size(),
              FLAGS_type.c_str(), model.name.c_str(), FLAGS_out.c_str());
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
      "--noise_m=0.01 --seed=1 --out=measurements.csv");
  return activecal::Main();
}
