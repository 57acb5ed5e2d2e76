// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/tour.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

namespace activecal {
namespace {

// Open-path cost of an order under a move cost.
template <typename Cost>
double PathCost(const std::vector<int>& order, Cost cost) {
  double total = 0.0;
  for (size_t k = 0; k + 1 < order.size(); ++k) {
    total += cost(order[k], order[k + 1]);
  }
  return total;
}

}  // namespace

bool TourOptions::IsValid(std::string* error) const {
  std::string e;
  if (!(default_velocity > 0) || !std::isfinite(default_velocity)) {
    e = "default_velocity must be > 0";
  } else if (!(resolution_rad > 0) || !(resolution_m > 0)) {
    e = "the resolutions must be > 0";
  }
  for (double v : velocity_limits) {
    if (!std::isfinite(v)) e = "velocity limits must be finite";
  }
  if (e.empty()) return true;
  if (error) *error = e;
  return false;
}

double MoveTime(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                const std::vector<double>& velocities) {
  double t = 0.0;
  for (int j = 0; j < a.size(); ++j) {
    t = std::max(t, std::abs(b[j] - a[j]) / velocities[j]);
  }
  return t;
}

bool MoveIsFree(const CellChecker& checker, const Eigen::VectorXd& a,
                const Eigen::VectorXd& b, const TourOptions& options,
                CellChecker::Workspace* workspace, PoseVerdict* verdict,
                int64_t* configurations) {
  const RobotModel& model = checker.model();
  double steps = 1.0;
  for (int j = 0; j < a.size(); ++j) {
    const double r = model.links[j].joint_type == JointType::kPrismatic
                         ? options.resolution_m
                         : options.resolution_rad;
    steps = std::max(steps, std::ceil(std::abs(b[j] - a[j]) / r));
  }
  const int64_t n = static_cast<int64_t>(steps);
  Eigen::VectorXd q(a.size());
  for (int64_t k = 0; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    q = a + s * (b - a);
    if (configurations) ++*configurations;
    const PoseVerdict v = checker.CheckCollisions(q.data(), workspace);
    if (!v.feasible()) {
      if (verdict) *verdict = v;
      return false;
    }
  }
  return true;
}

std::string TourSummary::BriefReport(const std::string& not_checked) const {
  char line[320];
  if (!not_checked.empty()) {
    std::snprintf(line, sizeof(line),
                  "tour: %zu poses, estimated motion time %.4g s -> %.4g s; "
                  "%s: moves not checked, %.3g s\n",
                  order.size(), time_before_s, time_after_s,
                  not_checked.c_str(), seconds);
    return line;
  }
  std::snprintf(line, sizeof(line),
                "tour: %zu poses, estimated motion time %.4g s -> %.4g s; "
                "%lld moves checked (%lld configurations), %zu blocked "
                "(%d in the input order), %.3g s\n",
                order.size(), time_before_s, time_after_s,
                static_cast<long long>(moves_checked),
                static_cast<long long>(configurations_checked),
                blocked_moves.size(), blocked_before, seconds);
  return line;
}

bool OrderTour(const CellChecker* checker, const Eigen::MatrixXd& poses,
               const TourOptions& options, TourSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  *summary = TourSummary();
  TourSummary& s = *summary;
  std::string error;
  if (!options.IsValid(&error)) {
    s.termination_type = TerminationType::kUserFailure;
    s.message = error;
    return false;
  }
  const int n = static_cast<int>(poses.rows());
  const int dof = static_cast<int>(poses.cols());
  s.velocities.assign(dof, options.default_velocity);
  for (int j = 0;
       j < dof && j < static_cast<int>(options.velocity_limits.size()); ++j) {
    if (options.velocity_limits[j] > 0)
      s.velocities[j] = options.velocity_limits[j];
  }
  std::vector<Eigen::VectorXd> q(n);
  for (int i = 0; i < n; ++i) q[i] = poses.row(i).transpose();
  std::vector<double> time(static_cast<size_t>(n) * n);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k)
      time[i * n + k] = MoveTime(q[i], q[k], s.velocities);
  }
  const bool check =
      options.check_moves && checker != nullptr && checker->has_geometry();
  std::unique_ptr<CellChecker::Workspace> workspace;
  if (check) workspace = checker->NewWorkspace();
  // Whether a move is blocked, checked once per pair.
  std::map<std::pair<int, int>, std::string> blocked;  // pair -> why
  std::map<std::pair<int, int>, bool> known;
  auto is_blocked = [&](int i, int k) {
    if (!check) return false;
    const std::pair<int, int> key(std::min(i, k), std::max(i, k));
    const auto it = known.find(key);
    if (it != known.end()) return it->second;
    PoseVerdict v;
    ++s.moves_checked;
    const bool free =
        MoveIsFree(*checker, q[key.first], q[key.second], options,
                   workspace.get(), &v, &s.configurations_checked);
    known[key] = !free;
    if (!free) blocked[key] = checker->Describe(v);
    return !free;
  };
  auto cost = [&](int i, int k) {
    return time[i * n + k] + (is_blocked(i, k) ? kBlockedMovePenaltyS : 0.0);
  };
  auto plain = [&](int i, int k) { return time[i * n + k]; };

  std::vector<int> input(n);
  for (int i = 0; i < n; ++i) input[i] = i;
  s.time_before_s = PathCost(input, plain);
  for (int k = 0; k + 1 < n; ++k)
    s.blocked_before += is_blocked(input[k], input[k + 1]);

  // 2-opt on an open path: reverse order[i..k] when that shortens it. A
  // reversal is first judged by time alone; the new moves are checked
  // only for one that would shorten it.
  auto two_opt = [&](std::vector<int>* order) {
    std::vector<int>& o = *order;
    bool improved = true;
    while (improved) {
      improved = false;
      for (int i = 0; i < n - 1; ++i) {
        for (int k = i + 1; k < n; ++k) {
          // Moves (i-1, i) and (k, k+1) become (i-1, k) and (i, k+1).
          double old_cost = 0.0, new_time = 0.0;
          if (i > 0) {
            old_cost += cost(o[i - 1], o[i]);
            new_time += plain(o[i - 1], o[k]);
          }
          if (k < n - 1) {
            old_cost += cost(o[k], o[k + 1]);
            new_time += plain(o[i], o[k + 1]);
          }
          if (new_time >= old_cost - 1e-12) continue;
          double new_cost = 0.0;
          if (i > 0) new_cost += cost(o[i - 1], o[k]);
          if (k < n - 1) new_cost += cost(o[i], o[k + 1]);
          if (new_cost < old_cost - 1e-12) {
            std::reverse(o.begin() + i, o.begin() + k + 1);
            improved = true;
          }
        }
      }
    }
  };
  // Nearest neighbour from every start, by time.
  std::vector<int> best;
  double best_time = std::numeric_limits<double>::infinity();
  for (int first = 0; first < n; ++first) {
    std::vector<int> order = {first};
    std::vector<bool> used(n, false);
    used[first] = true;
    for (int step = 1; step < n; ++step) {
      const int from = order.back();
      int next = -1;
      for (int k = 0; k < n; ++k) {
        if (!used[k] && (next < 0 || plain(from, k) < plain(from, next)))
          next = k;
      }
      used[next] = true;
      order.push_back(next);
    }
    const double t = PathCost(order, plain);
    if (t < best_time) {
      best_time = t;
      best = order;
    }
  }
  if (n > 0) {
    two_opt(&best);
    std::vector<int> improved_input = input;
    two_opt(&improved_input);
    s.order = PathCost(improved_input, cost) <= PathCost(best, cost)
                  ? improved_input
                  : best;
  }
  s.time_after_s = PathCost(s.order, plain);
  for (int k = 0; k + 1 < n; ++k) {
    if (is_blocked(s.order[k], s.order[k + 1])) {
      s.blocked_moves.push_back(k);
      const std::pair<int, int> key(std::min(s.order[k], s.order[k + 1]),
                                    std::max(s.order[k], s.order[k + 1]));
      s.blocked_reasons.push_back(blocked[key]);
    }
  }
  s.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  s.termination_type = TerminationType::kConvergence;
  if (!s.blocked_moves.empty()) {
    s.message = std::to_string(s.blocked_moves.size()) +
                " moves of the tour are blocked (no free order found)";
  }
  return true;
}

}  // namespace activecal
