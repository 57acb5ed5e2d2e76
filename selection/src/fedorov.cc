#include "activecal/selection/fedorov.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/selection/criteria.h"
#include "selection_internal.h"

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

bool GreedyOptions::IsValid(std::string* error) const {
  if (num_poses > 0) return true;
  if (error) *error = "num_poses must be > 0, got " + std::to_string(num_poses);
  return false;
}

bool DetmaxOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (num_poses <= 0)
    msg << "num_poses must be > 0, got " << num_poses;
  else if (restarts <= 0)
    msg << "restarts must be > 0, got " << restarts;
  else if (max_excursion <= 0)
    msg << "max_excursion must be > 0";
  else if (max_iterations < 0)
    msg << "max_iterations must be >= 0";
  if (msg.tellp() == 0) return true;
  if (error) *error = msg.str();
  return false;
}

namespace internal {

RestartResult BestOfRestarts(
    int restarts, int num_threads,
    const std::function<RestartResult(int restart, int inner_threads)>& run,
    const ProgressCallback& progress) {
  std::vector<RestartResult> results(restarts);
  const int threads = ResolveNumThreads(num_threads);
  std::atomic<int64_t> done{0};
  if (progress) progress(0, restarts);
  if (restarts >= threads) {
    ParallelFor(restarts, threads, [&](int64_t b, int64_t e, int) {
      for (int64_t r = b; r < e; ++r) {
        results[r] = run(r, 1);
        if (progress) progress(++done, restarts);
      }
    });
  } else {
    for (int r = 0; r < restarts; ++r) {
      results[r] = run(r, threads);
      if (progress) progress(++done, restarts);
    }
  }
  int best = -1;
  for (int r = 0; r < restarts; ++r) {
    results[r].restart = r;
    if (!results[r].ok) continue;
    if (best < 0 || results[r].log_det > results[best].log_det) best = r;
  }
  if (best < 0) return results[0];
  return results[best];
}

std::vector<int64_t> InitialDesign(const CandidatePool& pool,
                                   const DesignConstraints& constraints,
                                   const std::vector<char>& eligible,
                                   int num_poses, uint64_t seed,
                                   const ApproximateDesignSummary* approximate,
                                   bool randomized, int num_threads,
                                   std::string* note) {
  std::vector<int64_t> design = constraints.fixed;
  const int want = num_poses - static_cast<int>(constraints.fixed.size());
  if (approximate) {
    // Round the approximate design: restart 0 (randomized == false) takes
    // its heaviest poses; later restarts draw poses without replacement
    // with probability proportional to their weights.
    std::vector<int64_t> support;
    std::vector<double> weights;
    for (size_t k = 0; k < approximate->support.size(); ++k) {
      if (eligible[approximate->support[k]]) {
        support.push_back(approximate->support[k]);
        weights.push_back(approximate->weights[k]);
      }
    }
    if (randomized) {
      Random random(Random::StreamSeed(seed, 1));
      for (int n = 0; n < want && !support.empty(); ++n) {
        const double total =
            std::accumulate(weights.begin(), weights.end(), 0.0);
        double u = random.Uniform() * total;
        size_t k = 0;
        while (k + 1 < weights.size() && u >= weights[k]) u -= weights[k++];
        design.push_back(support[k]);
        support.erase(support.begin() + k);
        weights.erase(weights.begin() + k);
      }
    } else {
      std::vector<size_t> order(support.size());
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return weights[a] > weights[b];
      });
      for (size_t k = 0; k < order.size() && k < static_cast<size_t>(want);
           ++k) {
        design.push_back(support[order[k]]);
      }
    }
  }
  std::vector<int64_t> candidates;
  std::vector<char> taken(pool.size(), 0);
  for (int64_t i : design) taken[i] = 1;
  for (int64_t i = 0; i < pool.size(); ++i) {
    if (eligible[i] && !taken[i]) candidates.push_back(i);
  }
  const int missing = num_poses - static_cast<int>(design.size());
  if (missing > 0) {
    Random random(seed);
    for (int64_t j :
         random.SampleWithoutReplacement(candidates.size(), missing)) {
      design.push_back(candidates[j]);
    }
  }
  if (!std::isfinite(LogDetFromScratch(pool, design))) {
    const int added =
        CompleteSingularDesign(pool, eligible, num_threads, &design);
    if (added < 0) return {};
    // Back to num_poses: drop the non-fixed poses that cost least.
    DeterminantScorer d(pool, num_threads);
    for (int64_t i : design) d.Add(i);
    std::vector<char> is_fixed(pool.size(), 0);
    for (int64_t f : constraints.fixed) is_fixed[f] = 1;
    while (d.size() > num_poses) {
      int64_t worst;
      double value;
      if (!d.BestRemoval(is_fixed, &worst, &value) || !d.Remove(worst)) break;
    }
    design = d.poses();
    if (note) {
      *note = "a singular start was completed greedily on M + eps I (" +
              std::to_string(added) + " poses) and trimmed back";
    }
  }
  return design;
}

}  // namespace internal

namespace {

using internal::RestartResult;

struct YEntry {
  double trace;
  int64_t pose;
};

// Tries DETMAX excursions of size min_size..max_excursion on `poses` (add k
// best then remove k, or remove k then add k). Returns true and updates poses
// when one raises log det by more than min_improvement.
bool TryExcursion(const CandidatePool& pool, const std::vector<char>& eligible,
                  const std::vector<char>& is_fixed, int min_size,
                  int max_excursion, double min_improvement, int threads,
                  std::vector<int64_t>* poses, std::string* kind) {
  for (int k = min_size; k <= max_excursion; ++k) {
    for (int direction = 0; direction < 2; ++direction) {
      internal::DeterminantScorer scorer(pool, threads);
      for (int64_t i : *poses) scorer.Add(i);
      const double base = scorer.Value();
      bool ok = true;
      for (int phase = 0; phase < 2 && ok; ++phase) {
        const bool adding = (phase == 0) == (direction == 0);
        for (int j = 0; j < k && ok; ++j) {
          int64_t pose;
          double value;
          if (adding) {
            ok = scorer.BestAddition(eligible, &pose, &value);
            if (ok) scorer.Add(pose);
          } else {
            ok = scorer.BestRemoval(is_fixed, &pose, &value) &&
                 scorer.Remove(pose);
          }
        }
      }
      // Accepted on values recomputed from scratch: the incremental ones of
      // a nearly singular design can drift by more than the threshold, and
      // two excursions could then undo each other forever.
      if (ok && scorer.Value() > base + internal::ImprovementThreshold(
                                            base, min_improvement)) {
        const double before = LogDetFromScratch(pool, *poses);
        const double after = LogDetFromScratch(pool, scorer.poses());
        if (!(after > before + internal::ImprovementThreshold(
                                   before, min_improvement))) {
          continue;
        }
        *poses = scorer.poses();
        *kind =
            std::string(direction == 0 ? "excursion up " : "excursion down ") +
            std::to_string(k);
        return true;
      }
    }
  }
  return false;
}

RestartResult FedorovRestart(const CandidatePool& pool,
                             const std::vector<char>& eligible,
                             const std::vector<char>& is_fixed,
                             std::vector<int64_t> initial,
                             const FedorovOptions& options, int threads) {
  RestartResult result;
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
  result.history.push_back({"initial", -1, -1, design.log_det()});
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
              Wx.noalias() = pool.block(x) * V;
              for (size_t j = 0; j < num_y; ++j) {
                const YEntry& y = ys[j];
                if (trx - y.trace <= threshold) break;
                Dxy.noalias() = Wx * pool.block(y.pose).transpose();
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
      result.history.push_back({"exchange", best_x, best_y, design.log_det()});
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
    std::string kind;
    if (!TryExcursion(pool, eligible, is_fixed, 2, options.max_excursion,
                      options.min_improvement, threads, &poses, &kind)) {
      break;
    }
    Design next(pool);
    for (int64_t i : poses) next.Add(i);
    design = std::move(next);
    refresh_all();
    since_refresh = 0;
    ++swaps;
    result.history.push_back({kind, -1, -1, design.log_det()});
  }
  result.design = design.poses();
  result.log_det = LogDetFromScratch(pool, result.design);
  result.ok = std::isfinite(result.log_det);
  return result;
}

// Resets the summary, checks the options and the constraints, and marks the
// eligible and the fixed poses.
template <typename Options>
bool Prepare(const CandidatePool& pool, const DesignConstraints& constraints,
             const Options& options, const char* algorithm,
             SelectionSummary* summary, std::vector<char>* eligible,
             std::vector<char>* is_fixed) {
  *summary = SelectionSummary();
  summary->algorithm = algorithm;
  summary->num_parameters = pool.num_parameters();
  summary->pool_size = pool.size();
  std::string error;
  if (!options.IsValid(&error) ||
      !PrepareCandidates(pool, options.num_poses, constraints, eligible,
                         &error)) {
    summary->message = error;
    return false;
  }
  is_fixed->assign(pool.size(), 0);
  for (int64_t f : constraints.fixed) (*is_fixed)[f] = 1;
  return true;
}

// The note a restart left, if any.
std::string NoteOf(const std::vector<std::string>& notes, int restart) {
  return restart < static_cast<int>(notes.size()) ? notes[restart] : "";
}

void Finish(const RestartResult& best, int restarts,
            std::chrono::steady_clock::time_point start,
            const std::string& note, SelectionSummary* summary) {
  summary->design = best.design;
  summary->history = best.history;
  summary->log_det = best.log_det;
  summary->restarts = restarts;
  summary->best_restart = best.restart;
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  summary->termination_type = !best.ok         ? TerminationType::FAILURE
                              : best.hit_bound ? TerminationType::NO_CONVERGENCE
                                               : TerminationType::CONVERGENCE;
  std::ostringstream msg;
  if (best.ok) {
    msg << best.design.size() << " poses, " << best.history.size() - 1
        << " improving steps in the best restart (" << best.restart << ")";
    if (best.hit_bound) {
      msg << "; stopped by an iteration bound (max_swaps, max_iterations or "
             "max_polish_rounds) before a local optimum";
    }
  } else {
    msg << "no restart produced a non-singular design: the eligible poses "
           "(fixed and not excluded) cannot identify all "
        << summary->num_parameters << " parameters";
  }
  if (!note.empty()) msg << "; " << note;
  summary->message = msg.str();
}

}  // namespace

namespace {

// The poses of `keep` (pool indices, ascending) as a pool of their own.
CandidatePool SubPool(const CandidatePool& pool,
                      const std::vector<int64_t>& keep) {
  const int t = pool.block_rows();
  RowMatrixXd rows(keep.size() * t, pool.num_parameters());
  for (size_t n = 0; n < keep.size(); ++n) {
    rows.middleRows(n * t, t) = pool.block(keep[n]);
  }
  CandidatePool sub;
  std::string unused;  // rows of a valid pool: Create cannot fail here
  CandidatePool::Create(std::move(rows), t, &sub, &unused);
  return sub;
}

// Swaps over the polish_pool_size poses of largest variance under the
// current design, re-ranked after each round, until a round makes no swap.
RestartResult PolishInRounds(const CandidatePool& pool,
                             const std::vector<char>& eligible,
                             const DesignConstraints& constraints,
                             std::vector<int64_t> design,
                             const FedorovOptions& options) {
  RestartResult result;
  result.ok = false;
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
    const Eigen::LLT<Eigen::MatrixXd> llt(M);
    if (llt.info() != Eigen::Success) break;
    Eigen::VectorXd d;
    ComputeVariances(pool, llt.solve(Eigen::MatrixXd::Identity(p, p)),
                     options.num_threads, &d);
    std::vector<char> keep(pool.size(), 0);
    for (int64_t i : design) keep[i] = 1;
    for (int64_t f : constraints.fixed) keep[f] = 1;
    std::vector<int64_t> order;
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (eligible[i] && !keep[i]) order.push_back(i);
    }
    const int64_t k = std::min<int64_t>(options.polish_pool_size, order.size());
    std::partial_sort(order.begin(), order.begin() + k, order.end(),
                      [&](int64_t a, int64_t b) {
                        return d[a] > d[b] || (d[a] == d[b] && a < b);
                      });
    for (int64_t n = 0; n < k; ++n) keep[order[n]] = 1;
    std::vector<int64_t> to_full, to_sub(pool.size(), -1);
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (keep[i]) {
        to_sub[i] = static_cast<int64_t>(to_full.size());
        to_full.push_back(i);
      }
    }
    const CandidatePool sub = SubPool(pool, to_full);
    std::vector<char> sub_eligible(sub.size(), 1), sub_fixed(sub.size(), 0);
    for (int64_t f : constraints.fixed) {
      sub_eligible[to_sub[f]] = 0;
      sub_fixed[to_sub[f]] = 1;
    }
    std::vector<int64_t> initial;
    for (int64_t i : design) initial.push_back(to_sub[i]);
    RestartResult r = FedorovRestart(sub, sub_eligible, sub_fixed, initial,
                                     options, options.num_threads);
    if (!r.ok) break;
    for (int64_t& i : r.design) i = to_full[i];
    for (size_t n = 1; n < r.history.size(); ++n) {
      SelectionStep step = r.history[n];
      if (step.added >= 0) step.added = to_full[step.added];
      if (step.removed >= 0) step.removed = to_full[step.removed];
      history.push_back(step);
    }
    const bool changed = r.history.size() > 1;
    design = r.design;
    r.history.clear();
    r.history.push_back(SelectionStep());  // the caller skips entry 0
    for (const SelectionStep& step : history) r.history.push_back(step);
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
  if (!Prepare(pool, constraints, options, "fedorov", summary, &eligible,
               &is_fixed)) {
    return false;
  }
  // With an approximate design and a large pool, the restarts swap within
  // a reduced pool first: the approximate design's support and the poses of
  // largest variance under it, where good exact designs live. The best
  // result is then polished by swaps over the whole pool, so it is a local
  // optimum of the full problem either way.
  const CandidatePool* work_pool = &pool;
  CandidatePool reduced;
  std::vector<int64_t> to_full;  // reduced index -> pool index
  DesignConstraints work_constraints = constraints;
  ApproximateDesignSummary work_approx;
  const ApproximateDesignSummary* work_approximate = approximate;
  std::vector<char> work_eligible = eligible, work_fixed = is_fixed;
  const int64_t reduced_size = std::max<int64_t>(
      options.reduced_pool_size,
      options.reduced_pool_per_pose * static_cast<int64_t>(options.num_poses));
  if (approximate && !approximate->support.empty() &&
      options.reduced_pool_size > 0 && pool.size() > reduced_size) {
    const int p = pool.num_parameters();
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
    for (size_t k = 0; k < approximate->support.size(); ++k) {
      const auto X = pool.block(approximate->support[k]);
      M.noalias() += approximate->weights[k] * X.transpose() * X;
    }
    Eigen::VectorXd d;
    ComputeVariances(
        pool,
        Eigen::LLT<Eigen::MatrixXd>(M).solve(Eigen::MatrixXd::Identity(p, p)),
        options.num_threads, &d);
    std::vector<char> keep(pool.size(), 0);
    for (int64_t f : constraints.fixed) keep[f] = 1;
    for (int64_t i : approximate->support) keep[i] = keep[i] || eligible[i];
    std::vector<int64_t> order;
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (eligible[i]) order.push_back(i);
    }
    const int64_t k = std::min<int64_t>(reduced_size, order.size());
    std::partial_sort(order.begin(), order.begin() + k, order.end(),
                      [&](int64_t a, int64_t b) {
                        return d[a] > d[b] || (d[a] == d[b] && a < b);
                      });
    for (int64_t n = 0; n < k; ++n) keep[order[n]] = 1;
    std::vector<int64_t> to_reduced(pool.size(), -1);
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (keep[i]) {
        to_reduced[i] = static_cast<int64_t>(to_full.size());
        to_full.push_back(i);
      }
    }
    const int t = pool.block_rows();
    RowMatrixXd rows(to_full.size() * t, p);
    for (size_t n = 0; n < to_full.size(); ++n) {
      rows.middleRows(n * t, t) = pool.block(to_full[n]);
    }
    // Rows of a valid pool: Create cannot fail here.
    std::string unused;
    CandidatePool::Create(std::move(rows), t, &reduced, &unused);
    work_pool = &reduced;
    work_constraints = DesignConstraints();
    for (int64_t f : constraints.fixed) {
      work_constraints.fixed.push_back(to_reduced[f]);
    }
    work_approx = *approximate;
    work_approx.support.clear();
    work_approx.weights.clear();
    for (size_t n = 0; n < approximate->support.size(); ++n) {
      const int64_t r = to_reduced[approximate->support[n]];
      if (r >= 0) {
        work_approx.support.push_back(r);
        work_approx.weights.push_back(approximate->weights[n]);
      }
    }
    work_approximate = &work_approx;
    work_eligible.assign(reduced.size(), 1);
    work_fixed.assign(reduced.size(), 0);
    for (int64_t f : work_constraints.fixed) {
      work_eligible[f] = 0;
      work_fixed[f] = 1;
    }
  }
  std::vector<std::string> notes(options.restarts);
  RestartResult best = internal::BestOfRestarts(
      options.restarts, options.num_threads,
      [&](int r, int threads) {
        const std::vector<int64_t> initial = internal::InitialDesign(
            *work_pool, work_constraints, work_eligible, options.num_poses,
            Random::StreamSeed(options.seed, r), work_approximate, r > 0,
            threads, &notes[r]);
        if (initial.empty()) return RestartResult();
        return FedorovRestart(*work_pool, work_eligible, work_fixed, initial,
                              options, threads);
      },
      options.progress);
  const auto restarts_done = std::chrono::steady_clock::now();
  std::string timing;
  if (work_pool != &pool && best.ok) {
    std::vector<int64_t> initial;
    for (int64_t i : best.design) initial.push_back(to_full[i]);
    RestartResult polished;
    if (options.polish_pool_size <= 0 ||
        pool.size() <= options.polish_pool_size) {
      polished = FedorovRestart(pool, eligible, is_fixed, initial, options,
                                options.num_threads);
    } else {
      polished = PolishInRounds(pool, eligible, constraints, initial, options);
    }
    std::vector<SelectionStep> history = best.history;
    for (SelectionStep& step : history) {
      if (step.added >= 0) step.added = to_full[step.added];
      if (step.removed >= 0) step.removed = to_full[step.removed];
    }
    for (size_t n = 1; n < polished.history.size(); ++n) {
      history.push_back(polished.history[n]);
    }
    polished.history = std::move(history);
    polished.restart = best.restart;
    const size_t reduced_steps = best.history.size();
    polished.hit_bound = polished.hit_bound || best.hit_bound;
    if (polished.ok) best = std::move(polished);
    std::ostringstream msg;
    msg.precision(3);
    msg << "restarts on a reduced pool of " << reduced.size() << " poses "
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
  std::string note = NoteOf(notes, best.restart);
  if (!timing.empty()) note = note.empty() ? timing : note + "; " + timing;
  Finish(best, options.restarts, start, note, summary);
  return summary->IsSolutionUsable();
}

bool Detmax(const CandidatePool& pool, const DesignConstraints& constraints,
            const DetmaxOptions& options, SelectionSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<char> eligible, is_fixed;
  if (!Prepare(pool, constraints, options, "detmax", summary, &eligible,
               &is_fixed)) {
    return false;
  }
  std::vector<std::string> notes(options.restarts);
  const RestartResult best = internal::BestOfRestarts(
      options.restarts, options.num_threads,
      [&](int r, int threads) {
        RestartResult result;
        std::vector<int64_t> poses = internal::InitialDesign(
            pool, constraints, eligible, options.num_poses,
            Random::StreamSeed(options.seed, r), nullptr, false, threads,
            &notes[r]);
        if (poses.empty()) return result;
        {
          internal::DeterminantScorer start_scorer(pool, threads);
          for (int64_t i : poses) start_scorer.Add(i);
          result.history.push_back({"initial", -1, -1, start_scorer.Value()});
        }
        for (int it = 0;; ++it) {
          if (it >= options.max_iterations) {
            result.hit_bound = true;
            break;
          }
          std::string kind;
          if (!TryExcursion(pool, eligible, is_fixed, 1, options.max_excursion,
                            options.min_improvement, threads, &poses, &kind)) {
            break;
          }
          result.history.push_back(
              {kind, -1, -1, LogDetFromScratch(pool, poses)});
        }
        result.design = poses;
        result.log_det = LogDetFromScratch(pool, result.design);
        result.ok = std::isfinite(result.log_det);
        return result;
      },
      options.progress);
  Finish(best, options.restarts, start, NoteOf(notes, best.restart), summary);
  return summary->IsSolutionUsable();
}

bool GreedyDesign(const CandidatePool& pool,
                  const DesignConstraints& constraints,
                  const GreedyOptions& options, SelectionSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<char> eligible, is_fixed;
  if (!Prepare(pool, constraints, options, "greedy", summary, &eligible,
               &is_fixed)) {
    return false;
  }
  const double eps = internal::RegularisingRidge(pool);
  Design design(pool, eps);
  for (int64_t f : constraints.fixed) design.Add(f);
  RestartResult result;
  Eigen::VectorXd gains;
  while (design.size() < options.num_poses) {
    ComputeAddGains(pool, design.information(), options.num_threads, &gains);
    int64_t best = -1;
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (eligible[i] && !design.Contains(i) &&
          (best < 0 || gains[i] > gains[best])) {
        best = i;
      }
    }
    if (best < 0) break;
    design.Add(best);
    result.history.push_back(
        {"add", best, -1, LogDetFromScratch(pool, design.poses())});
  }
  result.design = design.poses();
  result.log_det = LogDetFromScratch(pool, result.design);
  result.ok = std::isfinite(result.log_det);
  Finish(result, 1, start,
         "ridge " + std::to_string(eps) + " while the design was singular",
         summary);
  return summary->IsSolutionUsable();
}

}  // namespace activecal
