// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Part of a pool as a pool of its own, with the index maps both ways: the
// reduced pool of Fedorov's restarts and its polish rounds work on one.
// Not installed.

#ifndef ACTIVECAL_SELECTION_SRC_SUB_POOL_H_
#define ACTIVECAL_SELECTION_SRC_SUB_POOL_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/design.h"

namespace activecal {
namespace internal {

// The (at most k) poses i with candidate[i] set and the largest d[i], in
// decreasing order of d (ties: the lower index first).
std::vector<int64_t> TopByVariance(const Eigen::VectorXd& d,
                                   const std::vector<char>& candidate,
                                   int64_t k);

// The variance function d_i = tr(X_i M^-1 X_i^T) of every pool pose;
// false if M is not positive definite.
bool VariancesUnder(const CandidatePool& pool, const Eigen::MatrixXd& M,
                    int num_threads, Eigen::VectorXd* d);

class SubPool {
 public:
  // The poses i of `full` with keep[i] set, in increasing index order.
  SubPool(const CandidatePool& full, const std::vector<char>& keep);

  const CandidatePool& pool() const { return pool_; }
  int64_t size() const { return pool_.size(); }
  // Sub-pool index -> full-pool index.
  int64_t ToFull(int64_t sub) const { return to_full_[sub]; }
  // Full-pool index -> sub-pool index; CHECK-fails for a pose not kept.
  int64_t ToSub(int64_t full) const;
  std::vector<int64_t> ToSub(const std::vector<int64_t>& full) const;
  std::vector<int64_t> ToFull(const std::vector<int64_t>& sub) const;
  // The added/removed poses of every step, sub -> full.
  void ToFull(std::vector<SelectionStep>* history) const;
  // A per-pose flag of the full pool (eligible, fixed) on the sub-pool.
  std::vector<char> Restrict(const std::vector<char>& full) const;
  // The approximate design's support (and weights) within the sub-pool.
  ApproximateDesignSummary Restrict(const ApproximateDesignSummary& a) const;

 private:
  CandidatePool pool_;
  std::vector<int64_t> to_full_;
  std::vector<int64_t> to_sub_;
};

// What an exchange's restarts work on: the pool, the fixed poses (the
// constraints' other fields left empty: the eligible flags hold the
// exclusions) and the eligible and fixed flags, those of the sub-pool when
// `reduced` is set, else the full pool's.
struct WorkingSet {
  WorkingSet(const CandidatePool& full, const SubPool* reduced,
             const DesignConstraints& full_constraints,
             const std::vector<char>& full_eligible,
             const std::vector<char>& full_fixed)
      : pool(reduced ? reduced->pool() : full),
        eligible(reduced ? reduced->Restrict(full_eligible) : full_eligible),
        is_fixed(reduced ? reduced->Restrict(full_fixed) : full_fixed) {
    constraints.fixed = reduced ? reduced->ToSub(full_constraints.fixed)
                                : full_constraints.fixed;
  }

  const CandidatePool& pool;
  DesignConstraints constraints;
  std::vector<char> eligible;
  std::vector<char> is_fixed;
};

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_SRC_SUB_POOL_H_
