// activecal_active: the active calibration loop on a simulated robot. A
// D-optimal first batch at the nominal values, then, round by round,
// simulate, identify, and select the next task-optimal batch at the new
// estimate, until the predicted task RMS meets --target_rms_m. With
// --compare, one-shot designs of the same total size (D-optimal and
// task-optimal at nominal, random) are measured and identified too.

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "activecal/core/random.h"
#include "activecal/calibration/active_loop.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/task_criterion.h"
#include "activecal/selection/task_exchange.h"
#include "app_common.h"

DEFINE_int32(levels, 4,
             "Lattice values per joint of the pool (and of the task: the "
             "robot works over the whole lattice).");
DEFINE_double(noise_m, 1e-4, "Simulated tracker noise per axis (m).");
DEFINE_double(target_rms_m, 5e-5,
              "Stop when the predicted task RMS position error is at most "
              "this (m).");
DEFINE_int32(first_batch, 12, "Poses of the first, D-optimal batch.");
DEFINE_int32(batch_size, 6, "Poses of each later, task-optimal batch.");
DEFINE_int32(max_rounds, 30, "Rounds at most.");
DEFINE_double(nominal_error_scale, 1.0,
              "Start from truth + s (nominal - truth): 1 is the robot file's "
              "nominal, 0.1 one ten times closer to the truth, 2 farther.");
DEFINE_bool(compare, false,
            "Also measure one-shot designs of the loop's total size at the "
            "nominal values: D-optimal, task-optimal, random.");
DEFINE_int32(restarts, 4, "Restarts of each design.");
DEFINE_uint64(seed, 1, "Seed of the noise and the random choices.");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");
DEFINE_string(json_out, "", "If set, write the per-round report here.");

namespace activecal {
namespace {

nlohmann::json RoundJson(const ActiveRound& r) {
  return {{"num_poses", r.num_poses},
          {"batch", r.batch},
          {"predicted_task_rms_m", r.predicted_task_rms_m},
          {"true_task_rms_m", r.true_task_rms_m},
          {"parameter_change_task_rms_m", r.parameter_change_task_rms_m},
          {"parameter_change_max_abs", r.parameter_change_max_abs},
          {"residual_sigma_m", std::isfinite(r.residual_sigma_m)
                                   ? nlohmann::json(r.residual_sigma_m)
                                   : nlohmann::json()},
          {"residuals_exceed_noise", r.residuals_exceed_noise}};
}

int Main() {
  const RobotDescription robot = app::LoadRobotOrDie();
  if (robot.true_parameters.size() != robot.model.num_parameters()) {
    app::Fail(
        "--robot has no true values to simulate from (add 'true:' "
        "entries, docs/formats.md)");
  }
  if (!(FLAGS_nominal_error_scale >= 0) ||
      !std::isfinite(FLAGS_nominal_error_scale)) {
    app::Fail("--nominal_error_scale must be >= 0");
  }
  RobotModel model = robot.model;
  const Eigen::VectorXd truth = robot.true_parameters;
  model.nominal = truth + FLAGS_nominal_error_scale * (model.nominal - truth);
  const JointLattice lattice = app::MakeLatticeOrDie(model, FLAGS_levels);
  const Eigen::MatrixXd joints = lattice.AllJointValues();
  ActiveLoopOptions options;
  options.sigma_m = FLAGS_noise_m;
  options.target_rms_m = FLAGS_target_rms_m;
  options.first_batch = FLAGS_first_batch;
  options.batch_size = FLAGS_batch_size;
  options.max_rounds = FLAGS_max_rounds;
  options.seed = FLAGS_seed;
  options.num_threads = FLAGS_threads;
  std::string error;
  if (!options.IsValid(&error)) {
    // The options' names are the flags' but for sigma_m (--noise_m).
    if (error.rfind("sigma_m", 0) == 0) error.replace(0, 7, "noise_m");
    app::Fail("--" + error);
  }

  // Round 0: D-optimal; later rounds: task-optimal counting what is measured.
  auto d_optimal = [&](const CandidatePool& pool, int n,
                       std::vector<int64_t>* out, std::string* why) {
    FedorovOptions f;
    f.num_poses = n;
    f.restarts = FLAGS_restarts;
    f.seed = FLAGS_seed;
    f.num_threads = FLAGS_threads;
    SelectionSummary s;
    if (!FedorovExchange(pool, {}, f, nullptr, &s)) {
      *why = s.message;
      return false;
    }
    *out = s.design;
    return true;
  };
  auto task_optimal = [&](const CandidatePool& pool, const Eigen::MatrixXd& W,
                          const RowMatrixXd& prior,
                          const std::vector<int64_t>& measured, int n,
                          std::vector<int64_t>* out, std::string* why) {
    std::vector<char> taken(pool.size(), 0);
    for (int64_t i : measured) taken[i] = 1;
    DesignConstraints c;
    c.excluded = [&taken](int64_t i) { return taken[i] != 0; };
    TaskExchangeOptions t;
    t.num_poses = n;
    t.restarts = FLAGS_restarts;
    t.seed = FLAGS_seed;
    t.num_threads = FLAGS_threads;
    SelectionSummary s;
    if (!TaskExchange(pool, W, prior, c, t, nullptr, &s)) {
      *why = s.message;
      return false;
    }
    *out = s.design;
    return true;
  };
  BatchSelector select = [&](int round, const CandidatePool& pool,
                             const Eigen::MatrixXd& W, const RowMatrixXd& prior,
                             const std::vector<int64_t>& measured, int n,
                             std::vector<int64_t>* batch, std::string* why) {
    if (round == 0) return d_optimal(pool, n, batch, why);
    return task_optimal(pool, W, prior, measured, n, batch, why);
  };
  ActiveLoopSummary summary;
  const bool ok =
      RunActiveLoop(model, truth, joints, joints, options, select, &summary);
  if (!ok && summary.rounds.empty()) app::Fail(summary.message);
  std::printf("activecal active loop: %s\n  %s\n",
              TerminationTypeToString(summary.termination_type),
              summary.message.c_str());
  std::printf(
      "  nominal model: true task RMS %.6g m (--nominal_error_scale "
      "%g)\n",
      summary.nominal_true_task_rms_m, FLAGS_nominal_error_scale);
  std::printf("  %-6s %-6s %-14s %-14s %-14s %-14s %s\n", "round", "poses",
              "predicted_m", "true_m", "change_m", "change_max",
              "resid_sigma_m");
  for (size_t r = 0; r < summary.rounds.size(); ++r) {
    const ActiveRound& a = summary.rounds[r];
    std::printf("  %-6zu %-6d %-14.6g %-14.6g %-14.6g %-14.6g %.6g%s\n", r,
                a.num_poses, a.predicted_task_rms_m, a.true_task_rms_m,
                a.parameter_change_task_rms_m, a.parameter_change_max_abs,
                a.residual_sigma_m,
                a.residuals_exceed_noise ? "  (above the noise)" : "");
  }
  for (size_t r = 0; r < summary.rounds.size(); ++r) {
    if (!summary.rounds[r].residuals_exceed_noise) continue;
    std::fprintf(stderr,
                 "warning: round %zu: the residual sigma %.3g m is %.1f "
                 "times --noise_m: the identified model does not fit the "
                 "measurements (a wrong local minimum?); its predicted task "
                 "RMS does not hold\n",
                 r, summary.rounds[r].residual_sigma_m,
                 summary.rounds[r].residual_sigma_m / FLAGS_noise_m);
  }
  nlohmann::json j;
  j["termination_type"] = TerminationTypeToString(summary.termination_type);
  j["message"] = summary.message;
  j["robot"] = model.name;
  j["levels"] = FLAGS_levels;
  j["noise_m"] = FLAGS_noise_m;
  j["target_rms_m"] = FLAGS_target_rms_m;
  j["seed"] = FLAGS_seed;
  j["nominal_error_scale"] = FLAGS_nominal_error_scale;
  j["nominal_true_task_rms_m"] = summary.nominal_true_task_rms_m;
  j["rounds"] = nlohmann::json::array();
  for (const ActiveRound& a : summary.rounds)
    j["rounds"].push_back(RoundJson(a));
  j["measured_pose_indices"] = summary.measured;

  if (FLAGS_compare && !summary.measured.empty()) {
    const int n = static_cast<int>(summary.measured.size());
    CandidatePoolOptions pool_options;
    pool_options.num_threads = FLAGS_threads;
    RobotModel pool_model = model;
    CandidatePool pool;
    CandidatePoolSummary pool_summary;
    if (!BuildCandidatePool(&pool_model, model.nominal, joints, pool_options,
                            &pool, &pool_summary)) {
      app::Fail("pool at nominal: " + pool_summary.message);
    }
    const Eigen::MatrixXd W = TaskMatrix(pool);
    std::vector<std::pair<std::string, std::vector<int64_t>>> designs(3);
    designs[0].first = "d_optimal_at_nominal";
    designs[1].first = "task_optimal_at_nominal";
    designs[2].first = "random";
    if (!d_optimal(pool, n, &designs[0].second, &error) ||
        !task_optimal(pool, W, RowMatrixXd(0, pool.num_parameters()), {}, n,
                      &designs[1].second, &error)) {
      app::Fail("one-shot design: " + error);
    }
    Random random(Random::StreamSeed(FLAGS_seed, 1000));
    designs[2].second = random.SampleWithoutReplacement(pool.size(), n);
    std::printf("  one-shot designs of %d poses at the nominal values:\n", n);
    std::printf("  %-26s %-14s %s\n", "design", "predicted_m", "true_m");
    j["one_shot"] = nlohmann::json::object();
    for (const auto& [name, design] : designs) {
      ActiveRound r;
      if (!EvaluateOneShot(model, truth, joints, joints, design, options, &r,
                           &error)) {
        std::printf("  %-26s failed: %s\n", name.c_str(), error.c_str());
        j["one_shot"][name] = {{"error", error}};
        continue;
      }
      std::printf("  %-26s %-14.6g %.6g\n", name.c_str(),
                  r.predicted_task_rms_m, r.true_task_rms_m);
      j["one_shot"][name] = RoundJson(r);
    }
  }
  if (!FLAGS_json_out.empty()) app::WriteJsonOrDie(FLAGS_json_out, j);
  if (!ok) app::Fail(summary.message);
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "The active calibration loop on a simulated robot (--robot with "
      "'true:' values; default the Sun & Hollerbach PUMA 560): a D-optimal "
      "first batch, then task-optimal batches designed at each new "
      "estimate, until the predicted task RMS meets --target_rms_m.\n"
      "  activecal_active --target_rms_m=5e-5 --compare --json_out=loop.json");
  return activecal::Main();
}
