// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/select_design.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "activecal/selection/detmax.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/greedy.h"
#include "activecal/selection/random_designs.h"
#include "activecal/selection/task_criterion.h"
#include "activecal/selection/task_exchange.h"

namespace activecal {
namespace {

std::string Number(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6g", x);
  return buffer;
}

bool IsAlgorithm(const std::string& a) {
  static const char* const kAlgorithms[] = {"eae",    "random", "fedorov",
                                            "detmax", "greedy", "approx"};
  return std::find(std::begin(kAlgorithms), std::end(kAlgorithms), a) !=
         std::end(kAlgorithms);
}

// The approximate designs are solved for the starts (fedorov, approx) and
// for the certificate.
bool NeedsApproximate(const SelectDesignOptions& o) {
  return o.certificate || o.algorithm == "fedorov" || o.algorithm == "approx";
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

bool SelectDesignOptions::IsValid(std::string* error) const {
  std::string e;
  const bool is_task = task();
  if (!IsAlgorithm(algorithm)) {
    e = "algorithm must be one of eae, random, fedorov, detmax, greedy, "
        "approx; got '" +
        algorithm + "'";
  } else if (restarts < 0) {
    e = "restarts must be >= 0, got " + std::to_string(restarts);
  } else if (!is_task && criterion != "det" && criterion != "d" &&
             criterion != "svd") {
    e = "criterion must be det (d), svd or task_rms, got '" + criterion + "'";
  } else if (is_task && algorithm != "fedorov" && algorithm != "greedy" &&
             algorithm != "approx") {
    e = "criterion=task_rms: algorithm must be fedorov, greedy or approx, "
        "got '" +
        algorithm + "'";
  } else if (!(noise_m > 0) || !std::isfinite(noise_m)) {
    e = "noise_m must be > 0 (m), got " + Number(noise_m);
  } else if (target_rms_m &&
             (!(*target_rms_m > 0) || !std::isfinite(*target_rms_m))) {
    e = "target_rms_m must be > 0 (m), got " + Number(*target_rms_m);
  } else if (NeedsApproximate(*this)) {
    std::string why;
    if (!is_task) {
      ApproximateDesignOptions a;
      a.tolerance = approx_tolerance;
      if (!a.IsValid(&why)) e = "approx_tolerance: " + why;
    } else {
      TaskApproximateOptions a;
      a.tolerance = task_approx_tolerance;
      if (!a.IsValid(&why)) e = "approx_tolerance: " + why;
    }
  }
  if (e.empty()) return true;
  if (error) *error = e;
  return false;
}

int ResolvedRestarts(const SelectDesignOptions& options, int64_t pool_size) {
  const std::string& a = options.algorithm;
  if (a == "approx") return 1;
  if (a == "random" || a == "greedy") return 0;
  if (options.restarts > 0) return options.restarts;
  if (options.task()) return TaskExchangeOptions().restarts;
  if (a == "eae") return ExchangeAddExchangeOptions().restarts;
  if (a == "detmax") return DetmaxOptions().restarts;
  return pool_size > kFedorovLargePool ? kFedorovLargePoolRestarts
                                       : FedorovOptions().restarts;
}

std::string SelectDesignSummary::BriefReport() const {
  std::string report = selection.BriefReport();
  if (with_approx) report += approx.BriefReport();
  if (with_task_approx) report += task_approx.BriefReport();
  return report;
}

bool SelectDesign(const CandidatePool& pool, const Eigen::MatrixXd& W,
                  const RowMatrixXd& prior, const SelectDesignOptions& options,
                  SelectDesignSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  *summary = SelectDesignSummary();
  SelectDesignSummary& s = *summary;
  auto fail = [&](TerminationType type, std::string message) {
    s.termination_type = type;
    s.message = std::move(message);
    s.total_seconds = SecondsSince(start);
    return false;
  };
  std::string error;
  if (!options.IsValid(&error)) {
    return fail(TerminationType::kUserFailure, error);
  }
  const bool task = options.task();
  s.task = task;
  s.algorithm = options.algorithm;
  s.with_target = options.target_rms_m.has_value();
  s.with_prior = prior.rows() > 0;
  s.restarts = ResolvedRestarts(options, pool.size());
  if (!s.with_target &&
      (options.num_poses <= 0 || options.num_poses > pool.size())) {
    return fail(TerminationType::kUserFailure,
                "num_poses must be in [1, " + std::to_string(pool.size()) +
                    "] (the pool size), got " +
                    std::to_string(options.num_poses));
  }
  if (s.with_prior && !task) {
    return fail(TerminationType::kUserFailure,
                "a prior (poses already measured) needs criterion task_rms "
                "(the D-criterion algorithms take no prior information)");
  }
  if (s.with_prior && prior.cols() != pool.num_parameters()) {
    return fail(TerminationType::kUserFailure,
                "prior: expected " + std::to_string(pool.num_parameters()) +
                    " columns, got " + std::to_string(prior.cols()));
  }

  s.with_approx = !task && NeedsApproximate(options);
  if (s.with_approx) {
    ApproximateDesignOptions a;
    a.progress = options.approximate_progress;
    a.tolerance = options.approx_tolerance;
    a.num_threads = options.num_threads;
    a.seed = options.seed;
    if (!SolveApproximateDesign(pool, {}, a, &s.approx) &&
        s.approx.support.empty()) {
      return fail(TerminationType::kFailure,
                  "approximate design: " + s.approx.message);
    }
    s.approximate_seconds = s.approx.seconds;
  }
  // The approximate task design ignores the prior: with measured poses it
  // is not used.
  s.with_task_approx = task && !s.with_prior && NeedsApproximate(options);
  if (s.with_task_approx) {
    TaskApproximateOptions a;
    a.tolerance = options.task_approx_tolerance;
    a.num_threads = options.num_threads;
    if (!SolveTaskApproximateDesign(pool, W, {}, a, &s.task_approx)) {
      return fail(TerminationType::kFailure,
                  "approximate task design: " + s.task_approx.message);
    }
    s.approximate_seconds = s.task_approx.seconds;
  }

  const std::string& algorithm = options.algorithm;
  const int restarts = s.restarts;
  // Designs num_poses poses by the chosen criterion and algorithm.
  auto design_of_size = [&](int num_poses, SelectionSummary* out) {
    if (task) {
      if (algorithm == "greedy") {
        return TaskGreedy(pool, W, prior, {}, num_poses, options.num_threads,
                          out);
      }
      TaskExchangeOptions o;
      o.num_poses = num_poses;
      o.restarts = restarts;
      o.seed = options.seed;
      o.num_threads = options.num_threads;
      o.progress = options.restarts_progress;
      if (algorithm == "approx") o.max_swaps = 0;  // only the rounding
      const bool ok =
          TaskExchange(pool, W, prior, {}, o,
                       s.with_task_approx ? &s.task_approx : nullptr, out);
      if (algorithm == "approx") out->algorithm = "task approx (rounded)";
      return ok;
    }
    if (algorithm == "eae") {
      ExchangeAddExchangeOptions o;
      o.num_poses = num_poses;
      o.initial_poses = std::min(options.initial_poses, num_poses);
      o.restarts = restarts;
      o.seed = options.seed;
      o.num_threads = options.num_threads;
      o.progress = options.restarts_progress;
      o.criterion = options.criterion == "svd"
                        ? SelectionCriterion::kEigenvalueOi
                        : SelectionCriterion::kDeterminantUpdate;
      return ExchangeAddExchange(pool, {}, o, out);
    }
    if (algorithm == "random") {
      RandomDesignOptions o;
      o.num_poses = num_poses;
      o.num_designs = options.random_designs;
      o.seed = options.seed;
      o.num_threads = options.num_threads;
      return SelectRandomDesigns(pool, {}, o, out);
    }
    if (algorithm == "fedorov" || algorithm == "approx") {
      FedorovOptions o;
      o.num_poses = num_poses;
      o.restarts = restarts;
      o.seed = options.seed;
      o.num_threads = options.num_threads;
      o.progress = options.restarts_progress;
      o.polish_pool_size = options.polish_pool_size;
      if (algorithm == "approx") o.max_swaps = 0;  // only the rounding
      const bool ok = FedorovExchange(pool, {}, o, &s.approx, out);
      if (algorithm == "approx") out->algorithm = "approx (rounded)";
      return ok;
    }
    if (algorithm == "detmax") {
      DetmaxOptions o;
      o.num_poses = num_poses;
      o.restarts = restarts;
      o.seed = options.seed;
      o.num_threads = options.num_threads;
      o.progress = options.restarts_progress;
      return Detmax(pool, {}, o, out);
    }
    GreedyOptions o;
    o.num_poses = num_poses;
    o.num_threads = options.num_threads;
    return GreedyDesign(pool, {}, o, out);
  };

  SelectionSummary& selection = s.selection;
  if (s.with_target) {
    TargetSizeOptions o;
    o.sigma_m = options.noise_m;
    o.target_rms_m = *options.target_rms_m;
    if (!FindSizeForTarget(pool, W, prior, {}, o, design_of_size, &s.target)) {
      return fail(TerminationType::kFailure,
                  "target_rms_m: " + s.target.message);
    }
    selection = s.target.design;
  } else if (!design_of_size(options.num_poses, &selection)) {
    return fail(TerminationType::kFailure, selection.message);
  }
  // The task criterion of whatever design was chosen.
  selection.task_criterion =
      TaskCriterionFromScratch(pool, W, prior, selection.design);
  s.predicted_task_rms_m =
      PredictedTaskRms(selection.task_criterion, options.noise_m);
  if (options.certificate) {
    if (!task) {
      CertifyDesign(pool, {}, &s.approx, options.num_threads, &selection);
    } else if (!s.with_prior) {
      CertifyTaskDesign(pool, W, {}, &s.task_approx, options.num_threads,
                        &selection);
    }
  }
  s.termination_type = selection.termination_type;
  s.message = selection.message;
  s.total_seconds = SecondsSince(start);
  return true;
}

}  // namespace activecal
