// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Fedorov exchange and greedy additions for the task criterion.

#include "activecal/selection/task_exchange.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/core/validation.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/greedy.h"
#include "activecal/selection/task_approximate.h"
#include "activecal/selection/task_criterion.h"
#include "selection_internal.h"
#include "sub_pool.h"

namespace activecal {

bool TaskExchangeOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (internal::PositivePosesAndRestarts(*this, &msg)) {
    if (max_swaps < 0)
      msg << "max_swaps must be >= 0, got " << max_swaps;
    else if (!(min_improvement >= 0))
      msg << "min_improvement must be >= 0";
  }
  return FinishValidation(msg, error);
}

namespace {

using internal::kInf;
using internal::RestartResult;

struct Entry {
  double value;
  int64_t pose;
};

// The add change -tr((I + A)^-1 B) of a pose from its t x t blocks.
template <int T>
double AddChangeOf(const double* a, const double* b, int t) {
  using Mat = Eigen::Matrix<double, T, T>;
  Mat S = Eigen::Map<const Mat>(a, t, t);
  S.diagonal().array() += 1.0;
  Eigen::LLT<Mat> llt(S);
  return -llt.solve(Eigen::Map<const Mat>(b, t, t)).trace();
}

// The swap formula of task_criterion.h with fixed-size t x t blocks.
template <int T>
struct SwapKernel {
  using Mat = Eigen::Matrix<double, T, T>;
  // The candidate: S^-1 = (I + A_x)^-1, B_x, and its add change.
  Mat Si;
  Mat Bx;
  double add = 0;

  void Set(const double* a, const double* b, int t) {
    Mat S = Eigen::Map<const Mat>(a, t, t);
    S.diagonal().array() += 1.0;
    Si = S.inverse();  // closed form for 3 x 3; S is SPD
    Bx = Eigen::Map<const Mat>(b, t, t);
    add = -(Si.cwiseProduct(Bx)).sum();  // tr(S^-1 B), both symmetric
  }
  // D = X V Y^T, E = X V W V Y^T; Ay, By of the removed pose.
  double Change(const Mat& D, const Mat& E, const double* ay, const double* by,
                int t) const {
    const Mat SiD = Si.lazyProduct(D);
    Mat R = -Eigen::Map<const Mat>(ay, t, t);
    R.noalias() += D.transpose().lazyProduct(SiD);
    R.diagonal().array() += 1.0;  // I - A_y'
    Mat By1 = Eigen::Map<const Mat>(by, t, t);
    const Mat ESiD = E.transpose().lazyProduct(SiD);
    By1 -= ESiD + ESiD.transpose();
    By1.noalias() += SiD.transpose().lazyProduct(Bx.lazyProduct(SiD));
    if (LogDetSpd(R) == -kInf) return kInf;
    const Mat Ri = R.inverse();
    return add + (Ri.cwiseProduct(By1.transpose())).sum();
  }
};

// One best-swap search and step. Returns false when no swap lowers phi by
// more than the threshold.
template <int T>
bool BestSwap(const CandidatePool& pool, const TaskDesign& design,
              const std::vector<char>& eligible,
              const std::vector<char>& is_fixed, double threshold, int threads,
              std::vector<double>* a, std::vector<double>* b, int64_t* best_x,
              int64_t* best_y) {
  using Mat = Eigen::Matrix<double, T, T>;
  const int t = pool.block_rows();
  const int p = pool.num_parameters();
  const int tt = t * t;
  design.AllQuadraticForms(threads, a, b);
  std::vector<Entry> xs;
  for (int64_t x = 0; x < pool.size(); ++x) {
    if (!eligible[x] || design.Contains(x)) continue;
    const double dx = AddChangeOf<T>(a->data() + x * tt, b->data() + x * tt, t);
    if (dx < -threshold) xs.push_back({dx, x});
  }
  std::sort(xs.begin(), xs.end(), [](const Entry& u, const Entry& v) {
    return u.value < v.value || (u.value == v.value && u.pose < v.pose);
  });
  std::vector<int64_t> ys;
  for (int64_t y : design.poses()) {
    if (!is_fixed[y]) ys.push_back(y);
  }
  std::sort(ys.begin(), ys.end());
  if (ys.empty() || xs.empty()) return false;
  // P = [V Y^T, V W V Y^T] for every removable design pose, p x 2t each.
  const Eigen::MatrixXd& V = design.inverse();
  std::vector<Eigen::MatrixXd> P(ys.size());
  for (size_t j = 0; j < ys.size(); ++j) {
    const auto Y = pool.block(ys[j]);
    P[j].resize(p, 2 * t);
    P[j].leftCols(t).noalias() = V * Y.transpose();
    P[j].rightCols(t).noalias() = design.vwv() * Y.transpose();
  }
  double best = -threshold;
  *best_x = *best_y = -1;
  constexpr int64_t kBlock = 128;
  std::vector<double> item_value(kBlock);
  std::vector<int64_t> item_y(kBlock);
  // The best swap among the first num_x candidates and the design poses
  // ys_order[0 .. num_y).
  auto scan = [&](size_t num_x, const std::vector<size_t>& y_list) {
    for (size_t begin = 0; begin < num_x; begin += kBlock) {
      if (xs[begin].value >= best) break;
      const double bound = best;
      const int64_t count = std::min<int64_t>(kBlock, num_x - begin);
      ParallelFor(count, threads, [&](int64_t kb, int64_t ke, int) {
        SwapKernel<T> kernel;
        Eigen::MatrixXd DE(t, 2 * t);
        Mat D(t, t), E(t, t);
        for (int64_t k = kb; k < ke; ++k) {
          item_value[k] = kInf;
          item_y[k] = -1;
          const int64_t x = xs[begin + k].pose;
          if (xs[begin + k].value >= bound) continue;
          kernel.Set(a->data() + x * tt, b->data() + x * tt, t);
          const auto X = pool.block(x);
          for (size_t j : y_list) {
            DE.noalias() = X.lazyProduct(P[j]);
            D = DE.leftCols(t);
            E = DE.rightCols(t);
            const double c = kernel.Change(D, E, a->data() + ys[j] * tt,
                                           b->data() + ys[j] * tt, t);
            if (c < item_value[k] ||
                (c == item_value[k] && ys[j] < item_y[k])) {
              item_value[k] = c;
              item_y[k] = ys[j];
            }
          }
        }
      });
      for (int64_t k = 0; k < count; ++k) {
        if (item_value[k] < best) {
          best = item_value[k];
          *best_x = xs[begin + k].pose;
          *best_y = item_y[k];
        }
      }
    }
  };
  // KL exchange first (Atkinson & Donev): the design poses whose removal
  // costs least against the candidates whose addition gains most. Only when
  // no such swap helps is every pair scanned, so the result is a local
  // optimum over all swaps.
  std::vector<Entry> removal(ys.size());
  for (size_t j = 0; j < ys.size(); ++j) {
    Mat R = -Eigen::Map<const Mat>(a->data() + ys[j] * tt, t, t);
    R.diagonal().array() += 1.0;
    const double c =
        LogDetSpd(R) == -kInf
            ? kInf
            : Eigen::LLT<Mat>(R)
                  .solve(Eigen::Map<const Mat>(b->data() + ys[j] * tt, t, t))
                  .trace();
    removal[j] = {c, static_cast<int64_t>(j)};
  }
  std::sort(removal.begin(), removal.end(), [](const Entry& u, const Entry& v) {
    return u.value < v.value || (u.value == v.value && u.pose < v.pose);
  });
  const size_t kl_y =
      std::min<size_t>(ys.size(), std::max<size_t>(4, ys.size() / 8));
  const size_t kl_x = std::min<size_t>(xs.size(), 64 * kl_y);
  std::vector<size_t> y_list;
  for (size_t j = 0; j < kl_y; ++j) y_list.push_back(removal[j].pose);
  scan(kl_x, y_list);
  if (*best_x < 0) {
    y_list.clear();
    for (size_t j = 0; j < ys.size(); ++j) y_list.push_back(j);
    scan(xs.size(), y_list);
  }
  return *best_x >= 0;
}

RestartResult TaskRestart(const CandidatePool& pool, const Eigen::MatrixXd& W,
                          const RowMatrixXd& prior_rows,
                          const std::vector<char>& eligible,
                          const std::vector<char>& is_fixed,
                          const std::vector<int64_t>& initial,
                          const TaskExchangeOptions& options, int threads) {
  RestartResult result;
  TaskDesign design(pool, W, prior_rows);
  for (int64_t i : initial) design.Add(i);
  if (!design.positive_definite()) return result;
  result.history.push_back({SelectionStep::kInitial, -1, -1, design.log_det()});
  std::vector<double> a, b;
  const int t = pool.block_rows();
  int swaps = 0;
  for (; swaps < options.max_swaps; ++swaps) {
    const double threshold = options.min_improvement * design.value();
    int64_t x, y;
    const bool found =
        t == 3   ? BestSwap<3>(pool, design, eligible, is_fixed, threshold,
                             threads, &a, &b, &x, &y)
        : t == 6 ? BestSwap<6>(pool, design, eligible, is_fixed, threshold,
                               threads, &a, &b, &x, &y)
                 : BestSwap<Eigen::Dynamic>(pool, design, eligible, is_fixed,
                                            threshold, threads, &a, &b, &x, &y);
    if (!found) break;
    const double before = design.value();
    design.Add(x);
    if (!design.Remove(y) || !(design.value() < before)) {
      // Rounding made the predicted gain vanish: undo and stop.
      if (design.Contains(y)) {
        design.Remove(x);
      } else {
        design.Add(y);
        design.Remove(x);
      }
      break;
    }
    result.history.push_back(
        {SelectionStep::kExchange, x, y, design.log_det()});
  }
  result.hit_bound = swaps >= options.max_swaps && options.max_swaps > 0;
  result.design = design.poses();
  const double phi =
      TaskCriterionFromScratch(pool, W, prior_rows, result.design);
  result.ok = std::isfinite(phi);
  // BestOfRestarts keeps the largest log_det: -phi ranks by the criterion.
  result.log_det = -phi;
  return result;
}

void FinishTaskSummary(const CandidatePool& pool, const Eigen::MatrixXd& W,
                       const RowMatrixXd& prior_rows,
                       SelectionSummary* summary) {
  if (!summary->IsSolutionUsable()) return;
  summary->task_criterion =
      TaskCriterionFromScratch(pool, W, prior_rows, summary->design);
  summary->log_det = LogDetFromScratch(pool, summary->design);
}

}  // namespace

bool TaskExchange(const CandidatePool& pool, const Eigen::MatrixXd& W,
                  const RowMatrixXd& prior_rows,
                  const DesignConstraints& constraints,
                  const TaskExchangeOptions& options,
                  const TaskApproximateSummary* approximate,
                  SelectionSummary* summary) {
  internal::SelectionStart start;
  if (!internal::PrepareSelection(pool, constraints, options, "task_fedorov",
                                  summary, &start, prior_rows.rows())) {
    return false;
  }
  const std::vector<char>& eligible = start.eligible;
  const std::vector<char>& is_fixed = start.is_fixed;
  CHECK_EQ(W.rows(), pool.num_parameters());
  ApproximateDesignSummary rounding;
  if (approximate) {
    rounding.support = approximate->support;
    rounding.weights = approximate->weights;
  }
  const bool has_approximate = approximate && !rounding.support.empty();
  // The reduced pool: the poses of largest b_i under the approximate
  // design, its support and the fixed poses.
  const int64_t reduced_size = std::max<int64_t>(
      options.reduced_pool_size,
      options.reduced_pool_per_pose * static_cast<int64_t>(options.num_poses));
  std::unique_ptr<internal::SubPool> reduced;
  if (has_approximate && options.reduced_pool_size > 0 &&
      pool.size() > reduced_size) {
    const int p = pool.num_parameters();
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
    for (size_t k = 0; k < rounding.support.size(); ++k) {
      const auto X = pool.block(rounding.support[k]);
      M.noalias() += rounding.weights[k] * X.transpose() * X;
    }
    Eigen::LLT<Eigen::MatrixXd> llt(M);
    if (llt.info() == Eigen::Success) {
      const Eigen::MatrixXd V = llt.solve(Eigen::MatrixXd::Identity(p, p));
      const Eigen::MatrixXd G = V * W * V;
      Eigen::VectorXd bvalues(pool.size());
      internal::ForEachQuadraticForm(
          pool, G, options.num_threads,
          [&](int64_t i, const Eigen::MatrixXd& S) { bvalues[i] = S.trace(); });
      std::vector<char> keep = is_fixed;
      for (int64_t i : rounding.support) keep[i] = keep[i] || eligible[i];
      for (int64_t i :
           internal::TopByVariance(bvalues, eligible, reduced_size)) {
        keep[i] = 1;
      }
      reduced = std::make_unique<internal::SubPool>(pool, keep);
    }
  }
  const internal::WorkingSet work(pool, reduced.get(), constraints, eligible,
                                  is_fixed);
  const ApproximateDesignSummary work_rounding =
      reduced ? reduced->Restrict(rounding) : rounding;
  std::vector<std::string> notes(options.restarts);
  RestartResult best = internal::BestOfRestarts(
      options.restarts, options.num_threads,
      [&](int r, int threads) {
        std::vector<int64_t> initial;
        if (prior_rows.rows() > 0) {
          // The prior may make up for a design too small to be non-singular
          // alone, so the start is not completed on the design's own M: the
          // fixed poses and a random draw (the restart fails if prior and
          // start are singular together).
          initial = work.constraints.fixed;
          std::vector<int64_t> candidates;
          for (int64_t i = 0; i < work.pool.size(); ++i) {
            if (work.eligible[i]) candidates.push_back(i);
          }
          Random random(Random::StreamSeed(options.seed, r));
          for (int64_t k : random.SampleWithoutReplacement(
                   candidates.size(), options.num_poses - initial.size())) {
            initial.push_back(candidates[k]);
          }
        } else {
          initial = internal::InitialDesign(
              work, options.num_poses, Random::StreamSeed(options.seed, r),
              has_approximate ? &work_rounding : nullptr, r > 0, threads,
              &notes[r]);
        }
        if (initial.empty()) return RestartResult();
        return TaskRestart(work.pool, W, prior_rows, work.eligible,
                           work.is_fixed, initial, options, threads);
      },
      options.progress);
  std::string note = internal::NoteOf(notes, best.restart);
  if (reduced && best.ok) {
    // Polish over the whole pool.
    RestartResult polished =
        TaskRestart(pool, W, prior_rows, eligible, is_fixed,
                    reduced->ToFull(best.design), options, options.num_threads);
    std::vector<SelectionStep> history = best.history;
    reduced->ToFull(&history);
    const size_t reduced_steps = history.size();
    if (polished.ok) {
      history.insert(history.end(), polished.history.begin() + 1,
                     polished.history.end());
      polished.history = std::move(history);
      polished.restart = best.restart;
      polished.hit_bound = polished.hit_bound || best.hit_bound;
      best = std::move(polished);
    }
    const std::string polish =
        "restarts on a reduced pool of " + std::to_string(reduced->size()) +
        " poses, then " + std::to_string(best.history.size() - reduced_steps) +
        " swaps over the whole pool";
    note = note.empty() ? polish : note + "; " + polish;
  }
  internal::FinishSummary(best, options.restarts, start.time, note, summary);
  FinishTaskSummary(pool, W, prior_rows, summary);
  return summary->IsSolutionUsable();
}

bool TaskGreedy(const CandidatePool& pool, const Eigen::MatrixXd& W,
                const RowMatrixXd& prior_rows,
                const DesignConstraints& constraints, int num_poses,
                int num_threads, SelectionSummary* summary,
                std::vector<double>* criterion_by_size) {
  internal::SelectionStart start;
  GreedyOptions options;
  options.num_poses = num_poses;
  if (!internal::PrepareSelection(pool, constraints, options, "task_greedy",
                                  summary, &start, prior_rows.rows())) {
    return false;
  }
  CHECK_EQ(W.rows(), pool.num_parameters());
  if (criterion_by_size) criterion_by_size->clear();
  const double eps = internal::RegularisingRidge(pool);
  // While M (prior and design) is singular the additions are scored on
  // M + eps I; the design then continues on M itself.
  std::unique_ptr<TaskDesign> design =
      std::make_unique<TaskDesign>(pool, W, prior_rows);
  bool ridged = !design->positive_definite();
  if (ridged) design = std::make_unique<TaskDesign>(pool, W, prior_rows, eps);
  InformationMatrix plain(pool.num_parameters());
  if (prior_rows.rows() > 0) plain.Add(prior_rows);
  RestartResult result;
  auto add = [&](int64_t pose) {
    design->Add(pose);
    plain.Add(pool.block(pose));
    if (ridged && plain.positive_definite()) {
      auto fresh = std::make_unique<TaskDesign>(pool, W, prior_rows);
      for (int64_t i : design->poses()) fresh->Add(i);
      design = std::move(fresh);
      ridged = false;
    }
    if (criterion_by_size) {
      criterion_by_size->push_back(ridged ? kInf : design->value());
    }
  };
  for (int64_t f : constraints.fixed) add(f);
  const int t = pool.block_rows();
  const int tt = t * t;
  std::vector<double> a, b;
  while (design->size() < num_poses) {
    design->AllQuadraticForms(num_threads, &a, &b);
    int64_t best = -1;
    double best_change = kInf;
    for (int64_t x = 0; x < pool.size(); ++x) {
      if (!start.eligible[x] || design->Contains(x)) continue;
      const double c =
          t == 3 ? AddChangeOf<3>(a.data() + x * tt, b.data() + x * tt, t)
                 : AddChangeOf<Eigen::Dynamic>(a.data() + x * tt,
                                               b.data() + x * tt, t);
      if (c < best_change) {
        best_change = c;
        best = x;
      }
    }
    if (best < 0) break;
    add(best);
    result.history.push_back(
        {SelectionStep::kAdd, best, -1, design->log_det()});
  }
  result.design = design->poses();
  const double phi =
      TaskCriterionFromScratch(pool, W, prior_rows, result.design);
  result.ok = std::isfinite(phi);
  result.log_det = -phi;
  internal::FinishSummary(result, 1, start.time, "", summary);
  FinishTaskSummary(pool, W, prior_rows, summary);
  return summary->IsSolutionUsable();
}

}  // namespace activecal
