// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Test helper: a simulated socket session (point_simulation.h) as a
// measurements CSV of type=point rows, for the CLI tests of calibration
// without a tracker.
//
//   make_point_measurements URDF TIP OUT.csv POINTS.yaml SEED [PLACEMENT_M]
//       [NUM_POINTS] [PER_POINT] [SOCKET_SEED]
//
// The truth: the URDF's nominal with a ball 0.02, -0.01, 0.1 m off the tip
// and every free parameter moved by 0.5 mm / 0.5 mrad (PerturbParameters,
// SEED); the sockets and configurations from SOCKET_SEED (default SEED + 1:
// another SOCKET_SEED is another placement of the block). POINTS.yaml: the true
// distances between consecutive sockets, in the --points form.

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "activecal/core/point_simulation.h"
#include "activecal/core/simulation.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/urdf_robot.h"
#include "simulated_session.h"

int main(int argc, char** argv) {
  using namespace activecal;
  if (argc < 6) {
    std::fprintf(stderr,
                 "usage: %s URDF TIP OUT.csv POINTS.yaml SEED [PLACEMENT_M] "
                 "[NUM_POINTS] [PER_POINT] [SOCKET_SEED]\n",
                 argv[0]);
    return 2;
  }
  RobotDescription robot;
  if (!testing::LoadSessionRobot(argv[1], argv[2], &robot)) return 1;
  const RobotModel& model = robot.model;
  const uint64_t seed = std::strtoull(argv[5], nullptr, 10);
  Eigen::VectorXd truth;
  if (!testing::SessionTruth(model, seed, &truth)) return 1;
  PointSimulationOptions options;
  if (argc > 6) options.placement_m = std::atof(argv[6]);
  if (argc > 7) options.num_points = std::atoi(argv[7]);
  if (argc > 8) options.per_point = std::atoi(argv[8]);
  const uint64_t socket_seed =
      argc > 9 ? std::strtoull(argv[9], nullptr, 10) : seed + 1;
  std::vector<Measurement> rows;
  std::vector<Eigen::Vector3d> points;
  std::string error;
  if (!SimulatePointMeasurements(model, truth, options, socket_seed, &rows,
                                 &points, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  std::ofstream(argv[3]) << MeasurementsCsvText(model, rows);
  std::ofstream yaml(argv[4]);
  yaml << "distances:\n";
  char line[256];
  for (size_t k = 1; k < points.size(); ++k) {
    std::snprintf(line, sizeof(line),
                  "  - {from: %s%zu, to: %s%zu, distance_m: %.12f}\n",
                  options.prefix.c_str(), k - 1, options.prefix.c_str(), k,
                  (points[k] - points[k - 1]).norm());
    yaml << line;
  }
  return 0;
}
