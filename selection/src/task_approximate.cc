// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The approximate task design (multiplicative updates on a working set)
// and the certificate of exact designs.

#include "activecal/selection/task_approximate.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

#include "activecal/core/validation.h"
#include "activecal/selection/information_matrix.h"
#include "activecal/selection/task_criterion.h"
#include "selection_internal.h"

namespace activecal {

bool TaskApproximateOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (!(tolerance > 0))
    msg << "tolerance must be > 0, got " << tolerance;
  else if (max_rounds <= 0)
    msg << "max_rounds must be > 0, got " << max_rounds;
  else if (inner_iterations <= 0)
    msg << "inner_iterations must be > 0, got " << inner_iterations;
  return FinishValidation(msg, error);
}

std::string TaskApproximateSummary::BriefReport() const {
  std::ostringstream out;
  out.precision(6);
  out << "Approximate task design: "
      << TerminationTypeToString(termination_type) << ", " << support.size()
      << " support poses, phi " << criterion << ", max b " << max_b
      << ", efficiency >= " << efficiency_lower_bound << ", " << rounds
      << " rounds, " << seconds << " s";
  if (!message.empty()) out << "; " << message;
  out << "\n";
  return out.str();
}

namespace {

// V = M^-1 and G = V W V; false when M is singular.
bool Inverses(const Eigen::MatrixXd& M, const Eigen::MatrixXd& W,
              Eigen::MatrixXd* V, Eigen::MatrixXd* G) {
  if (LogDetSpd(M) == -std::numeric_limits<double>::infinity()) return false;
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  *V = llt.solve(Eigen::MatrixXd::Identity(M.rows(), M.cols()));
  *V = 0.5 * (*V + V->transpose()).eval();
  *G = *V * W * *V;
  *G = 0.5 * (*G + G->transpose()).eval();
  return true;
}

// b_i = tr(X_i G X_i^T) of every pool pose.
void AllB(const CandidatePool& pool, const Eigen::MatrixXd& G, int threads,
          Eigen::VectorXd* b) {
  b->resize(pool.size());
  internal::ForEachQuadraticForm(
      pool, G, threads,
      [&](int64_t i, const Eigen::MatrixXd& S) { (*b)[i] = S.trace(); });
}

}  // namespace

bool SolveTaskApproximateDesign(const CandidatePool& pool,
                                const Eigen::MatrixXd& W,
                                const DesignConstraints& constraints,
                                const TaskApproximateOptions& options,
                                TaskApproximateSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  *summary = TaskApproximateSummary();
  if (!options.IsValid(&summary->message)) {
    summary->termination_type = TerminationType::kUserFailure;
    return false;
  }
  const int p = pool.num_parameters();
  const int t = pool.block_rows();
  CHECK_EQ(W.rows(), p);
  std::vector<char> eligible(pool.size(), 1);
  int64_t num_eligible = 0;
  for (int64_t i = 0; i < pool.size(); ++i) {
    if (constraints.excluded && constraints.excluded(i)) eligible[i] = 0;
    num_eligible += eligible[i];
  }
  auto finish = [&](TerminationType type, const std::string& message) {
    summary->termination_type = type;
    summary->message = message;
    summary->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    return summary->IsSolutionUsable();
  };
  // Start: uniform weights on every eligible pose.
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p), V, G;
  for (int64_t i = 0; i < pool.size(); ++i) {
    if (!eligible[i]) continue;
    const auto X = pool.block(i);
    M.noalias() += X.transpose() * X;
  }
  if (num_eligible == 0 || !Inverses(M / num_eligible, W, &V, &G)) {
    return finish(TerminationType::kFailure,
                  "the eligible poses do not identify every parameter");
  }
  Eigen::VectorXd b;
  AllB(pool, G, options.num_threads, &b);
  const int k_max =
      options.working_set > 0 ? options.working_set : std::max(200, 8 * p);
  // The eligible poses outside `in` of largest b, at most k; ties to the
  // lowest index.
  auto top_by_b = [&](const std::vector<char>& in, int k) {
    std::vector<int64_t> idx;
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (eligible[i] && !in[i]) idx.push_back(i);
    }
    const size_t n = std::min<size_t>(k, idx.size());
    std::partial_sort(idx.begin(), idx.begin() + n, idx.end(),
                      [&](int64_t u, int64_t v) {
                        return b[u] > b[v] || (b[u] == b[v] && u < v);
                      });
    idx.resize(n);
    return idx;
  };
  std::vector<char> in_set(pool.size(), 0);
  std::vector<int64_t> set = top_by_b(in_set, k_max);
  std::vector<double> w(set.size(), 1.0 / set.size());
  RowMatrixXd XS;
  auto gather = [&]() {
    XS.resize(set.size() * t, p);
    for (size_t k = 0; k < set.size(); ++k) {
      XS.middleRows(k * t, t) = pool.block(set[k]);
    }
  };
  // M, V, G of the working set's weights.
  auto weighted = [&]() {
    RowMatrixXd Xw = XS;
    for (size_t k = 0; k < set.size(); ++k) {
      Xw.middleRows(k * t, t) *= std::sqrt(w[k]);
    }
    M.noalias() = Xw.transpose() * Xw;
    return Inverses(M, W, &V, &G);
  };
  gather();
  if (!weighted()) {
    // The top poses alone miss a direction: start from every eligible pose.
    set.clear();
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (eligible[i]) set.push_back(i);
    }
    w.assign(set.size(), 1.0 / set.size());
    gather();
    CHECK(weighted());
  }
  double best_phi = std::numeric_limits<double>::infinity();
  std::vector<int64_t> best_support;
  std::vector<double> best_weights;
  Eigen::VectorXd bs;
  for (int round = 0; round < options.max_rounds; ++round) {
    summary->rounds = round + 1;
    for (int it = 0; it < options.inner_iterations; ++it) {
      // b on the working set: rows of XS G dotted with rows of XS.
      auto working_b = [&]() {
        const RowMatrixXd XG = XS * G;
        bs = (XG.cwiseProduct(XS)).rowwise().sum();
        Eigen::VectorXd out(set.size());
        for (size_t k = 0; k < set.size(); ++k) {
          out[k] = bs.segment(k * t, t).sum();
        }
        return out;
      };
      Eigen::VectorXd bk = working_b();
      // Optimal on the working set (to a quarter of the tolerance): check
      // the whole pool.
      double phi_set = 0;
      for (size_t i = 0; i < set.size(); ++i) phi_set += w[i] * bk[i];
      if (bk.maxCoeff() <= phi_set * (1 + 0.25 * options.tolerance)) break;
      // A multiplicative sweep.
      double total = 0;
      for (size_t k = 0; k < set.size(); ++k) {
        w[k] *= std::sqrt(std::max(bk[k], 0.0));
        total += w[k];
      }
      for (double& x : w) x /= total;
      if (!weighted()) break;  // cannot happen with weights from a PD M
      // A vertex exchange: weight from the support pose of least b to the
      // pose of largest b, by exact line search (phi is convex on the line).
      bk = working_b();
      size_t j = 0, k = set.size();
      for (size_t i = 0; i < set.size(); ++i) {
        if (bk[i] > bk[j]) j = i;
        if (w[i] > 0 && (k == set.size() || bk[i] < bk[k])) k = i;
      }
      if (k == set.size() || j == k || !(bk[j] > bk[k])) continue;
      RowMatrixXd U(2 * t, p);
      U.topRows(t) = pool.block(set[j]);
      U.bottomRows(t) = pool.block(set[k]);
      const Eigen::MatrixXd A = U * V * U.transpose();
      const Eigen::MatrixXd B = U * G * U.transpose();
      // phi(delta) - phi = -tr((I + C A)^-1 C B), C = diag(delta I, -delta I).
      auto change = [&](double delta) {
        Eigen::MatrixXd CA = A, CB = B;
        CA.topRows(t) *= delta;
        CA.bottomRows(t) *= -delta;
        CB.topRows(t) *= delta;
        CB.bottomRows(t) *= -delta;
        CA.diagonal().array() += 1.0;
        Eigen::PartialPivLU<Eigen::MatrixXd> lu(CA);
        return -lu.solve(CB).trace();
      };
      double lo = 0, hi = w[k];
      const double golden = 0.5 * (std::sqrt(5.0) - 1);
      double x1 = hi - golden * (hi - lo), x2 = lo + golden * (hi - lo);
      double f1 = change(x1), f2 = change(x2);
      for (int iter = 0; iter < 60; ++iter) {
        if (f1 < f2) {
          hi = x2;
          x2 = x1;
          f2 = f1;
          x1 = hi - golden * (hi - lo);
          f1 = change(x1);
        } else {
          lo = x1;
          x1 = x2;
          f1 = f2;
          x2 = lo + golden * (hi - lo);
          f2 = change(x2);
        }
      }
      const double delta = 0.5 * (lo + hi);
      if (!(change(delta) < 0)) continue;
      const std::vector<double> before = w;
      w[j] += delta;
      w[k] = std::max(0.0, w[k] - delta);
      if (!weighted()) {
        w = before;
        CHECK(weighted());
      }
    }
    // Drop vanishing weights.
    {
      std::vector<int64_t> s2;
      std::vector<double> w2;
      const double wmax = *std::max_element(w.begin(), w.end());
      for (size_t k = 0; k < set.size(); ++k) {
        if (w[k] > 1e-3 * wmax) {
          s2.push_back(set[k]);
          w2.push_back(w[k]);
        }
      }
      const double total = std::accumulate(w2.begin(), w2.end(), 0.0);
      for (double& x : w2) x /= total;
      set = std::move(s2);
      w = std::move(w2);
      gather();
      if (!weighted()) {
        return finish(TerminationType::kFailure,
                      "dropping vanishing weights made M singular");
      }
    }
    // Check the whole pool.
    AllB(pool, G, options.num_threads, &b);
    const double phi = (W.cwiseProduct(V)).sum();
    double max_b = 0;
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (eligible[i]) max_b = std::max(max_b, b[i]);
    }
    const double lower = phi * phi / max_b;
    if (lower > summary->criterion_lower_bound) {
      summary->criterion_lower_bound = lower;
    }
    if (phi < best_phi) {
      best_phi = phi;
      best_support = set;
      best_weights = w;
      summary->max_b = max_b;
    }
    if (max_b <= phi * (1 + options.tolerance)) break;
    // Next working set: the support and the poses of largest b outside it,
    // which get 5% of the weight to start from.
    std::fill(in_set.begin(), in_set.end(), 0);
    for (int64_t i : set) in_set[i] = 1;
    const std::vector<int64_t> extra = top_by_b(in_set, k_max);
    if (extra.empty()) continue;  // the whole pool is the working set
    for (double& x : w) x *= 0.95;
    for (int64_t i : extra) {
      set.push_back(i);
      w.push_back(0.05 / extra.size());
    }
    gather();
    CHECK(weighted());
  }
  // Support sorted by pool index.
  std::vector<size_t> order(best_support.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t u, size_t v) {
    return best_support[u] < best_support[v];
  });
  for (size_t k : order) {
    summary->support.push_back(best_support[k]);
    summary->weights.push_back(best_weights[k]);
  }
  summary->criterion = best_phi;
  summary->efficiency_lower_bound = summary->criterion_lower_bound / best_phi;
  const bool converged = summary->max_b <= best_phi * (1 + options.tolerance);
  return finish(converged ? TerminationType::kConvergence
                          : TerminationType::kNoConvergence,
                converged ? "" : "max_rounds reached before the tolerance");
}

bool CertifyTaskDesign(const CandidatePool& pool, const Eigen::MatrixXd& W,
                       const DesignConstraints& constraints,
                       const TaskApproximateSummary* approximate,
                       int num_threads, SelectionSummary* summary) {
  const int p = pool.num_parameters();
  summary->efficiency_lower_bound = std::numeric_limits<double>::quiet_NaN();
  summary->task_criterion_lower_bound =
      std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p), V, G;
  for (int64_t i : summary->design) {
    const auto X = pool.block(i);
    M.noalias() += X.transpose() * X;
  }
  if (summary->design.empty() || !Inverses(M, W, &V, &G)) return false;
  const double n = static_cast<double>(summary->design.size());
  const double phi = (W.cwiseProduct(V)).sum();
  Eigen::VectorXd b;
  AllB(pool, G, num_threads, &b);
  double max_b = 0;
  for (int64_t i = 0; i < pool.size(); ++i) {
    if (!(constraints.excluded && constraints.excluded(i))) {
      max_b = std::max(max_b, b[i]);
    }
  }
  double bound = phi * phi / (n * max_b);  // phi_N^2 / (N max b_N)
  if (approximate && approximate->IsSolutionUsable()) {
    bound = std::max(bound, approximate->criterion_lower_bound / n);
  }
  summary->task_criterion_lower_bound = bound;
  summary->efficiency_lower_bound = std::min(1.0, bound / phi);
  return true;
}

}  // namespace activecal
