// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The approximate (continuous-weight) design for the task criterion and the
// certificate it gives for exact designs.
//
// For weights w_i >= 0, sum w_i = 1, on pool poses, M(w) = sum w_i X_i^T X_i,
// phi(w) = tr(W M(w)^-1) and b_i(w) = tr(X_i M^-1 W M^-1 X_i^T) (minus the
// derivative of phi in w_i). phi is convex, sum_i w_i b_i(w) = phi(w), and
// w is optimal iff max_i b_i(w) <= phi(w) (equivalence theorem for linear
// criteria). Convexity of M -> M^-1 gives, for every w and every c > 0,
// phi(M*) >= 2 phi(cM) - tr((cM)^-1 W (cM)^-1 M*); the best c yields
//
//   phi*  >=  phi(w)^2 / max_i b_i(w)                                 (1)
//
// so w is at least phi(w) / max_i b_i(w) efficient. Any exact design of N
// poses has M_N = N M(uniform on its poses), hence phi_N* >= phi* / N for the
// best N-pose design, and an exact design with phi_N is certified
//
//   eff = phi_N* / phi_N  >=  (bound (1)) / (N phi_N).                (2)
//
// A second bound needs no solver: (1) with w uniform on the design gives
// eff >= phi_N / (N max_i b_i(M_N)). CertifyTaskDesign reports the larger.
// Both hold whatever the solver's tolerance, because (1) holds for every w.
//
// The solver: multiplicative updates w_i <- w_i sqrt(b_i) / sum_j w_j
// sqrt(b_j) (monotone for this criterion; Fellman 1974, Torsney 1983) on a
// working set of poses (the support and those with largest b_i), with a
// check of the whole pool after each round. It stops when
// max_i b_i <= phi (1 + tolerance).

#ifndef ACTIVECAL_SELECTION_TASK_APPROXIMATE_H_
#define ACTIVECAL_SELECTION_TASK_APPROXIMATE_H_

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/types.h"
#include "activecal/selection/design.h"

namespace activecal {

struct TaskApproximateOptions {
  // Stop when max_i b_i(w) <= phi(w) (1 + tolerance): w is then at least
  // 1 / (1 + tolerance) efficient.
  double tolerance = 1e-3;
  int max_rounds = 100;        // full-pool checks
  int inner_iterations = 300;  // multiplicative sweeps per round
  int working_set = 0;         // poses per round; <= 0: max(200, 8 p)
  int num_threads = 0;         // <= 0: all; result does not depend on it

  bool IsValid(std::string* error) const;
};

struct TaskApproximateSummary {
  // CONVERGENCE: tolerance met; NO_CONVERGENCE: max_rounds came first (w
  // and the bounds are still valid); FAILURE: the pool does not identify
  // every parameter; USER_FAILURE: bad options.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  std::vector<int64_t> support;
  std::vector<double> weights;                                 // sum 1
  double criterion = std::numeric_limits<double>::infinity();  // phi(w)
  double max_b = std::numeric_limits<double>::infinity();
  // Bound (1) on phi of the best approximate design, and phi / max b.
  double criterion_lower_bound = 0.0;
  double efficiency_lower_bound = 0.0;
  int rounds = 0;
  double seconds = 0.0;

  bool IsSolutionUsable() const {
    return termination_type == TerminationType::kConvergence ||
           termination_type == TerminationType::kNoConvergence;
  }
  std::string BriefReport() const;
};

// Solves over the pool's eligible poses (excluded poses left out; fixed
// poses are ordinary candidates here: the bound then holds a fortiori).
bool SolveTaskApproximateDesign(const CandidatePool& pool,
                                const Eigen::MatrixXd& W,
                                const DesignConstraints& constraints,
                                const TaskApproximateOptions& options,
                                TaskApproximateSummary* summary);

// Fills summary->efficiency_lower_bound and summary->task_criterion_lower_bound
// (the bound on phi of the best design of the same size) for the exact
// design in summary->design, from bound (2) with `approximate` (may be
// null) and from the design's own b_i. Without prior information only
// (the bounds above assume M = sum over the design): returns false, and
// leaves NaN, for a singular design.
bool CertifyTaskDesign(const CandidatePool& pool, const Eigen::MatrixXd& W,
                       const DesignConstraints& constraints,
                       const TaskApproximateSummary* approximate,
                       int num_threads, SelectionSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_TASK_APPROXIMATE_H_
