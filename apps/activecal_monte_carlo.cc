// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_monte_carlo: checks the identification's statistics. Measures
// one design again and again with fresh simulated noise, identifies each
// time, and compares the scatter of the estimates with the predicted
// covariance sigma^2 (J^T J)^-1 (per-parameter std ratio, determinant
// ratio, bias).

#include <gflags/gflags.h>

#include <cstdio>
#include <memory>

#include "activecal/calibration/monte_carlo_study.h"
#include "app_common.h"

constexpr char kUsage[] =
    "Repeats the identification over many noise realisations on a fixed "
    "design and compares the empirical covariance of the estimates with "
    "the predicted sigma^2 (J^T J)^-1.\n  activecal_monte_carlo "
    "--trials=1000 --noise_m=0.01 --json_out=monte_carlo.json";

DEFINE_string(poses_csv, "",
              "The design: a poses CSV (e.g. from activecal_select). Empty: "
              "the exchange-add-exchange design of the 5-level lattice "
              "(the paper's Section V-D, --seed).");
DEFINE_int32(trials, 1000, "Noise realisations (identifications).");
DEFINE_double(noise_m, 0.01,
              "Noise standard deviation on each axis (m); the paper's 1 cm.");
DEFINE_uint64(seed, 1, "Seed of the design (when selected) and the noise.");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");
DEFINE_string(json_out, "",
              "If set, write per-parameter predicted and empirical std, "
              "their ratio and the bias, and the determinant ratio here.");

namespace activecal {
namespace {

int Main() {
  const RobotDescription robot = app::LoadRobotOrDie();
  MonteCarloStudyOptions options;
  app::NameProgramAndShowStages(&options);
  options.poses_csv = FLAGS_poses_csv;
  options.num_trials = FLAGS_trials;
  options.noise_m = FLAGS_noise_m;
  options.seed = FLAGS_seed;
  options.num_threads = FLAGS_threads;
  MonteCarloStudySummary summary;
  const bool ok =
      RunMonteCarloStudy(robot.model, robot.true_parameters, options, &summary);
  std::printf("%s", summary.report.c_str());
  if (!ok) app::Fail(summary.message);
  if (!FLAGS_json_out.empty())
    app::WriteJsonOrDie(FLAGS_json_out, summary.json);
  // The one-line result (what --quiet prints).
  app::PrintResult(summary.result_line);
  return 0;
}

}  // namespace
}  // namespace activecal

ACTIVECAL_APP_MAIN(kUsage, activecal::Main)
