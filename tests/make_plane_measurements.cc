// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Test helper: a simulated touch-probe session (plane_constraints.h) as a
// measurements CSV of type=plane rows, for the CLI tests of calibration
// without a tracker.
//
//   make_plane_measurements URDF TIP OUT.csv SEED RADIUS_M NUM_PLANES
//       PER_PLANE [PLACEMENT_SEED] [NOISE_M]
//
// The truth: the URDF's nominal with a ball 0.02, -0.01, 0.1 m off the tip
// and every free parameter moved by 0.5 mm / 0.5 mrad (PerturbParameters,
// SEED). The planes: up to 3 orthogonal ones (a table, normal +z, then two
// walls, normals -x and +y) through a corner at 0.45, -0.35, 0.25 m, moved
// by up to 5 cm per axis by PLACEMENT_SEED (default SEED + 1: another
// PLACEMENT_SEED is another placement of the fixture). NOISE_M: each touch
// off its plane by a Gaussian of this std (m) along the normal.

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/plane_constraints.h"
#include "activecal/core/point_constraints.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/urdf_robot.h"
#include "simulated_session.h"

int main(int argc, char** argv) {
  using namespace activecal;
  if (argc < 8) {
    std::fprintf(stderr,
                 "usage: %s URDF TIP OUT.csv SEED RADIUS_M NUM_PLANES "
                 "PER_PLANE [PLACEMENT_SEED] [NOISE_M]\n",
                 argv[0]);
    return 2;
  }
  RobotDescription robot;
  if (!testing::LoadSessionRobot(argv[1], argv[2], &robot)) return 1;
  const RobotModel& model = robot.model;
  const uint64_t seed = std::strtoull(argv[4], nullptr, 10);
  const double radius = std::atof(argv[5]);
  const int num_planes = std::atoi(argv[6]);
  const int per_plane = std::atoi(argv[7]);
  const uint64_t placement =
      argc > 8 ? std::strtoull(argv[8], nullptr, 10) : seed + 1;
  const double noise = argc > 9 ? std::atof(argv[9]) : 0.0;
  if (num_planes < 1 || num_planes > 3) {
    std::fprintf(stderr, "NUM_PLANES: 1, 2 or 3\n");
    return 2;
  }
  Eigen::VectorXd truth;
  if (!testing::SessionTruth(model, seed, &truth)) return 1;
  Random random(placement);
  Eigen::Vector3d corner(0.45, -0.35, 0.25);
  for (int a = 0; a < 3; ++a) corner[a] += 0.1 * (random.Uniform() - 0.5);
  const Eigen::Vector3d normals[3] = {{0, 0, 1}, {-1, 0, 0}, {0, 1, 0}};
  std::vector<Measurement> rows;
  for (int k = 0; k < num_planes; ++k) {
    Eigen::Vector4d plane;
    plane << normals[k], normals[k].dot(corner);
    std::vector<Measurement> touches =
        SimulatePlaneTouches(model, truth, "plane_" + std::to_string(k), plane,
                             radius, per_plane, placement * 10 + k);
    if (static_cast<int>(touches.size()) < per_plane) {
      std::fprintf(stderr, "plane %d: %zu touches found of %d\n", k,
                   touches.size(), per_plane);
      return 1;
    }
    for (Measurement& m : touches) {
      if (noise > 0) {
        const Eigen::Vector3d c = MeasuredPoint(model, truth, m.joints);
        ReachPoint(model, truth, 0, c + noise * random.Gaussian() * normals[k],
                   &m.joints);
      }
      rows.push_back(m);
    }
  }
  std::ofstream(argv[3]) << MeasurementsCsvText(model, rows);
  return 0;
}
