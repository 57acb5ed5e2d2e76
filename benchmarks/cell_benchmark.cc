// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Speed of the cell's preprocess (cell/pool_filter.h): poses per second
// filtered on 1 and 2 threads, and what a feasible pose costs by rejection
// sampling of a Sobol pool against the measurable pool (inverse
// kinematics, cell/measurable_pool.h).
//
//   build/benchmarks/activecal_cell_benchmark [--pool_size=200000]
//       [--measurable_poses=5000] [--repeats=3]
//       [--robot=data/ur10e.urdf --tip_link=tool0
//        --cell=data/cells/ur10e_table.yaml]
//
// Prints a Markdown table: per thread count the best of `repeats` filter
// runs (seconds, poses/s), how many poses reached the collision checks,
// and the feasible count; then draws, seconds and inverse kinematics
// solves per feasible pose for both ways of getting feasible poses. Checks
// that 1 and 2 threads give the same verdicts.

#include <gflags/gflags.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "activecal/cell/cell_setup.h"
#include "activecal/cell/measurable_pool.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/core/joint_sampling.h"
#include "activecal/io/robot_loader.h"

DEFINE_int64(pool_size, 200000, "Sobol poses filtered.");
DEFINE_int64(measurable_poses, 5000, "Feasible poses of the measurable pool.");
DEFINE_int32(ik_iterations, 40, "Measurable pool: iterations per IK solve.");
DEFINE_int32(seeds_per_target, 4, "Measurable pool: IK starts per target.");
DEFINE_int32(repeats, 3, "Filter runs per thread count; the fastest counts.");
DEFINE_string(robot, ACTIVECAL_DATA_DIR "/ur10e.urdf", "The robot (URDF).");
DEFINE_string(tip_link, "tool0", "The chain's tip link.");
DEFINE_string(cell, ACTIVECAL_DATA_DIR "/cells/ur10e_table.yaml",
              "The cell file.");

namespace activecal {
namespace {

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

int Main() {
  RobotLoadOptions load;
  load.chain.tip_link = FLAGS_tip_link;
  RobotDescription robot;
  std::string error;
  if (!LoadRobot(FLAGS_robot, load, &robot, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  CellSetupOptions options;
  options.cell_path = FLAGS_cell;
  options.robot_path = FLAGS_robot;
  options.chain = load.chain;
  CellSetup cell;
  if (!SetUpCell(options, &robot, &cell, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  const CellChecker& checker = *cell.checker;
  Eigen::MatrixXd joints;
  auto start = std::chrono::steady_clock::now();
  if (!SampleJointValues(robot.model, JointSampling::kSobol, FLAGS_pool_size, 1,
                         &joints, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  const double sobol_seconds = Since(start);
  std::printf("%s, %s: %d shapes, %d self pairs, %zu obstacles\n\n",
              robot.model.name.c_str(), FLAGS_cell.c_str(),
              cell.collision.num_shapes(), checker.num_self_pairs(),
              cell.cell.obstacles.size());
  std::printf(
      "| threads | poses | seconds | poses/s | reached collision checks | "
      "feasible |\n| --- | --- | --- | --- | --- | --- |\n");
  PoolFilterSummary reference;
  double filter_seconds = 0;
  for (int threads : {1, 2}) {
    double best = 1e30;
    PoolFilterSummary s;
    for (int r = 0; r < FLAGS_repeats; ++r) {
      PoolFilterOptions o;
      o.num_threads = threads;
      FilterPool(checker, joints, o, &s);
      best = std::min(best, s.seconds);
    }
    // Poses that passed the margins and the target checks.
    int64_t reached = 0;
    for (const PoseVerdict& v : s.verdicts) {
      reached += v.reason == RejectionReason::kNone ||
                 v.reason == RejectionReason::kSelfCollision ||
                 v.reason == RejectionReason::kObstacle ||
                 v.reason == RejectionReason::kLineOfSight;
    }
    std::printf("| %d | %lld | %.3f | %.0f | %lld | %lld |\n", threads,
                static_cast<long long>(joints.rows()), best,
                joints.rows() / best, static_cast<long long>(reached),
                static_cast<long long>(s.num_feasible()));
    if (threads == 1) {
      reference = s;
    } else {
      filter_seconds = best;
      bool same = reference.feasible == s.feasible;
      for (size_t i = 0; same && i < s.verdicts.size(); ++i) {
        same = s.verdicts[i].reason == reference.verdicts[i].reason;
      }
      if (!same) {
        std::printf("ERROR: 1 and 2 threads disagree\n");
        return 1;
      }
    }
  }
  std::printf("\n%s", reference.BriefReport(checker).c_str());

  MeasurablePoolOptions mo;
  mo.num_poses = FLAGS_measurable_poses;
  mo.num_threads = 2;
  mo.ik_iterations = FLAGS_ik_iterations;
  mo.seeds_per_target = FLAGS_seeds_per_target;
  MeasurablePoolSummary measurable;
  if (!SampleMeasurablePool(checker, mo, &measurable)) {
    std::fprintf(stderr, "%s\n", measurable.message.c_str());
    return 1;
  }
  const double feasible = static_cast<double>(reference.num_feasible());
  std::printf(
      "\n| feasible poses by | poses | draws per feasible pose | IK solves "
      "per pose | ms per feasible pose (2 threads) |\n"
      "| --- | --- | --- | --- | --- |\n");
  std::printf("| rejection (Sobol, filtered) | %.0f | %.1f | - | %.3f |\n",
              feasible, joints.rows() / feasible,
              1e3 * (filter_seconds + sobol_seconds) / feasible);
  std::printf("| measurable pool (IK) | %lld | %.2f | %.2f | %.3f |\n",
              static_cast<long long>(measurable.joints.rows()),
              measurable.DrawsPerPose(), measurable.SolvesPerPose(),
              1e3 * measurable.seconds / measurable.joints.rows());
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  return activecal::Main();
}
