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
// pairs of poses by exact line search (vertex exchange, Bohning 1986) with
// multiplicative sweeps (Titterington 1976), and checks the whole pool
// after each round. It stops when max_i d_i(w) <= p (1 + tolerance).

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
  int max_rounds = 200;              // full-pool checks
  int max_inner_iterations = 20000;  // per round, on the working set
  int num_threads = 0;               // <= 0: all; result does not depend on it
  // Called after each round (done = rounds so far, total = max_rounds).
  ProgressCallback progress;

  bool IsValid(std::string* error) const;
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
bool CertifyDesign(const CandidatePool& pool,
                   const DesignConstraints& constraints,
                   const ApproximateDesignSummary* approximate, int num_threads,
                   SelectionSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_APPROXIMATE_DESIGN_H_
