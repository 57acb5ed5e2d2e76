// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/selection/target_size.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "activecal/core/validation.h"
#include "activecal/selection/task_criterion.h"

namespace activecal {

bool TargetSizeOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (!(sigma_m > 0) || !std::isfinite(sigma_m))
    msg << "the noise sigma must be > 0 m, got " << sigma_m;
  else if (!(target_rms_m > 0) || !std::isfinite(target_rms_m))
    msg << "the target RMS must be > 0 m, got " << target_rms_m;
  return FinishValidation(msg, error);
}

bool FindSizeForTarget(const CandidatePool& pool, const Eigen::MatrixXd& W,
                       const RowMatrixXd& prior_rows,
                       const DesignConstraints& constraints,
                       const TargetSizeOptions& options,
                       const DesignOfSize& design_of_size,
                       TargetSizeSummary* summary) {
  *summary = TargetSizeSummary();
  if (!options.IsValid(&summary->message)) {
    summary->termination_type = TerminationType::kUserFailure;
    return false;
  }
  std::vector<int64_t> all;
  for (int64_t i = 0; i < pool.size(); ++i) {
    if (!(constraints.excluded && constraints.excluded(i))) all.push_back(i);
  }
  const int max_poses = static_cast<int>(all.size());
  summary->best_reachable_rms_m = PredictedTaskRms(
      TaskCriterionFromScratch(pool, W, prior_rows, all), options.sigma_m);
  std::ostringstream msg;
  msg.precision(4);
  if (!(summary->best_reachable_rms_m <= options.target_rms_m)) {
    msg << "the target task RMS " << options.target_rms_m
        << " m cannot be met with sigma " << options.sigma_m << " m: even all "
        << max_poses << " pool poses together predict "
        << summary->best_reachable_rms_m << " m (the best reachable value)";
    summary->message = msg.str();
    summary->termination_type = TerminationType::kFailure;
    return false;
  }
  int n0 = options.min_poses;
  if (n0 <= 0) {
    const int p = pool.num_parameters();
    int prior_rank = 0;
    if (prior_rows.rows() > 0) {
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(prior_rows);
      qr.setThreshold(1e-10);
      prior_rank = static_cast<int>(qr.rank());
    }
    n0 = std::max(1,
                  (p - prior_rank + pool.block_rows() - 1) / pool.block_rows());
  }
  n0 = std::max<int>(n0, constraints.fixed.size());
  n0 = std::min(n0, max_poses);
  std::map<int, std::pair<double, SelectionSummary>> tried;
  auto evaluate = [&](int n) -> bool {
    auto it = tried.find(n);
    if (it == tried.end()) {
      SelectionSummary s;
      double rms = std::numeric_limits<double>::infinity();
      if (n == max_poses) {
        s.design = all;
        s.termination_type = TerminationType::kConvergence;
        s.algorithm = "every pool pose";
        s.num_parameters = pool.num_parameters();
        s.pool_size = pool.size();
        rms = summary->best_reachable_rms_m;
      } else if (design_of_size(n, &s)) {
        rms = PredictedTaskRms(
            TaskCriterionFromScratch(pool, W, prior_rows, s.design),
            options.sigma_m);
      }
      it = tried.emplace(n, std::make_pair(rms, std::move(s))).first;
    }
    return it->second.first <= options.target_rms_m;
  };
  if (prior_rows.rows() > 0) {
    // The poses already measured may meet the target alone.
    const double rms = PredictedTaskRms(
        TaskCriterionFromScratch(pool, W, prior_rows, {}), options.sigma_m);
    SelectionSummary none;
    none.termination_type = TerminationType::kConvergence;
    none.algorithm = "the poses already measured";
    none.num_parameters = pool.num_parameters();
    none.pool_size = pool.size();
    tried.emplace(0, std::make_pair(rms, none));
    if (rms <= options.target_rms_m) n0 = 0;
  }
  int lo = n0, hi = n0;  // lo: smallest size not known to miss
  while (!evaluate(hi)) {
    lo = hi + 1;
    hi = std::min(2 * hi, max_poses);
  }
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (evaluate(mid)) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  for (const auto& [n, entry] : tried) {
    summary->sizes.push_back(n);
    summary->rms_by_size_m.push_back(entry.first);
  }
  summary->num_poses = hi;
  summary->predicted_task_rms_m = tried[hi].first;
  summary->design = tried[hi].second;
  msg << hi << " poses predict " << summary->predicted_task_rms_m
      << " m <= the target " << options.target_rms_m << " m";
  if (hi > n0)
    msg << "; " << hi - 1 << " poses predict " << tried[hi - 1].first << " m";
  summary->message = msg.str();
  summary->termination_type = TerminationType::kConvergence;
  return true;
}

}  // namespace activecal
