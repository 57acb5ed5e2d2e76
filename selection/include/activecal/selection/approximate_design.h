// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The approximate (continuous-weight) D-optimal design over a pool, and the
// certificate it gives for exact designs.
//
// An approximate design puts weights w_i >= 0, sum w_i = 1, on pool poses;
// M(w) = sum w_i X_i^T X_i and d_i(w) = tr(X_i M(w)^-1 X_i^T). The
// Kiefer-Wolfowitz equivalence theorem (block form) says w is D-optimal iff
// max_i d_i(w) = p, and for every w
//
//   log det M*  <=  log det M(w) + p log(max_i d_i(w) / p).          (1)
//
// Any exact design of N poses has M_N = N M(uniform weights on its poses),
// so det M_N <= N^p det M*: N^p det M* bounds every N-pose design from
// above, and
//
//   eff(M_N) = (det M_N / (N^p det M*))^(1/p)
//            >= exp((log det M_N - p log N - bound (1)) / p)           (2)
//
// is a certified lower bound on its D-efficiency against the best N-pose
// design. A second bound needs no solver: with w uniform on the design,
// (1) gives eff >= p / (N max_i tr(X_i M_N^-1 X_i^T)). CertifyDesign
// reports the larger of the two. Both hold whatever the solver's
// tolerance, because (1) holds for every w; the tolerance only decides how
// tight they are. See docs/certificate.md.
//
// The solver works on a small working set of poses (the support and the
// poses that violate the equivalence theorem most), moving weight between
// pairs of poses by exact line search: the vertex exchange (Bohning 1986)
// between the poses of largest and least variance, and exchanges within
// random pairs of the support and the poses of largest variance
// (randomized exchange, after Harman, Filova & Richtarik 2020), each
// pair's variances read from an inverse kept by rank-2t updates and
// recomputed from the weights every iteration. Each round solves the
// working set to a quarter of the last whole-pool excess max_i d_i - p
// (to tolerance / 2 at the end), then checks its candidate set. It stops
// when max_i d_i(w) <= p (1 + tolerance) over the whole pool.
//
// On a pool of at most subsample_size eligible poses the candidate set is
// the pool: every round ends with a sweep over it. On a larger pool it is
// first a random subsample (fixed seed) of subsample_size poses, solved to
// the tolerance with sweeps over the subsample only; then one sweep over
// the whole pool checks the equivalence theorem, its violators (largest
// variance first, up to max_added_per_sweep) join the candidate set, the
// candidate set is solved again from the current weights, and so on
// (column generation): the work grows with the full sweeps needed, not
// with the pool size times the rounds. Either way the reported
// max_variance, and so the bounds, are from a sweep over the whole pool.

#ifndef ACTIVECAL_SELECTION_APPROXIMATE_DESIGN_H_
#define ACTIVECAL_SELECTION_APPROXIMATE_DESIGN_H_

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/types.h"
#include "activecal/selection/design.h"

namespace activecal {

struct ApproximateDesignOptions {
  // Stop when max_i d_i(w) <= p (1 + tolerance); w is then at least
  // 1 / (1 + tolerance) D-efficient.
  double tolerance = 1e-4;
  int max_rounds = 200;  // candidate-set checks, in total
  // Per round, on the working set: recomputations of M(w), each followed
  // by one vertex exchange and one pass of random pair exchanges.
  int max_inner_iterations = 20000;
  int num_threads = 0;  // <= 0: all; result does not depend on it
  // Pools with more eligible poses than this start on a random subsample
  // of this many (see above); <= 0: max(20000, 200 p).
  int64_t subsample_size = 0;
  // The seed of the subsample and of the random exchange pairs (any seed
  // gives a certified solution; the weights found depend on it within the
  // tolerance).
  uint64_t seed = 1;
  // Violators added to the candidate set per full-pool sweep; <= 0: 100 p
  // (on a 10^6-pose KUKA pool 6 full sweeps, against 8 with 25 p).
  int64_t max_added_per_sweep = 0;
  // Called after each round (done = rounds so far, total = max_rounds).
  ProgressCallback progress;

  bool IsValid(std::string* error) const;
  // subsample_size, or its default for p parameters.
  int64_t ResolvedSubsampleSize(int num_parameters) const;
};

struct ApproximateDesignSummary {
  // CONVERGENCE: max_i d_i(w) <= p (1 + tolerance); NO_CONVERGENCE: a round
  // or iteration bound came first (w and the bounds are still valid);
  // FAILURE: bad input or a pool that cannot identify every parameter.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  int num_parameters = 0;
  // The design: poses with positive weight and their weights (sum 1).
  std::vector<int64_t> support;
  std::vector<double> weights;
  double log_det = -std::numeric_limits<double>::infinity();  // of M(w)
  double max_variance = std::numeric_limits<double>::infinity();
  // Upper bound (1) on log det M* and lower bound p / max d on the
  // efficiency of w.
  double log_det_upper_bound = std::numeric_limits<double>::infinity();
  double efficiency_lower_bound = 0.0;
  int rounds = 0;
  int64_t inner_iterations = 0;
  // Sweeps of the variance function over the whole pool (those over the
  // subsample not counted).
  int full_sweeps = 0;
  double seconds = 0.0;

  bool IsSolutionUsable() const {
    return termination_type != TerminationType::kFailure;
  }
  std::string BriefReport() const;
};

// Solves over the pool's eligible poses (fixed poses included, excluded
// poses left out). Returns summary->IsSolutionUsable().
bool SolveApproximateDesign(const CandidatePool& pool,
                            const DesignConstraints& constraints,
                            const ApproximateDesignOptions& options,
                            ApproximateDesignSummary* summary);

// Fills summary->efficiency_lower_bound and summary->log_det_upper_bound
// for the exact design in summary->design, from bound (2) with `approximate`
// (may be null) and from the design's own variance function. Returns false
// if the design is singular.
//
// Everything is computed in double over the pool's exact blocks
// (CandidatePool::ExactRows: the stored blocks when the pool has no exact
// source): the design's M from its exact blocks, and the variance sweep
// streamed over the exact blocks chunk by chunk, so a single-precision
// pool with an exact source gets a certificate for the double-precision
// blocks without holding the pool twice. With an exact source, bound (1)
// of `approximate` is recomputed over the exact blocks too (M(w) from the
// exact blocks of its support, max d in the same sweep): its own bound is
// for the stored blocks. If exact_log_det is not null it receives
// log det M of the design from the exact blocks.
bool CertifyDesign(const CandidatePool& pool,
                   const DesignConstraints& constraints,
                   const ApproximateDesignSummary* approximate, int num_threads,
                   SelectionSummary* summary, double* exact_log_det = nullptr);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_APPROXIMATE_DESIGN_H_
