// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Speed of program compensation (compensation.h): targets per second for
// 6-axis arms on 1 and 2 threads, and the iterations each target needs.
//
//   build/benchmarks/activecal_compensate_benchmark [--targets=10000]
//       [--repeats=5] [--ur10e=data/ur10e.urdf]
//
// Cases:
//   ur10e position / pose   data/ur10e.urdf (6 URDF joints, tool0) against a
//                           calibrated model with realistic errors (joint
//                           offsets ~1 mrad, origins ~1 mm), the usual case
//   puma560 position        the paper's PUMA: true values (Table I) as the
//                           calibrated model, Table II as the nominal one,
//                           errors of hundreds of mm (a worst case)
// Prints one Markdown table row per case and thread count: the best of
// `repeats` runs (targets/s), mean iterations, converged count; and checks
// that 1 and 2 threads give bit-identical joints.

#include <gflags/gflags.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/io/robot_loader.h"
#include "activecal/kinematics/compensation.h"

DEFINE_int32(targets, 10000, "Targets per program.");
DEFINE_int32(repeats, 5, "Runs per case; the fastest is reported.");
DEFINE_string(ur10e, ACTIVECAL_DATA_DIR "/ur10e.urdf", "The UR10e URDF.");

namespace activecal {
namespace {

Eigen::MatrixXd RandomProgram(const RobotModel& model, int n, uint64_t seed,
                              double margin) {
  Random random(seed);
  Eigen::MatrixXd program(n, model.num_joints());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j) {
      const Link& l = model.links[j];
      const double lo = std::isfinite(l.joint_min) ? l.joint_min : -M_PI;
      const double hi = std::isfinite(l.joint_max) ? l.joint_max : M_PI;
      program(i, j) = lo + margin + (hi - lo - 2 * margin) * random.Uniform();
    }
  }
  return program;
}

int Run(const std::string& name, const RobotModel& model,
        const Eigen::VectorXd& calibrated, const Eigen::VectorXd& nominal,
        IkMatch match) {
  const Eigen::MatrixXd program = RandomProgram(model, FLAGS_targets, 1, 0.1);
  CompensationSummary reference;
  int failures = 0;
  for (int threads : {1, 2}) {
    CompensationOptions options;
    options.ik.match = match;
    options.num_threads = threads;
    double best = 1e300;
    CompensationSummary summary;
    for (int r = 0; r < FLAGS_repeats; ++r) {
      CompensateProgram(model, calibrated, model, nominal, program, options,
                        &summary);
      best = std::min(best, summary.seconds);
    }
    int64_t iterations = 0;
    for (const InverseKinematicsResult& result : summary.results) {
      iterations += result.iterations;
    }
    std::printf("| %s | %s | %d | %d | %.0f | %.2f | %.1f | %d |\n",
                name.c_str(), IkMatchName(match), FLAGS_targets, threads,
                FLAGS_targets / best, 1e6 * best / FLAGS_targets,
                static_cast<double>(iterations) / FLAGS_targets,
                summary.num_converged);
    if (threads == 1) {
      reference = summary;
    } else {
      for (size_t i = 0; i < summary.results.size(); ++i) {
        if (!(summary.results[i].joints == reference.results[i].joints)) {
          ++failures;
        }
      }
    }
  }
  if (failures) {
    std::printf("ERROR: %s: %d targets differ between 1 and 2 threads\n",
                name.c_str(), failures);
  }
  return failures;
}

int Main() {
  std::printf(
      "| robot | match | targets | threads | targets/s | us/target | "
      "iterations/target | converged |\n| --- | --- | --- | --- | --- | --- "
      "| --- | --- |\n");
  int failures = 0;
  RobotLoadOptions load;
  load.chain.tip_link = "tool0";
  RobotDescription ur;
  std::string error;
  if (!LoadRobot(FLAGS_ur10e, load, &ur, &error)) {
    std::fprintf(stderr, "compensate_benchmark: error: %s\n", error.c_str());
    return 1;
  }
  // A calibrated UR10e: every joint origin off by ~1 mm and ~1 mrad, every
  // offset by ~1 mrad; a tool 0.1 m out with an orientation.
  RobotModel& model = ur.model;
  Eigen::VectorXd nominal = model.nominal;
  const int tool = model.block_offset(model.marker_block(0));
  nominal.segment(tool, 6) << 0.01, 0.02, 0.1, 0.2, -0.1, 0.3;
  Eigen::VectorXd calibrated = nominal;
  Random random(3);
  for (int j = 0; j < model.num_joints(); ++j) {
    double* p = calibrated.data() + model.block_offset(j + 1);
    for (int k = 0; k < 3; ++k) p[k] += 1e-3 * random.Gaussian();
    for (int k = 3; k < 7; ++k) p[k] += 1e-3 * random.Gaussian();
  }
  failures += Run("ur10e", model, calibrated, nominal, IkMatch::kPosition);
  failures += Run("ur10e", model, calibrated, nominal, IkMatch::kPose);
  const RobotModel puma = Puma560PaperModel();
  failures += Run("puma560 (Table I vs II)", puma, Puma560TrueParameters(),
                  puma.nominal, IkMatch::kPosition);
  return failures ? 1 : 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "Targets per second of CompensateProgram on 1 and 2 threads.");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  return activecal::Main();
}
