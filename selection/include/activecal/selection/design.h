// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A design (a set of distinct pool poses) with its information matrix kept
// current, the inputs every selection algorithm shares, and the Summary
// every selection algorithm returns.

#ifndef ACTIVECAL_SELECTION_DESIGN_H_
#define ACTIVECAL_SELECTION_DESIGN_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/types.h"
#include "activecal/selection/information_matrix.h"

namespace activecal {

class Design {
 public:
  // An empty design over `pool`, which must outlive it.
  explicit Design(const CandidatePool& pool, double ridge = 0.0);

  const CandidatePool& pool() const { return *pool_; }
  const std::vector<int64_t>& poses() const { return poses_; }
  int size() const { return static_cast<int>(poses_.size()); }
  bool Contains(int64_t pose) const { return member_[pose] != 0; }
  const InformationMatrix& information() const { return info_; }
  double log_det() const { return info_.log_det(); }

  // Adds a pose of the pool not yet in the design (CHECK-fails otherwise:
  // a programmer error).
  void Add(int64_t pose);
  // Removes a pose of the design (CHECK-fails for one not in it); refused
  // (false) if the information matrix would stop being positive definite.
  bool Remove(int64_t pose);
  // Recomputes the information matrix from the design's blocks.
  void Rebuild();
  // Drops a ridge used for a regularised start: M is rebuilt without it.
  void ClearRidge();

 private:
  const CandidatePool* pool_;
  std::vector<int64_t> poses_;
  std::vector<char> member_;
  InformationMatrix info_;
};

// The add gain log det(I + X_i V X_i^T) of every pool pose, against the
// information matrix `info` (positive definite). Spread over num_threads
// threads (<= 0: all); the result does not depend on the count.
void ComputeAddGains(const CandidatePool& pool, const InformationMatrix& info,
                     int num_threads, Eigen::VectorXd* gains);

// Which blocks a sweep over the pool reads: the stored ones (widened to
// double from a single-precision pool), or those of the pool's exact
// source (CandidatePool::ExactRows; the stored ones if it has none).
enum class PoolReading { kStored, kExact };

// The variance function d_i = tr(X_i V X_i^T) of every pool pose for a
// given V (the inverse of an information matrix).
void ComputeVariances(const CandidatePool& pool, const Eigen::MatrixXd& V,
                      int num_threads, Eigen::VectorXd* variances,
                      PoolReading reading = PoolReading::kStored);
// The same for several V in one pass over the pool ((*variances)[k] for
// Vs[k]): one read, or one recomputation from the exact source, of every
// block for all of them.
void ComputeVariances(const CandidatePool& pool,
                      const std::vector<Eigen::MatrixXd>& Vs, int num_threads,
                      std::vector<Eigen::VectorXd>* variances,
                      PoolReading reading = PoolReading::kStored);

// What every selection algorithm takes besides its own options.
struct DesignConstraints {
  // Poses always in the design and never removed (measured anyway, or
  // required). Counted in num_poses.
  std::vector<int64_t> fixed;
  // Poses never selected, e.g. those the measuring device cannot see.
  std::function<bool(int64_t)> excluded;
};

// Checks the constraints against the pool and a design size, and marks the
// poses that may be added (not fixed, not excluded). Returns false with a
// message on inconsistent input.
// prior_equations: rows of information the design adds to (poses already
// measured), counted with the design's when checking that it can be
// non-singular.
bool PrepareCandidates(const CandidatePool& pool, int num_poses,
                       const DesignConstraints& constraints,
                       std::vector<char>* eligible, std::string* error,
                       int64_t prior_equations = 0);

// One accepted step of a selection algorithm.
struct SelectionStep {
  enum Kind {
    kInitial,        // the starting design
    kExchange,       // one pose swapped for another
    kAdd,            // one pose added
    kExcursionUp,    // DETMAX: excursion_size poses added, then removed
    kExcursionDown,  // DETMAX: excursion_size poses removed, then added
  };
  Kind kind = kInitial;
  int64_t added = -1;    // pool index, or -1
  int64_t removed = -1;  // pool index, or -1
  double log_det = 0.0;  // natural log det X^T X after the step
  int excursion_size = 0;

  // "initial", "exchange", "add", "excursion up 2", "excursion down 3":
  // for printing, CSV and JSON.
  std::string name() const;
};

struct SelectionSummary {
  TerminationType termination_type = TerminationType::kFailure;
  // What happened, and on FAILURE why.
  std::string message;
  std::string algorithm;
  int num_parameters = 0;
  int64_t pool_size = 0;
  // The selected poses (pool indices), fixed poses first.
  std::vector<int64_t> design;
  // Natural log det X^T X of the design, recomputed from scratch.
  double log_det = -std::numeric_limits<double>::infinity();
  // The steps of the restart that produced the design.
  std::vector<SelectionStep> history;
  int restarts = 0;
  int best_restart = 0;
  double seconds = 0.0;
  // Filled by CertifyDesign (approximate_design.h): a certified lower bound on
  // the D-efficiency against the best possible design of the same size, and the
  // upper bound on log det it comes from. NaN when not computed.
  double efficiency_lower_bound = std::numeric_limits<double>::quiet_NaN();
  double log_det_upper_bound = std::numeric_limits<double>::quiet_NaN();
  // Task-criterion designs (task_exchange.h): phi = tr(W M^-1) of the
  // design, prior included, recomputed from scratch; NaN for the
  // D-criterion algorithms. CertifyTaskDesign (task_approximate.h) fills
  // efficiency_lower_bound (phi of the best design of the same size over
  // phi of this one, bounded below) and task_criterion_lower_bound (the
  // bound on phi of the best design it rests on).
  double task_criterion = std::numeric_limits<double>::quiet_NaN();
  double task_criterion_lower_bound = std::numeric_limits<double>::quiet_NaN();

  // A design was returned (CONVERGENCE or NO_CONVERGENCE): what every
  // selection function returns.
  bool IsSolutionUsable() const {
    return termination_type != TerminationType::kFailure;
  }
  double log10_det() const { return log_det / 2.302585092994046; }
  std::string BriefReport() const;
};

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_DESIGN_H_
