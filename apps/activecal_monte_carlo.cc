// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_monte_carlo: checks the identification's statistics. Measures
// one design again and again with fresh simulated noise, identifies each
// time, and compares the scatter of the estimates with the predicted
// covariance sigma^2 (J^T J)^-1 (per-parameter std ratio, determinant
// ratio, bias).

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>

#include "activecal/core/random.h"
#include "activecal/estimation/monte_carlo.h"
#include "activecal/io/csv_files.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "app_common.h"

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

Eigen::MatrixXd DesignJoints(const RobotModel& model) {
  if (!FLAGS_poses_csv.empty()) {
    PoseList poses;
    std::string error;
    if (!ReadPosesCsv(FLAGS_poses_csv, model, false, &poses, &error)) {
      app::Fail("--poses_csv: " + error);
    }
    return poses.joints;
  }
  const JointLattice lattice = app::MakeLatticeOrDie(model, 5);
  const Eigen::MatrixXd joints = lattice.AllJointValues();
  CandidatePoolOptions pool_options;
  pool_options.num_threads = FLAGS_threads;
  const CandidatePool pool = app::BuildPoolOrDie(model, joints, pool_options,
                                                 "the pool", nullptr, nullptr);
  ExchangeAddExchangeOptions options;
  options.seed = Random::StreamSeed(FLAGS_seed, 2);
  options.num_threads = FLAGS_threads;
  SelectionSummary design;
  if (!ExchangeAddExchange(pool, {}, options, &design)) {
    app::Fail(design.message);
  }
  Eigen::MatrixXd out(design.design.size(), model.num_joints());
  for (size_t i = 0; i < design.design.size(); ++i) {
    out.row(i) = joints.row(design.design[i]);
  }
  return out;
}

int Main() {
  const RobotDescription robot = app::LoadRobotOrDie();
  const RobotModel& model = robot.model;
  if (robot.true_parameters.size() != model.num_parameters()) {
    app::Fail(
        "--robot has no true values to simulate from (add 'true:' "
        "entries, docs/formats.md)");
  }
  const Eigen::MatrixXd joints = DesignJoints(model);
  std::vector<Measurement> plan(joints.rows());
  for (int i = 0; i < joints.rows(); ++i) {
    plan[i].joints = joints.row(i).transpose();
  }
  MonteCarloOptions options;
  options.num_trials = FLAGS_trials;
  options.noise.position_m = FLAGS_noise_m;
  options.seed = Random::StreamSeed(FLAGS_seed, 5);
  options.num_threads = FLAGS_threads;
  app::ProgressLine line("identifications");
  options.progress = line.callback();
  MonteCarloSummary s;
  RunMonteCarlo(model, robot.true_parameters, plan, options, &s);
  if (s.termination_type != TerminationType::kConvergence) {
    app::Fail(s.message);
  }
  std::printf("%-10s %14s %14s %10s %12s %12s\n", "parameter", "predicted std",
              "empirical std", "ratio", "bias/std", "reported");
  nlohmann::json params = nlohmann::json::array();
  for (size_t k = 0; k < s.names.size(); ++k) {
    const double pred = std::sqrt(s.predicted_covariance(k, k));
    const double emp = std::sqrt(s.empirical_covariance(k, k));
    std::printf("%-10s %14.6g %14.6g %10.3f %12.3f %12.3f\n",
                s.names[k].c_str(), pred, emp, s.std_ratio[k],
                s.mean_error[k] / pred, s.reported_std_ratio[k]);
    params.push_back({{"name", s.names[k]},
                      {"predicted_std", pred},
                      {"empirical_std", emp},
                      {"std_ratio", s.std_ratio[k]},
                      {"mean_error", s.mean_error[k]},
                      {"reported_std_ratio", s.reported_std_ratio[k]}});
  }
  std::printf("\n%d poses, %.3g m noise\n%s", static_cast<int>(plan.size()),
              FLAGS_noise_m, s.BriefReport().c_str());
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j;
    j["robot"] = model.name;
    j["num_poses"] = plan.size();
    j["noise_m"] = FLAGS_noise_m;
    j["trials"] = s.num_trials;
    j["failed"] = s.num_failed;
    j["seed"] = FLAGS_seed;
    j["parameters"] = params;
    j["std_ratio_sampling_sd"] = s.std_ratio_sd;
    j["log_det_ratio"] = s.log_det_ratio;
    j["expected_log_det_ratio"] = s.expected_log_det_ratio;
    j["log_det_ratio_sd"] = s.log_det_ratio_sd;
    j["fraction_within_2_std"] = s.fraction_within_2_std;
    j["timing"] = {{"seconds", s.seconds}};
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
  {
    // The one-line result (what --quiet prints): the JSON's trials, failed,
    // log_det_ratio, expected_log_det_ratio and fraction_within_2_std.
    char result[256];
    std::snprintf(result, sizeof(result),
                  "%s: %d trials (%d failed), log det ratio %.4f (expected "
                  "%.4f), %.1f%% within 2 std",
                  app::ProgramName().c_str(), s.num_trials, s.num_failed,
                  s.log_det_ratio, s.expected_log_det_ratio,
                  100.0 * s.fraction_within_2_std);
    app::PrintResult(result);
  }
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Repeats the identification over many noise realisations on a fixed "
      "design and compares the empirical covariance of the estimates with "
      "the predicted sigma^2 (J^T J)^-1.\n  activecal_monte_carlo "
      "--trials=1000 --noise_m=0.01 --json_out=monte_carlo.json");
  return activecal::app::Finish(activecal::Main());
}
