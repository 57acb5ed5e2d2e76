// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "sub_pool.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <string>
#include <utility>

namespace activecal {
namespace internal {

std::vector<int64_t> TopByVariance(const Eigen::VectorXd& d,
                                   const std::vector<char>& candidate,
                                   int64_t k) {
  std::vector<int64_t> order;
  for (int64_t i = 0; i < static_cast<int64_t>(candidate.size()); ++i) {
    if (candidate[i]) order.push_back(i);
  }
  k = std::min<int64_t>(k, order.size());
  std::partial_sort(order.begin(), order.begin() + k, order.end(),
                    [&](int64_t a, int64_t b) {
                      return d[a] > d[b] || (d[a] == d[b] && a < b);
                    });
  order.resize(k);
  return order;
}

bool VariancesUnder(const CandidatePool& pool, const Eigen::MatrixXd& M,
                    int num_threads, Eigen::VectorXd* d) {
  const Eigen::LLT<Eigen::MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) return false;
  ComputeVariances(pool,
                   llt.solve(Eigen::MatrixXd::Identity(M.rows(), M.cols())),
                   num_threads, d);
  return true;
}

SubPool::SubPool(const CandidatePool& full, const std::vector<char>& keep)
    : to_sub_(full.size(), -1) {
  CHECK_EQ(static_cast<int64_t>(keep.size()), full.size());
  for (int64_t i = 0; i < full.size(); ++i) {
    if (keep[i]) {
      to_sub_[i] = static_cast<int64_t>(to_full_.size());
      to_full_.push_back(i);
    }
  }
  // Always double: the exchanges run on it (a single-precision pool is
  // widened pose by pose, and never held twice in full).
  const int t = full.block_rows();
  RowMatrixXd rows(to_full_.size() * t, full.num_parameters()), buffer;
  for (size_t n = 0; n < to_full_.size(); ++n) {
    rows.middleRows(n * t, t) = full.Rows(to_full_[n], 1, &buffer);
  }
  std::string error;
  // Rows of a valid pool: Create cannot fail here.
  CHECK(CandidatePool::Create(std::move(rows), t, &pool_, &error)) << error;
}

int64_t SubPool::ToSub(int64_t full) const {
  CHECK(full >= 0 && full < static_cast<int64_t>(to_sub_.size()) &&
        to_sub_[full] >= 0)
      << "pose " << full << " is not in the sub-pool";
  return to_sub_[full];
}

std::vector<int64_t> SubPool::ToSub(const std::vector<int64_t>& full) const {
  std::vector<int64_t> sub;
  sub.reserve(full.size());
  for (int64_t i : full) sub.push_back(ToSub(i));
  return sub;
}

std::vector<int64_t> SubPool::ToFull(const std::vector<int64_t>& sub) const {
  std::vector<int64_t> full;
  full.reserve(sub.size());
  for (int64_t i : sub) full.push_back(to_full_[i]);
  return full;
}

void SubPool::ToFull(std::vector<SelectionStep>* history) const {
  for (SelectionStep& step : *history) {
    if (step.added >= 0) step.added = to_full_[step.added];
    if (step.removed >= 0) step.removed = to_full_[step.removed];
  }
}

std::vector<char> SubPool::Restrict(const std::vector<char>& full) const {
  std::vector<char> sub(to_full_.size());
  for (size_t n = 0; n < to_full_.size(); ++n) sub[n] = full[to_full_[n]];
  return sub;
}

ApproximateDesignSummary SubPool::Restrict(
    const ApproximateDesignSummary& a) const {
  ApproximateDesignSummary sub = a;
  sub.support.clear();
  sub.weights.clear();
  for (size_t n = 0; n < a.support.size(); ++n) {
    const int64_t s = to_sub_[a.support[n]];
    if (s >= 0) {
      sub.support.push_back(s);
      sub.weights.push_back(a.weights[n]);
    }
  }
  return sub;
}

}  // namespace internal
}  // namespace activecal
