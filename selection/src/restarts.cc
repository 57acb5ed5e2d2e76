// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The machinery the restarted selection algorithms share: the starting
// design, the best of the restarts, the summary.

#include <atomic>
#include <cmath>
#include <numeric>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/selection/criteria.h"
#include "selection_internal.h"

namespace activecal {
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

std::vector<int64_t> InitialDesign(const WorkingSet& work, int num_poses,
                                   uint64_t seed,
                                   const ApproximateDesignSummary* approximate,
                                   bool randomized, int num_threads,
                                   std::string* note) {
  const CandidatePool& pool = work.pool;
  const std::vector<char>& eligible = work.eligible;
  std::vector<int64_t> design = work.constraints.fixed;
  const int want = num_poses - static_cast<int>(design.size());
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
    while (d.size() > num_poses) {
      int64_t worst;
      double value;
      if (!d.BestRemoval(work.is_fixed, &worst, &value) || !d.Remove(worst)) {
        break;
      }
    }
    design = d.poses();
    if (note) {
      *note = "a singular start was completed greedily on M + eps I (" +
              std::to_string(added) + " poses) and trimmed back";
    }
  }
  return design;
}

void FinishSummary(const RestartResult& best, int restarts,
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
  summary->termination_type = !best.ok         ? TerminationType::kFailure
                              : best.hit_bound ? TerminationType::kNoConvergence
                                               : TerminationType::kConvergence;
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

}  // namespace internal
}  // namespace activecal
