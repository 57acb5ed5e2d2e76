// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/selection/criteria.h"

#include <Eigen/SVD>
#include <cmath>

#include "activecal/selection/information_matrix.h"
#include "selection_internal.h"

namespace activecal {

ObservabilityIndices ComputeObservabilityIndices(const Eigen::MatrixXd& X) {
  ObservabilityIndices o;
  Eigen::BDCSVD<Eigen::MatrixXd> svd(X);
  o.singular_values = svd.singularValues();
  const Eigen::VectorXd& s = o.singular_values;
  if (s.size() == 0 || s[0] <= 0) return o;
  const double tol = s[0] * std::max(X.rows(), X.cols()) * 1e-15;
  double log_prod = 0.0, inv_sum = 0.0;
  for (int i = 0; i < s.size(); ++i) {
    if (s[i] <= tol) break;
    ++o.rank;
    log_prod += std::log(s[i]);
    inv_sum += 1.0 / s[i];
  }
  const int L = o.rank;
  const double smin = s[L - 1], smax = s[0];
  o.oi = std::exp(log_prod / L) / L;
  o.log10_oid = 2.0 * log_prod / std::log(10.0);
  o.o1 = std::exp(log_prod / L) / std::sqrt(static_cast<double>(X.rows()));
  o.o2 = smin / smax;
  o.o3 = smin;
  o.o4 = smin * smin / smax;
  o.o5 = 1.0 / inv_sum;
  return o;
}

double OiFromLogDet(double log_det, int num_parameters) {
  const double p = num_parameters;
  return std::exp(log_det / (2.0 * p)) / p;
}

double LogDetFromOi(double oi, int num_parameters) {
  const double p = num_parameters;
  return 2.0 * p * std::log(oi * p);
}

namespace {

// log det of the sum of X^T X over the design's blocks, X = block_of(i).
template <typename BlockOf>
double LogDetOfBlocks(int num_parameters, const std::vector<int64_t>& design,
                      BlockOf block_of) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(num_parameters, num_parameters);
  for (int64_t i : design) {
    const auto X = block_of(i);
    M.noalias() += X.transpose() * X;
  }
  return LogDetSpd(M);
}

}  // namespace

double LogDetFromScratch(const CandidatePool& pool,
                         const std::vector<int64_t>& design) {
  return LogDetOfBlocks(pool.num_parameters(), design,
                        [&pool](int64_t i) { return pool.block(i); });
}

namespace internal {

double LogDetOfExactBlocks(const CandidatePool& pool,
                           const std::vector<int64_t>& design) {
  return LogDetOfBlocks(pool.num_parameters(), design,
                        [&pool](int64_t i) { return pool.ExactBlock(i); });
}

}  // namespace internal

}  // namespace activecal
