// Fedorov exchange (fast form of Nguyen & Miller 1992), with the reduced
// pool and the polish over the whole pool.

#include "activecal/selection/fedorov.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/selection/criteria.h"
#include "selection_internal.h"
#include "sub_pool.h"

namespace activecal {

bool FedorovOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (num_poses <= 0)
    msg << "num_poses must be > 0, got " << num_poses;
  else if (restarts <= 0)
    msg << "restarts must be > 0, got " << restarts;
  else if (max_swaps < 0)
    msg << "max_swaps must be >= 0";
  else if (refresh_interval <= 0)
    msg << "refresh_interval must be > 0";
  else if (reduced_pool_per_pose < 0)
    msg << "reduced_pool_per_pose must be >= 0";
  else if (max_polish_rounds <= 0)
    msg << "max_polish_rounds must be > 0";
  else if (!(min_improvement >= 0))
    msg << "min_improvement must be >= 0";
  if (msg.tellp() == 0) return true;
  if (error) *error = msg.str();
  return false;
}

namespace {

using internal::RestartResult;

struct YEntry {
  double trace;
  int64_t pose;
};

RestartResult FedorovRestart(const CandidatePool& pool,
                             const std::vector<char>& eligible,
                             const std::vector<char>& is_fixed,
                             std::vector<int64_t> initial,
                             const FedorovOptions& options, int threads) {
  internal::RestartResult result;
  const int t = pool.block_rows();
  const int p = pool.num_parameters();
  const int tt = t * t;
  const int64_t m = pool.size();
  Design design(pool);
  for (int64_t i : initial) design.Add(i);
  if (!design.information().positive_definite()) return result;
  std::vector<double> D(m * tt);
  auto refresh_all = [&]() {
    design.Rebuild();
    internal::ForEachQuadraticForm(
        pool, design.information().inverse(), threads,
        [&](int64_t i, const Eigen::MatrixXd& S) {
          Eigen::Map<Eigen::MatrixXd>(D.data() + i * tt, t, t) = S;
        });
  };
  auto trace_of = [&](int64_t i) {
    double s = 0;
    for (int k = 0; k < t; ++k) s += D[i * tt + k * t + k];
    return s;
  };
  refresh_all();
  result.history.push_back({SelectionStep::kInitial, -1, -1, design.log_det()});
  int since_refresh = 0;
  constexpr int64_t kBlock = 256;
  int swaps = 0;
  for (;;) {
    for (; swaps < options.max_swaps; ++swaps) {
      std::vector<YEntry> ys;
      for (int64_t y : design.poses()) {
        if (!is_fixed[y]) ys.push_back({trace_of(y), y});
      }
      if (ys.empty()) break;
      std::sort(ys.begin(), ys.end(), [](const YEntry& a, const YEntry& b) {
        return a.trace < b.trace || (a.trace == b.trace && a.pose < b.pose);
      });
      const double min_try = ys[0].trace;
      const double threshold0 = internal::ImprovementThreshold(
          design.log_det(), options.min_improvement);
      std::vector<YEntry> xs;
      for (int64_t x = 0; x < m; ++x) {
        if (!eligible[x] || design.Contains(x)) continue;
        const double tr = trace_of(x);
        if (tr - min_try > threshold0) xs.push_back({tr, x});
      }
      std::sort(xs.begin(), xs.end(), [](const YEntry& a, const YEntry& b) {
        return a.trace > b.trace || (a.trace == b.trace && a.pose < b.pose);
      });
      const Eigen::MatrixXd& V = design.information().inverse();
      double best_lr = threshold0;
      int64_t best_x = -1, best_y = -1;
      std::vector<double> item_lr(kBlock);
      std::vector<int64_t> item_y(kBlock);
      // Best swap among the first num_x candidates and num_y design poses.
      auto scan = [&](size_t num_x, size_t num_y) {
        for (size_t b = 0; b < num_x; b += kBlock) {
          if (xs[b].trace - min_try <= best_lr) break;
          const double threshold = best_lr;
          const int64_t count = std::min<int64_t>(kBlock, num_x - b);
          ParallelFor(count, threads, [&](int64_t ib, int64_t ie, int) {
            Eigen::MatrixXd Sx(t, t), Sx_inv(t, t), Dxy(t, t), T(t, t);
            RowMatrixXd Wx(t, p);
            for (int64_t k = ib; k < ie; ++k) {
              item_lr[k] = -std::numeric_limits<double>::infinity();
              item_y[k] = -1;
              const int64_t x = xs[b + k].pose;
              const double trx = xs[b + k].trace;
              if (trx - min_try <= threshold) continue;
              Sx = Eigen::Map<const Eigen::MatrixXd>(D.data() + x * tt, t, t);
              Sx.diagonal().array() += 1.0;
              const double gain = LogDetSpd(Sx);
              if (!(gain > threshold)) continue;
              Sx_inv = Sx.inverse();
              Wx.noalias() = pool.block(x).lazyProduct(V);
              for (size_t j = 0; j < num_y; ++j) {
                const YEntry& y = ys[j];
                if (trx - y.trace <= threshold) break;
                Dxy.noalias() = Wx.lazyProduct(pool.block(y.pose).transpose());
                T = -Eigen::Map<const Eigen::MatrixXd>(D.data() + y.pose * tt,
                                                       t, t);
                T.diagonal().array() += 1.0;
                T.noalias() += Dxy.transpose() * Sx_inv * Dxy;
                const double lr = gain + LogDetSpd(T);
                if (lr > item_lr[k]) {
                  item_lr[k] = lr;
                  item_y[k] = y.pose;
                }
              }
            }
          });
          for (int64_t k = 0; k < count; ++k) {
            if (item_lr[k] > best_lr) {
              best_lr = item_lr[k];
              best_x = xs[b + k].pose;
              best_y = item_y[k];
            }
          }
        }
      };
      // KL exchange first (Atkinson & Donev): the weakest design poses
      // against the strongest candidates. Only when no such swap helps is
      // every pair scanned, so the result is a local optimum over all swaps.
      const size_t kl_y =
          std::min<size_t>(ys.size(), std::max<size_t>(4, ys.size() / 8));
      const size_t kl_x = std::min<size_t>(xs.size(), 64 * kl_y);
      if (options.kl_exchange) scan(kl_x, kl_y);
      if (best_x < 0) scan(xs.size(), ys.size());
      if (best_x < 0) break;

      // The update terms, from V before the swap.
      const auto X = pool.block(best_x);
      const auto Y = pool.block(best_y);
      const Eigen::MatrixXd Wa = V * X.transpose();
      Eigen::MatrixXd Sa = X * Wa;
      Sa.diagonal().array() += 1.0;
      const Eigen::MatrixXd Sa_inv = Sa.inverse();
      const Eigen::MatrixXd V1 = V - Wa * Sa_inv * Wa.transpose();
      const Eigen::MatrixXd Wr = V1 * Y.transpose();
      Eigen::MatrixXd Sr = -(Y * Wr);
      Sr.diagonal().array() += 1.0;
      const Eigen::MatrixXd Sr_inv = Sr.inverse();

      design.Add(best_x);
      if (!design.Remove(best_y)) {
        // Cannot happen for an improving swap; stop rather than loop.
        design.Remove(best_x);
        break;
      }
      result.history.push_back(
          {SelectionStep::kExchange, best_x, best_y, design.log_det()});
      if (++since_refresh >= options.refresh_interval) {
        refresh_all();
        since_refresh = 0;
        continue;
      }
      Eigen::MatrixXd Wb(p, 2 * t);
      Wb.leftCols(t) = Wa;
      Wb.rightCols(t) = Wr;
      constexpr int64_t kChunk = 512;
      const int64_t chunks = (m + kChunk - 1) / kChunk;
      ParallelFor(chunks, threads, [&](int64_t cb, int64_t ce, int) {
        RowMatrixXd P;
        for (int64_t c = cb; c < ce; ++c) {
          const int64_t begin = c * kChunk;
          const int64_t n = std::min(kChunk, m - begin);
          Eigen::Map<const RowMatrixXd> Xc(
              pool.stacked().data() + begin * t * p, n * t, p);
          P.noalias() = Xc * Wb;
          for (int64_t k = 0; k < n; ++k) {
            Eigen::Map<Eigen::MatrixXd> Dj(D.data() + (begin + k) * tt, t, t);
            const auto Pa = P.block(k * t, 0, t, t);
            const auto Pr = P.block(k * t, t, t, t);
            Dj.noalias() -= Pa * Sa_inv * Pa.transpose();
            Dj.noalias() += Pr * Sr_inv * Pr.transpose();
          }
        }
      });
    }
    // No single swap helps: try larger excursions, and swap again after one.
    // Each counts as a step against max_swaps.
    if (swaps >= options.max_swaps) {
      result.hit_bound = options.max_swaps > 0;  // 0: rounding only
      break;
    }
    if (options.max_excursion < 2) break;
    std::vector<int64_t> poses = design.poses();
    SelectionStep step;
    if (!internal::TryExcursion(pool, eligible, is_fixed, 2,
                                options.max_excursion, options.min_improvement,
                                threads, &poses, &step)) {
      break;
    }
    Design next(pool);
    for (int64_t i : poses) next.Add(i);
    design = std::move(next);
    refresh_all();
    since_refresh = 0;
    ++swaps;
    step.log_det = design.log_det();
    result.history.push_back(step);
  }
  result.design = design.poses();
  result.log_det = LogDetFromScratch(pool, result.design);
  result.ok = std::isfinite(result.log_det);
  return result;
}

// Swaps over the polish_pool_size poses of largest variance under the
// current design, re-ranked after each round, until a round makes no swap
// or max_polish_rounds have run.
RestartResult PolishInRounds(const CandidatePool& pool,
                             const std::vector<char>& eligible,
                             const std::vector<char>& is_fixed,
                             std::vector<int64_t> design,
                             const FedorovOptions& options) {
  RestartResult result;
  std::vector<SelectionStep> history;
  for (int round = 0;; ++round) {
    if (round >= options.max_polish_rounds) {
      result.hit_bound = true;
      break;
    }
    const int p = pool.num_parameters();
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
    for (int64_t i : design) {
      const auto X = pool.block(i);
      M.noalias() += X.transpose() * X;
    }
    Eigen::VectorXd d;
    if (!internal::VariancesUnder(pool, M, options.num_threads, &d)) break;
    // The design, the fixed poses and the eligible poses of largest
    // variance outside them.
    std::vector<char> keep = is_fixed, candidate(pool.size());
    for (int64_t i : design) keep[i] = 1;
    for (int64_t i = 0; i < pool.size(); ++i) {
      candidate[i] = eligible[i] && !keep[i];
    }
    for (int64_t i :
         internal::TopByVariance(d, candidate, options.polish_pool_size)) {
      keep[i] = 1;
    }
    const internal::SubPool sub(pool, keep);
    RestartResult r = FedorovRestart(sub.pool(), sub.Restrict(eligible),
                                     sub.Restrict(is_fixed), sub.ToSub(design),
                                     options, options.num_threads);
    if (!r.ok) break;
    r.design = sub.ToFull(r.design);
    sub.ToFull(&r.history);
    const bool changed = r.history.size() > 1;
    history.insert(history.end(), r.history.begin() + 1, r.history.end());
    design = r.design;
    r.history.clear();
    r.history.push_back(SelectionStep());  // the caller skips entry 0
    r.history.insert(r.history.end(), history.begin(), history.end());
    result = std::move(r);
    if (!changed) break;
  }
  return result;
}

}  // namespace

bool FedorovExchange(const CandidatePool& pool,
                     const DesignConstraints& constraints,
                     const FedorovOptions& options,
                     const ApproximateDesignSummary* approximate,
                     SelectionSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<char> eligible, is_fixed;
  if (!internal::PrepareSelection(pool, constraints, options, "fedorov",
                                  summary, &eligible, &is_fixed)) {
    return false;
  }
  // With an approximate design and a large pool, the restarts swap within
  // a reduced pool first: the approximate design's support and the poses of
  // largest variance under it, where good exact designs live. The best
  // result is then polished by swaps over the whole pool, so it is a local
  // optimum of the full problem either way.
  const int64_t reduced_size = std::max<int64_t>(
      options.reduced_pool_size,
      options.reduced_pool_per_pose * static_cast<int64_t>(options.num_poses));
  std::unique_ptr<internal::SubPool> reduced;
  ApproximateDesignSummary reduced_approximate;
  if (approximate && !approximate->support.empty() &&
      options.reduced_pool_size > 0 && pool.size() > reduced_size) {
    const int p = pool.num_parameters();
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
    for (size_t k = 0; k < approximate->support.size(); ++k) {
      const auto X = pool.block(approximate->support[k]);
      M.noalias() += approximate->weights[k] * X.transpose() * X;
    }
    Eigen::VectorXd d;
    if (internal::VariancesUnder(pool, M, options.num_threads, &d)) {
      // The fixed poses, the eligible support and the eligible poses of
      // largest variance.
      std::vector<char> keep = is_fixed;
      for (int64_t i : approximate->support) keep[i] = keep[i] || eligible[i];
      for (int64_t i : internal::TopByVariance(d, eligible, reduced_size)) {
        keep[i] = 1;
      }
      reduced = std::make_unique<internal::SubPool>(pool, keep);
      reduced_approximate = reduced->Restrict(*approximate);
    }
  }
  const CandidatePool& work_pool = reduced ? reduced->pool() : pool;
  DesignConstraints work_constraints;
  work_constraints.fixed =
      reduced ? reduced->ToSub(constraints.fixed) : constraints.fixed;
  const std::vector<char> work_eligible =
      reduced ? reduced->Restrict(eligible) : eligible;
  const std::vector<char> work_fixed =
      reduced ? reduced->Restrict(is_fixed) : is_fixed;
  const ApproximateDesignSummary* work_approximate =
      reduced ? &reduced_approximate : approximate;
  std::vector<std::string> notes(options.restarts);
  RestartResult best = internal::BestOfRestarts(
      options.restarts, options.num_threads,
      [&](int r, int threads) {
        const std::vector<int64_t> initial = internal::InitialDesign(
            work_pool, work_constraints, work_eligible, options.num_poses,
            Random::StreamSeed(options.seed, r), work_approximate, r > 0,
            threads, &notes[r]);
        if (initial.empty()) return RestartResult();
        return FedorovRestart(work_pool, work_eligible, work_fixed, initial,
                              options, threads);
      },
      options.progress);
  const auto restarts_done = std::chrono::steady_clock::now();
  std::string timing;
  if (reduced && best.ok) {
    const std::vector<int64_t> initial = reduced->ToFull(best.design);
    RestartResult polished;
    if (options.polish_pool_size <= 0 ||
        pool.size() <= options.polish_pool_size) {
      polished = FedorovRestart(pool, eligible, is_fixed, initial, options,
                                options.num_threads);
    } else {
      polished = PolishInRounds(pool, eligible, is_fixed, initial, options);
    }
    std::vector<SelectionStep> history = best.history;
    reduced->ToFull(&history);
    if (!polished.history.empty()) {
      history.insert(history.end(), polished.history.begin() + 1,
                     polished.history.end());
    }
    polished.history = std::move(history);
    polished.restart = best.restart;
    const size_t reduced_steps = best.history.size();
    polished.hit_bound = polished.hit_bound || best.hit_bound;
    if (polished.ok) best = std::move(polished);
    std::ostringstream msg;
    msg.precision(3);
    msg << "restarts on a reduced pool of " << reduced->size() << " poses "
        << std::chrono::duration<double>(restarts_done - start).count()
        << " s, then " << best.history.size() - reduced_steps
        << (pool.size() <= options.polish_pool_size ||
                    options.polish_pool_size <= 0
                ? " swaps over the whole pool "
                : " swaps in rounds over the " +
                      std::to_string(options.polish_pool_size) +
                      " poses of largest variance ")
        << std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         restarts_done)
               .count()
        << " s";
    timing = msg.str();
  }
  std::string note = internal::NoteOf(notes, best.restart);
  if (!timing.empty()) note = note.empty() ? timing : note + "; " + timing;
  internal::FinishSummary(best, options.restarts, start, note, summary);
  return summary->IsSolutionUsable();
}

}  // namespace activecal
