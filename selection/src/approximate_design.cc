// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/selection/approximate_design.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/core/validation.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/information_matrix.h"
#include "selection_internal.h"
#include "sub_pool.h"
#include "weight_exchange.h"

namespace activecal {

bool ApproximateDesignOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (!(tolerance > 0)) {
    msg << "tolerance must be > 0, got " << tolerance;
  } else if (max_rounds <= 0 || max_inner_iterations <= 0) {
    msg << "max_rounds and max_inner_iterations must be > 0";
  }
  return FinishValidation(msg, error);
}

namespace {

using internal::WeightedInformation;

Eigen::MatrixXd Outer(const CandidatePool& pool, int64_t i,
                      RowMatrixXd* buffer) {
  // A view for a double pool (as block(i)), widened for a float one.
  const auto X = pool.Rows(i, 1, buffer);
  return X.transpose() * X;
}

// The weights on a working set of a pool, their information matrix, and
// the variances of every pool pose under it (the last sweep).
struct SolveState {
  std::vector<int64_t> working;
  std::vector<double> w;
  WeightedInformation info;
  Eigen::VectorXd d;
};

// The rounds of the solver on `pool` (eligible poses only): inner
// iterations on the working set, then a sweep over the pool that adds the
// worst violators. Starts from *state when warm (its working set and
// weights: M(w) must be non-singular), else from the poses of largest
// variance under uniform weights. Runs until max d <= p (1 + tolerance)
// over the pool or summary->rounds reaches options.max_rounds; adds to
// summary->rounds, inner_iterations and full_sweeps (when count_sweeps).
// Returns false with *error on failure.
bool SolveOnPool(const CandidatePool& pool, const std::vector<char>& eligible,
                 const ApproximateDesignOptions& options, bool warm,
                 bool count_sweeps, SolveState* state,
                 ApproximateDesignSummary* summary, std::string* error) {
  const int p = pool.num_parameters();
  const int t = pool.block_rows();
  std::vector<int64_t>& working = state->working;
  std::vector<double>& w = state->w;
  WeightedInformation& info = state->info;
  Eigen::VectorXd& d = state->d;
  RowMatrixXd buffer;
  // The k eligible poses outside `skip` of largest variance.
  auto top_by_variance = [&](int k, const std::vector<char>& skip) {
    std::vector<char> candidate(pool.size());
    for (int64_t i = 0; i < pool.size(); ++i) {
      candidate[i] = eligible[i] && !skip[i];
    }
    return internal::TopByVariance(d, candidate, k);
  };
  auto rebuild = [&]() {
    info.M = Eigen::MatrixXd::Zero(p, p);
    for (size_t k = 0; k < working.size(); ++k) {
      if (w[k] > 0) info.M.noalias() += w[k] * Outer(pool, working[k], &buffer);
    }
    return info.Factor();
  };
  std::vector<char> in_set(pool.size(), 0);
  // The largest variance over the pool at the last sweep (for the warm
  // start: the caller's, if it made one).
  double pool_max = summary->max_variance;
  if (warm) {
    for (int64_t i : working) in_set[i] = 1;
    if (!rebuild()) {
      *error = "the warm start's information matrix is singular";
      return false;
    }
  } else {
    // Start: the poses of largest variance under uniform weights on the
    // pool.
    Eigen::MatrixXd M0 = Eigen::MatrixXd::Zero(p, p);
    int64_t count = 0;
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (!eligible[i]) continue;
      const auto X = pool.Rows(i, 1, &buffer);
      M0.noalias() += X.transpose() * X;
      ++count;
    }
    M0 /= static_cast<double>(count);
    Eigen::LLT<Eigen::MatrixXd> llt0(M0);
    if (!std::isfinite(LogDetSpd(M0))) {
      *error =
          "the pool's information matrix is singular: no design identifies "
          "all " +
          std::to_string(p) + " parameters";
      return false;
    }
    ComputeVariances(pool, llt0.solve(Eigen::MatrixXd::Identity(p, p)),
                     options.num_threads, &d);
    if (count_sweeps) ++summary->full_sweeps;
    working = top_by_variance(4 * p, in_set);
    if (!working.empty()) pool_max = d[working.front()];
    for (int64_t i : working) in_set[i] = 1;
    w.assign(working.size(), 1.0 / working.size());
    // Grow the start until M(w) is non-singular.
    while (!rebuild()) {
      std::vector<int64_t> more = top_by_variance(p, in_set);
      if (more.empty()) {
        *error = "the eligible pool cannot identify all parameters";
        return false;
      }
      for (int64_t i : more) {
        in_set[i] = 1;
        working.push_back(i);
      }
      w.assign(working.size(), 1.0 / working.size());
    }
  }

  const double target = p * (1.0 + options.tolerance);
  const double inner_target = p * (1.0 + 0.5 * options.tolerance);
  Eigen::VectorXd dw;
  while (summary->rounds < options.max_rounds) {
    if (options.progress) options.progress(summary->rounds, options.max_rounds);
    // Inner: optimise the weights on the working set.
    const int64_t nw = static_cast<int64_t>(working.size());
    RowMatrixXd Xw(nw * t, p);
    for (int64_t k = 0; k < nw; ++k) {
      Xw.middleRows(k * t, t) = pool.Rows(working[k], 1, &buffer);
    }
    internal::WeightExchangeOptions inner;
    // The working set is solved only as far as the last sweep's violation
    // warrants: to a quarter of the pool's excess over p (the tolerance
    // at the end). The working set changes after every sweep, so solving
    // it further is wasted; the stopping test is over the whole pool.
    inner.target = std::isfinite(pool_max)
                       ? std::max(inner_target, p + 0.25 * (pool_max - p))
                       : inner_target;
    inner.max_iterations = options.max_inner_iterations;
    inner.num_top = p;
    Random random(Random::StreamSeed(options.seed, summary->rounds));
    ++summary->rounds;
    if (!internal::ExchangeWeights(Xw, t, inner, &random, &w, &info, &dw,
                                   &summary->inner_iterations, error)) {
      return false;
    }
    // Outer: check the whole pool.
    ComputeVariances(pool, info.V, options.num_threads, &d);
    if (count_sweeps) ++summary->full_sweeps;
    int64_t arg = -1;
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (eligible[i] && (arg < 0 || d[i] > d[arg])) arg = i;
    }
    summary->max_variance = pool_max = d[arg];
    summary->log_det = info.log_det;
    if (d[arg] <= target) break;
    // Add the worst violators, drop dead weight that is far from optimal.
    std::vector<int64_t> next;
    std::vector<double> next_w;
    for (size_t k = 0; k < working.size(); ++k) {
      if (w[k] > 0 || d[working[k]] > 0.9 * p) {
        next.push_back(working[k]);
        next_w.push_back(w[k]);
      } else {
        in_set[working[k]] = 0;
      }
    }
    for (int64_t i : top_by_variance(4 * p, in_set)) {
      if (d[i] <= inner_target) break;
      in_set[i] = 1;
      next.push_back(i);
      next_w.push_back(0.0);
    }
    working = std::move(next);
    w = std::move(next_w);
  }
  return true;
}

}  // namespace

int64_t ApproximateDesignOptions::ResolvedSubsampleSize(
    int num_parameters) const {
  if (subsample_size > 0) return subsample_size;
  return std::max<int64_t>(20000, 200 * static_cast<int64_t>(num_parameters));
}

bool SolveApproximateDesign(const CandidatePool& pool,
                            const DesignConstraints& constraints,
                            const ApproximateDesignOptions& options,
                            ApproximateDesignSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  *summary = ApproximateDesignSummary();
  const int p = pool.num_parameters();
  summary->num_parameters = p;
  std::string error;
  if (!options.IsValid(&error)) {
    summary->message = error;
    return false;
  }
  std::vector<char> eligible;
  const int min_poses = (p + pool.block_rows() - 1) / pool.block_rows();
  if (!PrepareCandidates(pool,
                         std::max<int>(min_poses, constraints.fixed.size()),
                         constraints, &eligible, &error)) {
    summary->message = error;
    return false;
  }
  for (int64_t f : constraints.fixed) eligible[f] = 1;
  const int64_t num_eligible =
      std::count(eligible.begin(), eligible.end(), char{1});
  const int64_t subsample = options.ResolvedSubsampleSize(p);
  const double target = p * (1.0 + options.tolerance);

  SolveState state;
  bool solved_on_subsample = false;
  if (num_eligible > subsample) {
    // Phase 1: a random subsample of the eligible poses (selection
    // sampling, Knuth's algorithm S: every subset equally likely), solved
    // to the tolerance with sweeps over the subsample only.
    std::vector<char> keep(pool.size(), 0);
    Random random(options.seed);
    int64_t needed = subsample, seen = 0;
    for (int64_t i = 0; i < pool.size() && needed > 0; ++i) {
      if (!eligible[i]) continue;
      if (random.Uniform() * (num_eligible - seen) < needed) {
        keep[i] = 1;
        --needed;
      }
      ++seen;
    }
    const int64_t cap = options.max_added_per_sweep > 0
                            ? options.max_added_per_sweep
                            : 100 * static_cast<int64_t>(p);
    bool warm = false;
    std::vector<int64_t> working_full;
    std::vector<double> w_full;
    Eigen::VectorXd d;
    for (;;) {
      // Phase 2: solve on the candidate set warm-started from the last
      // weights, then one sweep over the whole pool; its violators join
      // the candidate set (column generation).
      const internal::SubPool sub(pool, keep);
      SolveState sub_state;
      if (warm) {
        sub_state.working = sub.ToSub(working_full);
        sub_state.w = w_full;
      }
      if (!SolveOnPool(sub.pool(), sub.Restrict(eligible), options, warm,
                       /*count_sweeps=*/false, &sub_state, summary, &error)) {
        if (!warm) break;  // e.g. a singular subsample: solve on the pool
        summary->message = error;
        return false;
      }
      solved_on_subsample = true;
      ComputeVariances(pool, sub_state.info.V, options.num_threads, &d);
      ++summary->full_sweeps;
      int64_t arg = -1;
      for (int64_t i = 0; i < pool.size(); ++i) {
        if (eligible[i] && (arg < 0 || d[i] > d[arg])) arg = i;
      }
      // The certificate: over the whole pool, from this sweep.
      summary->max_variance = d[arg];
      summary->log_det = sub_state.info.log_det;
      state.info = sub_state.info;
      state.working = sub.ToFull(sub_state.working);
      state.w = sub_state.w;
      if (d[arg] <= target || summary->rounds >= options.max_rounds) break;
      std::vector<char> violating(pool.size(), 0);
      for (int64_t i = 0; i < pool.size(); ++i) {
        violating[i] = eligible[i] && !keep[i] && d[i] > target;
      }
      const std::vector<int64_t> added =
          internal::TopByVariance(d, violating, cap);
      if (added.empty()) break;  // the candidate set's solve fell short
      for (int64_t i : added) keep[i] = 1;
      // The warm start: the support, and the worst violators at weight 0
      // (the rounds bring in the others from the candidate set).
      working_full.clear();
      w_full.clear();
      for (size_t k = 0; k < state.working.size(); ++k) {
        if (state.w[k] > 0) {
          working_full.push_back(state.working[k]);
          w_full.push_back(state.w[k]);
        }
      }
      for (size_t k = 0; k < added.size() && k < 4 * static_cast<size_t>(p);
           ++k) {
        working_full.push_back(added[k]);
        w_full.push_back(0.0);
      }
      warm = true;
    }
  }
  if (!solved_on_subsample) {
    // The whole pool at once (every sweep is over the whole pool).
    if (!SolveOnPool(pool, eligible, options, /*warm=*/false,
                     /*count_sweeps=*/true, &state, summary, &error)) {
      summary->message = error;
      return false;
    }
  }
  for (size_t k = 0; k < state.working.size(); ++k) {
    if (state.w[k] > 0) {
      summary->support.push_back(state.working[k]);
      summary->weights.push_back(state.w[k]);
    }
  }
  summary->log_det_upper_bound =
      summary->log_det + p * std::log(summary->max_variance / p);
  summary->efficiency_lower_bound = p / summary->max_variance;
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  std::ostringstream msg;
  msg << "max variance " << summary->max_variance << " (p = " << p << ") on "
      << summary->support.size() << " support poses after " << summary->rounds
      << " rounds, " << summary->inner_iterations << " inner iterations, "
      << summary->full_sweeps << " full-pool sweeps";
  if (solved_on_subsample) {
    msg << " (started on a subsample of " << subsample << " of " << num_eligible
        << " poses)";
  }
  summary->termination_type = summary->max_variance <= target
                                  ? TerminationType::kConvergence
                                  : TerminationType::kNoConvergence;
  if (summary->termination_type != TerminationType::kConvergence) {
    msg << "; tolerance not reached within the round bound (bounds still "
           "hold)";
  }
  summary->message = msg.str();
  return true;
}

std::string ApproximateDesignSummary::BriefReport() const {
  std::ostringstream out;
  out << "activecal approximate D-optimal design: "
      << TerminationTypeToString(termination_type) << "\n  " << message
      << "\n  log10 det M(w) = " << log_det / std::log(10.0)
      << ", upper bound on log10 det M* = "
      << log_det_upper_bound / std::log(10.0)
      << ", efficiency of w >= " << efficiency_lower_bound << ", " << seconds
      << " s\n";
  return out.str();
}

bool CertifyDesign(const CandidatePool& pool,
                   const DesignConstraints& constraints,
                   const ApproximateDesignSummary* approximate, int num_threads,
                   SelectionSummary* summary, double* exact_log_det) {
  const int p = pool.num_parameters();
  const int t = pool.block_rows();
  const double N = static_cast<double>(summary->design.size());
  RowMatrixXd buffer;
  // M of a weighted set of poses from their exact blocks.
  auto exact_information = [&](const std::vector<int64_t>& poses,
                               const std::vector<double>* weights) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
    for (size_t k = 0; k < poses.size(); ++k) {
      const auto X = pool.ExactRows(poses[k], 1, &buffer);
      if (weights) {
        if ((*weights)[k] > 0)
          M.noalias() += (*weights)[k] * (X.transpose() * X);
      } else {
        M.noalias() += X.transpose() * X;
      }
    }
    return M;
  };
  const Eigen::MatrixXd M = exact_information(summary->design, nullptr);
  const double log_det = LogDetSpd(M);
  if (!std::isfinite(log_det)) return false;
  if (exact_log_det) *exact_log_det = log_det;
  const Eigen::MatrixXd V =
      Eigen::LLT<Eigen::MatrixXd>(M).solve(Eigen::MatrixXd::Identity(p, p));
  auto counted = [&](int64_t i) {
    return !(constraints.excluded && constraints.excluded(i));
  };
  double max_d = 0;
  // Bound (1) of the approximate design over the blocks certified.
  double approximate_bound = std::numeric_limits<double>::infinity();
  if (approximate && std::isfinite(approximate->log_det_upper_bound) &&
      pool.has_exact_source() && !approximate->support.empty()) {
    // Its bound is for the stored blocks: recompute it over the exact ones,
    // both variance functions in one streamed sweep of the exact blocks.
    const Eigen::MatrixXd Mw =
        exact_information(approximate->support, &approximate->weights);
    const double log_det_w = LogDetSpd(Mw);
    const bool use_w = std::isfinite(log_det_w);
    const Eigen::MatrixXd Vw =
        use_w ? Eigen::MatrixXd(Eigen::LLT<Eigen::MatrixXd>(Mw).solve(
                    Eigen::MatrixXd::Identity(p, p)))
              : V;
    const int64_t n = pool.size();
    constexpr int64_t kChunk = 512;
    const int64_t num_chunks = (n + kChunk - 1) / kChunk;
    // Per-chunk maxima, reduced after: the same for any thread count.
    std::vector<double> chunk_d(num_chunks, 0.0), chunk_dw(num_chunks, 0.0);
    ParallelFor(num_chunks, num_threads, [&](int64_t cb, int64_t ce, int) {
      RowMatrixXd rows, W, Ww;
      for (int64_t c = cb; c < ce; ++c) {
        const int64_t begin = c * kChunk;
        const int64_t count = std::min(kChunk, n - begin);
        const auto X = pool.ExactRows(begin, count, &rows);
        W.noalias() = X * V;
        Ww.noalias() = X * Vw;
        const Eigen::VectorXd r = W.cwiseProduct(X).rowwise().sum();
        const Eigen::VectorXd rw = Ww.cwiseProduct(X).rowwise().sum();
        for (int64_t k = 0; k < count; ++k) {
          if (!counted(begin + k)) continue;
          chunk_d[c] = std::max(chunk_d[c], r.segment(k * t, t).sum());
          chunk_dw[c] = std::max(chunk_dw[c], rw.segment(k * t, t).sum());
        }
      }
    });
    double max_dw = 0;
    for (int64_t c = 0; c < num_chunks; ++c) {
      max_d = std::max(max_d, chunk_d[c]);
      max_dw = std::max(max_dw, chunk_dw[c]);
    }
    if (use_w) approximate_bound = log_det_w + p * std::log(max_dw / p);
  } else {
    Eigen::VectorXd d;
    ComputeVariances(pool, V, num_threads, &d, PoolReading::kExact);
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (counted(i)) max_d = std::max(max_d, d[i]);
    }
    if (approximate && std::isfinite(approximate->log_det_upper_bound)) {
      approximate_bound = approximate->log_det_upper_bound;
    }
  }
  // Bound from the design's own variance function: w uniform on the
  // design, M(w) = M / N, d_i(w) = N d_i.
  double upper = log_det - p * std::log(N) + p * std::log(N * max_d / p);
  upper = std::min(upper, approximate_bound);
  summary->log_det_upper_bound = upper + p * std::log(N);
  summary->efficiency_lower_bound =
      std::exp((log_det - summary->log_det_upper_bound) / p);
  return true;
}

}  // namespace activecal
