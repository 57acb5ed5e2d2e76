// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/select_design.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "activecal/core/enum_name_list.h"
#include "activecal/selection/detmax.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/greedy.h"
#include "activecal/selection/random_designs.h"
#include "activecal/selection/task_criterion.h"
#include "activecal/selection/task_exchange.h"
#include "restart_options.h"
#include "seconds_since.h"

namespace activecal {
namespace {

std::string Number(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6g", x);
  return buffer;
}

// The approximate designs are solved for the starts (fedorov, approx) and
// for the certificate.
bool NeedsApproximate(const SelectDesignOptions& o) {
  return o.certificate || o.algorithm == DesignAlgorithm::kFedorov ||
         o.algorithm == DesignAlgorithm::kApprox;
}

// The options of a restarting algorithm designing num_poses poses, its
// restarts reported to options.restarts_progress.
template <typename Options>
Options RestartOptionsFor(const SelectDesignOptions& options, int restarts,
                          int num_poses) {
  Options o = internal::RestartOptions<Options>(
      num_poses, restarts, options.seed, options.num_threads);
  o.progress = options.restarts_progress;
  return o;
}

using internal::SecondsSince;

}  // namespace

constexpr const char* kDesignAlgorithmNames[] = {"eae",    "random", "fedorov",
                                                 "detmax", "greedy", "approx"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(DesignAlgorithm, kDesignAlgorithmNames)

bool ParseDesignAlgorithm(const std::string& text, DesignAlgorithm* algorithm,
                          std::string* error) {
  if (StringToDesignAlgorithm(text, algorithm)) return true;
  if (error) {
    *error =
        "algorithm must be one of eae, random, fedorov, detmax, greedy, "
        "approx; got '" +
        text + "'";
  }
  return false;
}

constexpr const char* kDesignCriterionNames[] = {"det", "svd", "task_rms"};

const char* DesignCriterionToString(DesignCriterion criterion) {
  return EnumToString(kDesignCriterionNames, criterion);
}

bool StringToDesignCriterion(const std::string& text,
                             DesignCriterion* criterion) {
  return StringToEnum(kDesignCriterionNames, text == "d" ? "det" : text,
                      criterion);
}

bool ParseDesignCriterion(const std::string& text, DesignCriterion* criterion,
                          std::string* error) {
  if (StringToDesignCriterion(text, criterion)) return true;
  if (error) {
    *error = "criterion must be det (d), svd or task_rms, got '" + text + "'";
  }
  return false;
}

bool ReadsFloatPool(DesignAlgorithm algorithm, DesignCriterion criterion) {
  return (algorithm == DesignAlgorithm::kFedorov ||
          algorithm == DesignAlgorithm::kApprox) &&
         criterion != DesignCriterion::kTaskRms;
}

bool SelectDesignOptions::IsValid(std::string* error) const {
  std::string e;
  const bool is_task = task();
  if (restarts < 0) {
    e = "restarts must be >= 0, got " + std::to_string(restarts);
  } else if (is_task && algorithm != DesignAlgorithm::kFedorov &&
             algorithm != DesignAlgorithm::kGreedy &&
             algorithm != DesignAlgorithm::kApprox) {
    e = "criterion=task_rms: algorithm must be fedorov, greedy or approx, "
        "got '" +
        std::string(DesignAlgorithmToString(algorithm)) + "'";
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
  const DesignAlgorithm a = options.algorithm;
  if (a == DesignAlgorithm::kApprox) return 1;
  if (a == DesignAlgorithm::kRandom || a == DesignAlgorithm::kGreedy) return 0;
  if (options.restarts > 0) return options.restarts;
  if (options.task()) return TaskExchangeOptions().restarts;
  if (a == DesignAlgorithm::kEae) return ExchangeAddExchangeOptions().restarts;
  if (a == DesignAlgorithm::kDetmax) return DetmaxOptions().restarts;
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

  const DesignAlgorithm algorithm = options.algorithm;
  const int restarts = s.restarts;
  // Designs num_poses poses by the chosen criterion and algorithm.
  auto design_of_size = [&](int num_poses, SelectionSummary* out) {
    if (task) {
      if (algorithm == DesignAlgorithm::kGreedy) {
        return TaskGreedy(pool, W, prior, {}, num_poses, options.num_threads,
                          out);
      }
      TaskExchangeOptions o =
          RestartOptionsFor<TaskExchangeOptions>(options, restarts, num_poses);
      if (algorithm == DesignAlgorithm::kApprox) o.max_swaps = 0;  // rounding
      const bool ok =
          TaskExchange(pool, W, prior, {}, o,
                       s.with_task_approx ? &s.task_approx : nullptr, out);
      if (algorithm == DesignAlgorithm::kApprox) {
        out->algorithm = "task approx (rounded)";
      }
      return ok;
    }
    switch (algorithm) {
      case DesignAlgorithm::kEae: {
        ExchangeAddExchangeOptions o =
            RestartOptionsFor<ExchangeAddExchangeOptions>(options, restarts,
                                                          num_poses);
        o.initial_poses = std::min(options.initial_poses, num_poses);
        o.criterion = options.criterion == DesignCriterion::kSvd
                          ? SelectionCriterion::kEigenvalueOi
                          : SelectionCriterion::kDeterminantUpdate;
        return ExchangeAddExchange(pool, {}, o, out);
      }
      case DesignAlgorithm::kRandom: {
        RandomDesignOptions o;
        o.num_poses = num_poses;
        o.num_designs = options.random_designs;
        o.seed = options.seed;
        o.num_threads = options.num_threads;
        return SelectRandomDesigns(pool, {}, o, out);
      }
      case DesignAlgorithm::kFedorov:
      case DesignAlgorithm::kApprox: {
        const bool approx = algorithm == DesignAlgorithm::kApprox;
        FedorovOptions o =
            RestartOptionsFor<FedorovOptions>(options, restarts, num_poses);
        o.polish_pool_size = options.polish_pool_size;
        if (approx) o.max_swaps = 0;  // only the rounding
        const bool ok = FedorovExchange(pool, {}, o, &s.approx, out);
        if (approx) out->algorithm = "approx (rounded)";
        return ok;
      }
      case DesignAlgorithm::kDetmax: {
        return Detmax(
            pool, {},
            RestartOptionsFor<DetmaxOptions>(options, restarts, num_poses),
            out);
      }
      case DesignAlgorithm::kGreedy:
        break;
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
