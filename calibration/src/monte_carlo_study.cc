// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/monte_carlo_study.h"

#include <cmath>
#include <vector>

#include "activecal/calibration/paper_example.h"
#include "activecal/core/random.h"
#include "activecal/io/csv_files.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "printf_text.h"
#include "workflow_fail.h"

namespace activecal {
namespace {

using internal::Printf;

using internal::Fail;

ProgressCallback Stage(const StageProgress& progress, const char* stage) {
  return progress ? progress(stage) : ProgressCallback();
}

// The design's joints: the poses CSV's, or the exchange-add-exchange design
// of the paper's pool. False with *error; the lattice's notes in *report.
bool DesignJoints(const RobotModel& model,
                  const MonteCarloStudyOptions& options,
                  Eigen::MatrixXd* joints, std::string* report,
                  std::string* error) {
  if (!options.poses_csv.empty()) {
    PoseList poses;
    if (!ReadPosesCsv(options.poses_csv, model, false, &poses, error)) {
      *error = "--poses_csv: " + *error;
      return false;
    }
    *joints = poses.joints;
    return true;
  }
  PaperPool paper;
  bool ok;
  {
    const ProgressCallback progress =
        Stage(options.progress, "Jacobians of the pool poses");
    ok = MakePaperPool(model, options.num_threads, progress, &paper, error);
  }
  *report += paper.notes;
  if (!ok) return false;
  ExchangeAddExchangeOptions eae;
  eae.seed = Random::StreamSeed(options.seed, 2);
  eae.num_threads = options.num_threads;
  SelectionSummary design;
  if (!ExchangeAddExchange(paper.pool, {}, eae, &design)) {
    *error = design.message;
    return false;
  }
  joints->resize(design.design.size(), model.num_joints());
  for (size_t i = 0; i < design.design.size(); ++i) {
    joints->row(i) = paper.joints.row(design.design[i]);
  }
  return true;
}

}  // namespace

bool RunMonteCarloStudy(const RobotModel& model,
                        const Eigen::VectorXd& true_parameters,
                        const MonteCarloStudyOptions& options,
                        MonteCarloStudySummary* summary) {
  *summary = MonteCarloStudySummary();
  if (true_parameters.size() != model.num_parameters()) {
    return Fail(
        "--robot has no true values to simulate from (add 'true:' "
        "entries, docs/formats.md)",
        summary);
  }
  Eigen::MatrixXd joints;
  std::string error;
  if (!DesignJoints(model, options, &joints, &summary->report, &error)) {
    return Fail(error, summary);
  }
  std::vector<Measurement> plan(joints.rows());
  for (int i = 0; i < joints.rows(); ++i) {
    plan[i].joints = joints.row(i).transpose();
  }
  summary->num_poses = static_cast<int>(plan.size());
  MonteCarloOptions mc;
  mc.num_trials = options.num_trials;
  mc.noise.position_m = options.noise_m;
  mc.seed = Random::StreamSeed(options.seed, 5);
  mc.num_threads = options.num_threads;
  MonteCarloSummary& s = summary->monte_carlo;
  {
    mc.progress = Stage(options.progress, "identifications");
    RunMonteCarlo(model, true_parameters, plan, mc, &s);
    mc.progress = nullptr;
  }
  if (s.termination_type != TerminationType::kConvergence) {
    return Fail(s.message, summary);
  }
  std::string& r = summary->report;
  r += Printf("%-10s %14s %14s %10s %12s %12s\n", "parameter", "predicted std",
              "empirical std", "ratio", "bias/std", "reported");
  nlohmann::json params = nlohmann::json::array();
  for (size_t k = 0; k < s.names.size(); ++k) {
    const double pred = std::sqrt(s.predicted_covariance(k, k));
    const double emp = std::sqrt(s.empirical_covariance(k, k));
    r += Printf("%-10s %14.6g %14.6g %10.3f %12.3f %12.3f\n",
                s.names[k].c_str(), pred, emp, s.std_ratio[k],
                s.mean_error[k] / pred, s.reported_std_ratio[k]);
    params.push_back({{"name", s.names[k]},
                      {"predicted_std", pred},
                      {"empirical_std", emp},
                      {"std_ratio", s.std_ratio[k]},
                      {"mean_error", s.mean_error[k]},
                      {"reported_std_ratio", s.reported_std_ratio[k]}});
  }
  r += Printf("\n%d poses, %.3g m noise\n", static_cast<int>(plan.size()),
              options.noise_m) +
       s.BriefReport();
  nlohmann::json& j = summary->json;
  j["robot"] = model.name;
  j["num_poses"] = plan.size();
  j["noise_m"] = options.noise_m;
  j["trials"] = s.num_trials;
  j["failed"] = s.num_failed;
  j["seed"] = options.seed;
  j["parameters"] = params;
  j["std_ratio_sampling_sd"] = s.std_ratio_sd;
  j["log_det_ratio"] = s.log_det_ratio;
  j["expected_log_det_ratio"] = s.expected_log_det_ratio;
  j["log_det_ratio_sd"] = s.log_det_ratio_sd;
  j["fraction_within_2_std"] = s.fraction_within_2_std;
  j["timing"] = {{"seconds", s.seconds}};
  // The one-line result: the JSON's trials, failed, log_det_ratio,
  // expected_log_det_ratio and fraction_within_2_std (a line of at most 255
  // bytes, as the program's).
  char result[256];
  std::snprintf(result, sizeof(result),
                "%s: %d trials (%d failed), log det ratio %.4f (expected "
                "%.4f), %.1f%% within 2 std",
                options.program_name.c_str(), s.num_trials, s.num_failed,
                s.log_det_ratio, s.expected_log_det_ratio,
                100.0 * s.fraction_within_2_std);
  summary->result_line = result;
  summary->termination_type = TerminationType::kConvergence;
  return true;
}

}  // namespace activecal
