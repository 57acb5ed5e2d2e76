// activecal_select: choose calibration poses for a robot (the paper's PUMA
// 560 by default) from a joint lattice or a pool read from CSV, by a
// D-optimal design algorithm.

#include <gflags/gflags.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "activecal/core/csv_files.h"
#include "activecal/core/lattice.h"
#include "activecal/core/robot_loader.h"
#include "activecal/residuals/parameter_reduction.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/random_designs.h"
#include "app_common.h"

DEFINE_int32(levels, 5,
             "Lattice values per joint, both range ends included (>= 2). "
             "The pool has levels^(number of joints) poses.");
DEFINE_string(pool_csv, "",
              "Read the candidate poses from this poses CSV "
              "(docs/formats.md) instead of the lattice; duplicates are an "
              "error. pose_index labels the poses in the output.");
DEFINE_string(poses_csv, "",
              "If set, write the selected poses here (pose_index, joints in "
              "rad and deg) to run on the robot.");
DEFINE_string(measurement, "position",
              "What the device measures at each pose: position (3D point) "
              "or pose (6D: point and orientation).");
DEFINE_double(rotation_weight, 1.0,
              "pose: weight of the orientation rows, m per rad (set it to "
              "sigma_position / sigma_rotation of the device).");
DEFINE_bool(auto_fix, false,
            "If the pool cannot identify some free parameters, hold them "
            "at their nominal values (named on stderr) instead of failing.");
DEFINE_string(algorithm, "eae",
              "eae: the paper's exchange-add-exchange; random: best of "
              "--random_designs random designs; fedorov: Fedorov exchange "
              "(best swap over all pairs), restart 0 from the rounded "
              "approximate design; detmax: Mitchell's excursions; greedy: "
              "sequential best additions; approx: the approximate "
              "(continuous-weight) D-optimal design, rounded to its "
              "--num_poses heaviest poses.");
DEFINE_string(criterion, "det",
              "For eae: det scores candidates by the determinant update "
              "formulas (fast); svd by the eigenvalue OI of the stacked "
              "design matrix (slow; same poses).");
DEFINE_int32(num_poses, 30, "Poses in the design.");
DEFINE_int32(initial_poses, 12, "eae: random poses in the initial design.");
DEFINE_int32(random_designs, 5000, "random: number of designs drawn.");
DEFINE_int32(restarts, 0,
             "eae, fedorov, detmax: independent restarts, run in parallel; "
             "the best is kept. 0: the algorithm's default (eae 1, fedorov "
             "16, or 8 for pools of more than 200,000 poses, detmax 4).");
DEFINE_bool(certificate, true,
            "Solve the approximate design and report a certified lower "
            "bound on the design's D-efficiency (efficiency_lower_bound) "
            "and the upper bound on log10 det it rests on.");
DEFINE_double(approx_tolerance, 2e-3,
              "Approximate design: stop when max_i d_i <= p (1 + tol). The "
              "bounds hold for any value; smaller is tighter and slower.");
DEFINE_int64(polish_pool_size, 20000,
             "fedorov: a pool larger than this is polished in rounds over "
             "this many poses of largest variance rather than over every "
             "pose (<= 0: always every pose).");
DEFINE_uint64(seed, 1, "Seed of every random choice.");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");
DEFINE_string(json_out, "", "If set, write the selected design here.");

namespace activecal {
namespace {

int Main() {
  const int64_t start = app::NowNs();
  const RobotDescription robot = app::LoadRobotOrDie();
  RobotModel model = robot.model;
  MeasurementType type;
  if (!ParseMeasurementType(FLAGS_measurement, &type) ||
      type == MeasurementType::kDistance) {
    app::Fail("--measurement must be position or pose, got '" +
              FLAGS_measurement + "'");
  }
  Eigen::MatrixXd pool_joints;
  std::vector<int64_t> labels;
  JointLattice lattice;
  const bool from_lattice = FLAGS_pool_csv.empty();
  if (from_lattice) {
    lattice = app::MakeLatticeOrDie(model, FLAGS_levels);
    pool_joints = lattice.AllJointValues();
  } else {
    PoseList list;
    std::string error;
    if (!ReadPosesCsv(FLAGS_pool_csv, model, /*reject_duplicates=*/true, &list,
                      &error)) {
      app::Fail("--pool_csv: " + error);
    }
    pool_joints = std::move(list.joints);
    labels = std::move(list.pose_indices);
  }
  if (FLAGS_num_poses <= 0 || FLAGS_num_poses > pool_joints.rows()) {
    app::Fail("--num_poses must be in [1, " +
              std::to_string(pool_joints.rows()) + "] (the pool size), got " +
              std::to_string(FLAGS_num_poses));
  }
  // The parameters the design is for: a named set is reduced to what the
  // pool separates (analysed on at most 2,000 of its poses, evenly spaced),
  // and the pool is linearised at the generic point of that analysis.
  std::vector<std::string> auto_fixed;
  {
    const ParameterSet set = app::ParameterSetOrDie(IsUrdfPath(FLAGS_robot));
    const int64_t step = std::max<int64_t>(1, pool_joints.rows() / 2000);
    Eigen::MatrixXd sample((pool_joints.rows() + step - 1) / step,
                           pool_joints.cols());
    for (int64_t i = 0; i < sample.rows(); ++i) {
      sample.row(i) = pool_joints.row(i * step);
    }
    Eigen::VectorXd point = model.nominal;
    std::vector<DroppedParameter> dropped;
    std::string error;
    if (!ApplyAndReduceParameterSet(set, MeasurementPlan(sample, type),
                                    FLAGS_rotation_weight, &model, &point,
                                    &dropped, &error)) {
      app::Fail("--parameter_set=" + std::string(ParameterSetName(set)) + ": " +
                error);
    }
    model.nominal = point;
    for (const DroppedParameter& d : dropped) {
      auto_fixed.push_back(d.name);
      std::printf("  --parameter_set=%s: %s held fixed: %s\n",
                  ParameterSetName(set), d.name.c_str(), d.reason.c_str());
    }
  }
  double jacobian_seconds = 0;
  CandidatePoolOptions pool_options;
  pool_options.type = type;
  pool_options.rotation_weight_m_per_rad = FLAGS_rotation_weight;
  pool_options.num_threads = FLAGS_threads;
  pool_options.check_identifiability = true;
  pool_options.auto_fix = FLAGS_auto_fix;
  std::vector<std::string> pool_fixed;
  const CandidatePool pool =
      app::BuildPoolOrDie(&model, pool_joints, pool_options, "the pool",
                          &jacobian_seconds, &pool_fixed);
  auto_fixed.insert(auto_fixed.end(), pool_fixed.begin(), pool_fixed.end());

  static const char* const kAlgorithms[] = {"eae",    "random", "fedorov",
                                            "detmax", "greedy", "approx"};
  if (std::find(std::begin(kAlgorithms), std::end(kAlgorithms),
                FLAGS_algorithm) == std::end(kAlgorithms)) {
    app::Fail(
        "--algorithm must be one of eae, random, fedorov, detmax, "
        "greedy, approx; got '" +
        FLAGS_algorithm + "'");
  }
  if (FLAGS_restarts < 0) {
    app::Fail("--restarts must be >= 0, got " + std::to_string(FLAGS_restarts));
  }
  const bool need_approx = FLAGS_certificate || FLAGS_algorithm == "fedorov" ||
                           FLAGS_algorithm == "approx";
  ApproximateDesignSummary approx;
  if (need_approx) {
    app::ProgressLine line("approximate design, rounds");
    ApproximateDesignOptions options;
    options.progress = line.callback();
    options.tolerance = FLAGS_approx_tolerance;
    options.num_threads = FLAGS_threads;
    std::string error;
    if (!options.IsValid(&error)) app::Fail("--approx_tolerance: " + error);
    if (!SolveApproximateDesign(pool, {}, options, &approx) &&
        approx.support.empty()) {
      app::Fail("approximate design: " + approx.message);
    }
  }

  app::ProgressLine restarts_line(FLAGS_algorithm + " restarts");
  SelectionSummary summary;
  bool ok = false;
  if (FLAGS_algorithm == "eae") {
    ExchangeAddExchangeOptions options;
    options.num_poses = FLAGS_num_poses;
    options.initial_poses = FLAGS_initial_poses;
    if (FLAGS_restarts > 0) options.restarts = FLAGS_restarts;
    options.seed = FLAGS_seed;
    options.num_threads = FLAGS_threads;
    if (FLAGS_criterion == "det") {
      options.criterion = SelectionCriterion::kDeterminantUpdate;
    } else if (FLAGS_criterion == "svd") {
      options.criterion = SelectionCriterion::kEigenvalueOi;
    } else {
      app::Fail("--criterion must be det or svd, got '" + FLAGS_criterion +
                "'");
    }
    ok = ExchangeAddExchange(pool, {}, options, &summary);
  } else if (FLAGS_algorithm == "random") {
    RandomDesignOptions options;
    options.num_poses = FLAGS_num_poses;
    options.num_designs = FLAGS_random_designs;
    options.seed = FLAGS_seed;
    options.num_threads = FLAGS_threads;
    ok = SelectRandomDesigns(pool, {}, options, &summary);
  } else if (FLAGS_algorithm == "fedorov" || FLAGS_algorithm == "approx") {
    FedorovOptions options;
    options.num_poses = FLAGS_num_poses;
    // Past 200,000 poses the restarts find designs within 0.1% of each
    // other (docs/scaling.md): half as many keep the run short.
    if (pool.size() > 200000) options.restarts = 8;
    if (FLAGS_restarts > 0) options.restarts = FLAGS_restarts;
    options.seed = FLAGS_seed;
    options.num_threads = FLAGS_threads;
    options.progress = restarts_line.callback();
    options.polish_pool_size = FLAGS_polish_pool_size;
    if (FLAGS_algorithm == "approx") {
      // Only the rounding: no swaps.
      options.max_swaps = 0;
      options.restarts = 1;
    }
    ok = FedorovExchange(pool, {}, options, &approx, &summary);
    if (FLAGS_algorithm == "approx") summary.algorithm = "approx (rounded)";
  } else if (FLAGS_algorithm == "detmax") {
    DetmaxOptions options;
    options.num_poses = FLAGS_num_poses;
    if (FLAGS_restarts > 0) options.restarts = FLAGS_restarts;
    options.seed = FLAGS_seed;
    options.num_threads = FLAGS_threads;
    options.progress = restarts_line.callback();
    ok = Detmax(pool, {}, options, &summary);
  } else {
    GreedyOptions options;
    options.num_poses = FLAGS_num_poses;
    options.num_threads = FLAGS_threads;
    ok = GreedyDesign(pool, {}, options, &summary);
  }
  if (!ok) app::Fail(summary.message);

  if (FLAGS_certificate) {
    CertifyDesign(pool, {}, &approx, FLAGS_threads, &summary);
  }
  const double total_seconds = app::Seconds(start);
  std::printf("%s", summary.BriefReport().c_str());
  if (need_approx) std::printf("%s", approx.BriefReport().c_str());
  std::printf("  Jacobians of %lld poses: %.3f s\n",
              static_cast<long long>(pool.size()), jacobian_seconds);
  std::printf("  %-6s %-8s %s\n", "#", "index",
              from_lattice ? "levels (joint 1..n)" : "joints (deg)");
  for (size_t k = 0; k < summary.design.size(); ++k) {
    const int64_t i = summary.design[k];
    std::printf("  %-6zu %-8lld", k,
                static_cast<long long>(labels.empty() ? i : labels[i]));
    if (from_lattice) {
      for (int l : lattice.Levels(i)) std::printf(" %d", l);
    } else {
      for (int c = 0; c < pool_joints.cols(); ++c) {
        std::printf(" %.3f", pool_joints(i, c) * 180.0 / M_PI);
      }
    }
    std::printf("\n");
  }
  if (!FLAGS_poses_csv.empty()) {
    PoseList chosen;
    chosen.joints.resize(summary.design.size(), model.num_joints());
    for (size_t k = 0; k < summary.design.size(); ++k) {
      const int64_t i = summary.design[k];
      chosen.joints.row(k) = pool_joints.row(i);
      chosen.pose_indices.push_back(labels.empty() ? i : labels[i]);
    }
    app::WriteTextOrDie(FLAGS_poses_csv, PosesCsvText(model, chosen));
  }
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j = app::SelectionJson(summary, pool_joints, labels);
    j["robot"] = model.name;
    j["measurement"] = FLAGS_measurement;
    j["free_parameters"] = model.FreeParameterNames();
    j["auto_fixed"] = auto_fixed;
    j["seed"] = FLAGS_seed;
    if (from_lattice) {
      j["levels"] = FLAGS_levels;
    } else {
      j["pool_csv"] = FLAGS_pool_csv;
    }
    // Wall-clock times: the only fields that vary between runs.
    j["timing"] = {{"jacobian_seconds", jacobian_seconds},
                   {"selection_seconds", summary.seconds},
                   {"approximate_seconds", approx.seconds},
                   {"total_seconds", total_seconds}};
    if (FLAGS_certificate) {
      j["efficiency_lower_bound"] = summary.efficiency_lower_bound;
      j["log10_det_upper_bound"] = summary.log_det_upper_bound / std::log(10.0);
    }
    if (need_approx) {
      j["approximate"] = {{"support", approx.support},
                          {"weights", approx.weights},
                          {"log10_det", approx.log_det / std::log(10.0)},
                          {"max_variance", approx.max_variance},
                          {"log10_det_upper_bound",
                           approx.log_det_upper_bound / std::log(10.0)},
                          {"tolerance", FLAGS_approx_tolerance},
                          {"converged", approx.termination_type ==
                                            TerminationType::kConvergence}};
    }
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Selects calibration poses from a lattice of joint values (or a pool "
      "read from CSV), maximising det(X^T X) of the measurement Jacobian at "
      "the nominal parameters. The robot is --robot (default: the Sun & "
      "Hollerbach PUMA 560).\n  activecal_select --algorithm=fedorov "
      "--seed=1 --json_out=design.json --poses_csv=poses.csv");
  return activecal::Main();
}
