#include "activecal/selection/approximate_design.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

#include "activecal/selection/criteria.h"
#include "activecal/selection/information_matrix.h"
#include "selection_internal.h"
#include "sub_pool.h"

namespace activecal {

bool ApproximateDesignOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (!(tolerance > 0)) {
    msg << "tolerance must be > 0, got " << tolerance;
  } else if (max_rounds <= 0 || max_inner_iterations <= 0) {
    msg << "max_rounds and max_inner_iterations must be > 0";
  }
  if (msg.tellp() == 0) return true;
  if (error) *error = msg.str();
  return false;
}

namespace {

constexpr double kNegInf = -std::numeric_limits<double>::infinity();

// M(w) over a working set and its inverse.
struct WeightedInformation {
  Eigen::MatrixXd M, V;
  double log_det = kNegInf;
  bool Factor() {
    // Cholesky with a relative pivot test: a numerically singular M(w)
    // would give a meaningless inverse.
    Eigen::LLT<Eigen::MatrixXd> llt(M);
    log_det = LogDetSpd(M);
    if (!std::isfinite(log_det)) return false;
    V = llt.solve(Eigen::MatrixXd::Identity(M.rows(), M.cols()));
    return true;
  }
};

Eigen::MatrixXd Outer(const CandidatePool& pool, int64_t i) {
  const auto X = pool.block(i);
  return X.transpose() * X;
}

// The step alpha in [0, max_step] maximising log det(M + alpha (A+ - A-)),
// A+ = X+^T X+, A- = X-^T X-. With U = [X+^T X-^T], G = U^T V U and
// S = diag(I, -I), log det(M + alpha B) - log det M = log det(I + alpha S G),
// whose derivative tr((I + alpha S G)^-1 S G) decreases in alpha.
double LineSearch(const Eigen::MatrixXd& G, int t, double max_step) {
  const int n = 2 * t;
  Eigen::MatrixXd SG = G;
  SG.bottomRows(t) *= -1.0;
  auto derivative = [&](double a) {
    Eigen::MatrixXd A = a * SG;
    A.diagonal().array() += 1.0;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
    // det(I + a S G) = det M(w') / det M(w): at or near zero the step
    // would make M(w') singular; treat the derivative as -inf there.
    if (!(lu.determinant() > 1e-8)) return kNegInf;
    return lu.solve(SG).trace();
  };
  if (derivative(0.0) <= 0) return 0.0;
  const double at_max = derivative(max_step);
  if (at_max >= 0 && std::isfinite(at_max)) return max_step;
  double lo = 0.0, hi = max_step;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    const double d = derivative(mid);
    if (d > 0 && std::isfinite(d)) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  (void)n;
  return lo;
}

}  // namespace

bool SolveApproximateDesign(const CandidatePool& pool,
                            const DesignConstraints& constraints,
                            const ApproximateDesignOptions& options,
                            ApproximateDesignSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  *summary = ApproximateDesignSummary();
  const int p = pool.num_parameters();
  const int t = pool.block_rows();
  summary->num_parameters = p;
  std::string error;
  if (!options.IsValid(&error)) {
    summary->message = error;
    return false;
  }
  std::vector<char> eligible;
  const int min_poses = (p + t - 1) / t;
  if (!PrepareCandidates(pool,
                         std::max<int>(min_poses, constraints.fixed.size()),
                         constraints, &eligible, &error)) {
    summary->message = error;
    return false;
  }
  for (int64_t f : constraints.fixed) eligible[f] = 1;

  // Start: the poses of largest variance under uniform weights on the pool.
  Eigen::MatrixXd M0 = Eigen::MatrixXd::Zero(p, p);
  int64_t count = 0;
  for (int64_t i = 0; i < pool.size(); ++i) {
    if (!eligible[i]) continue;
    const auto X = pool.block(i);
    M0.noalias() += X.transpose() * X;
    ++count;
  }
  M0 /= static_cast<double>(count);
  Eigen::LLT<Eigen::MatrixXd> llt0(M0);
  if (!std::isfinite(LogDetSpd(M0))) {
    summary->message =
        "the pool's information matrix is singular: no design identifies all " +
        std::to_string(p) + " parameters";
    return false;
  }
  Eigen::VectorXd d;
  ComputeVariances(pool, llt0.solve(Eigen::MatrixXd::Identity(p, p)),
                   options.num_threads, &d);
  // The k eligible poses outside `skip` of largest variance.
  auto top_by_variance = [&](int k, const std::vector<char>& skip) {
    std::vector<char> candidate(pool.size());
    for (int64_t i = 0; i < pool.size(); ++i) {
      candidate[i] = eligible[i] && !skip[i];
    }
    return internal::TopByVariance(d, candidate, k);
  };
  std::vector<char> in_set(pool.size(), 0);
  std::vector<int64_t> working = top_by_variance(4 * p, in_set);
  for (int64_t i : working) in_set[i] = 1;
  std::vector<double> w(working.size(), 1.0 / working.size());
  WeightedInformation info;
  auto rebuild = [&]() {
    info.M = Eigen::MatrixXd::Zero(p, p);
    for (size_t k = 0; k < working.size(); ++k) {
      if (w[k] > 0) info.M.noalias() += w[k] * Outer(pool, working[k]);
    }
    return info.Factor();
  };
  // Grow the start until M(w) is non-singular.
  while (!rebuild()) {
    std::vector<int64_t> more = top_by_variance(p, in_set);
    if (more.empty()) {
      summary->message = "the eligible pool cannot identify all parameters";
      return false;
    }
    for (int64_t i : more) {
      in_set[i] = 1;
      working.push_back(i);
    }
    w.assign(working.size(), 1.0 / working.size());
  }

  const double target = p * (1.0 + options.tolerance);
  const double inner_target = p * (1.0 + 0.5 * options.tolerance);
  Eigen::VectorXd dw;
  for (int round = 0; round < options.max_rounds; ++round) {
    summary->rounds = round + 1;
    if (options.progress) options.progress(round, options.max_rounds);
    // Inner: optimise the weights on the working set. Every
    // kRecomputeInterval steps M(w), V and the variances are recomputed
    // from the weights (and a multiplicative sweep is made); in between,
    // vertex exchanges update V and the variances by rank-2t formulas.
    constexpr int kRecomputeInterval = 25;
    const int64_t nw = static_cast<int64_t>(working.size());
    RowMatrixXd Xw(nw * t, p);
    for (int64_t k = 0; k < nw; ++k) {
      Xw.middleRows(k * t, t) = pool.block(working[k]);
    }
    RowMatrixXd P, Q;
    auto block_traces = [&](const RowMatrixXd& A, const RowMatrixXd& B,
                            Eigen::VectorXd* out) {
      // out_k = sum over block k's rows of the row-wise dot of A and B.
      const Eigen::VectorXd rows = A.cwiseProduct(B).rowwise().sum();
      out->resize(nw);
      for (int64_t k = 0; k < nw; ++k) (*out)[k] = rows.segment(k * t, t).sum();
    };
    Eigen::VectorXd delta, dw_good;
    std::vector<double> w_good = w;
    bool converged_inner = false;
    for (int it = 0; it < options.max_inner_iterations; ++it) {
      ++summary->inner_iterations;
      if (it % kRecomputeInterval == 0) {
        if (it > 0) {
          // Multiplicative sweep: w_k <- w_k d_k / p (sum is preserved).
          for (int64_t k = 0; k < nw; ++k) w[k] *= dw[k] / p;
        }
        if (!rebuild()) {
          // Rounding took M(w) to the edge of singularity: go back to the
          // last good weights and take a multiplicative sweep from there
          // (it keeps every weight positive).
          w = w_good;
          for (int64_t k = 0; k < nw; ++k) w[k] *= dw_good[k] / p;
          if (!rebuild()) {
            summary->message =
                "lost positive definiteness in the weight update";
            return false;
          }
        }
        w_good = w;
        P.noalias() = Xw * info.V;
        block_traces(P, Xw, &dw);
        dw_good = dw;
      }
      int kp = 0, km = -1;
      for (int64_t k = 0; k < nw; ++k) {
        if (dw[k] > dw[kp]) kp = k;
        if (w[k] > 0 && (km < 0 || dw[k] < dw[km])) km = k;
      }
      if (dw[kp] <= inner_target && it % kRecomputeInterval == 0) {
        converged_inner = true;
        break;
      }
      if (kp == km) continue;
      // Vertex exchange: weight from the weakest support pose to the
      // strongest pose, by exact line search.
      Eigen::MatrixXd U(p, 2 * t);
      U.leftCols(t) = Xw.middleRows(kp * t, t).transpose();
      U.rightCols(t) = Xw.middleRows(km * t, t).transpose();
      const Eigen::MatrixXd VU = info.V * U;
      const Eigen::MatrixXd G = U.transpose() * VU;
      const double alpha = LineSearch(G, t, w[km]);
      if (!(alpha > 0)) continue;
      w[kp] += alpha;
      w[km] -= alpha;
      // det M(w') / det M(w) = det(I + alpha S G). A step that takes most
      // of the information out of some direction is not trusted to the
      // update formula: recompute from the weights.
      Eigen::MatrixXd SG = G;
      SG.bottomRows(t) *= -1.0;
      Eigen::MatrixXd R = alpha * SG;
      R.diagonal().array() += 1.0;
      if (!(R.determinant() > 1e-3)) {
        if (w[km] < 1e-14) w[km] = 0.0;
        if (!rebuild()) {
          summary->message = "lost positive definiteness in the weight update";
          return false;
        }
        P.noalias() = Xw * info.V;
        block_traces(P, Xw, &dw);
        continue;
      }
      // V' = V - VU K VU^T with K = (S / alpha + G)^-1, S = diag(I, -I).
      Eigen::MatrixXd C = G;
      C.diagonal().head(t).array() += 1.0 / alpha;
      C.diagonal().tail(t).array() -= 1.0 / alpha;
      const Eigen::MatrixXd K = C.inverse();
      info.V.noalias() -= VU * K * VU.transpose();
      P.noalias() = Xw * VU;
      Q.noalias() = P * K;
      block_traces(P, Q, &delta);
      dw -= delta;
      if (w[km] < 1e-14) w[km] = 0.0;
    }
    if (!converged_inner && !rebuild()) {
      w = w_good;
      if (!rebuild()) {
        summary->message = "lost positive definiteness in the weight update";
        return false;
      }
    }
    // Outer: check the whole pool.
    ComputeVariances(pool, info.V, options.num_threads, &d);
    int64_t arg = -1;
    for (int64_t i = 0; i < pool.size(); ++i) {
      if (eligible[i] && (arg < 0 || d[i] > d[arg])) arg = i;
    }
    summary->max_variance = d[arg];
    summary->log_det = info.log_det;
    if (d[arg] <= target) break;
    // Add the worst violators, drop dead weight that is far from optimal.
    std::vector<int64_t> next;
    std::vector<double> next_w;
    for (size_t k = 0; k < working.size(); ++k) {
      if (w[k] > 0 || d[working[k]] > 0.9 * p) {
        next.push_back(working[k]);
        next_w.push_back(w[k]);
      } else {
        in_set[working[k]] = 0;
      }
    }
    for (int64_t i : top_by_variance(4 * p, in_set)) {
      if (d[i] <= inner_target) break;
      in_set[i] = 1;
      next.push_back(i);
      next_w.push_back(0.0);
    }
    working = std::move(next);
    w = std::move(next_w);
  }
  for (size_t k = 0; k < working.size(); ++k) {
    if (w[k] > 0) {
      summary->support.push_back(working[k]);
      summary->weights.push_back(w[k]);
    }
  }
  summary->log_det_upper_bound =
      summary->log_det + p * std::log(summary->max_variance / p);
  summary->efficiency_lower_bound = p / summary->max_variance;
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  std::ostringstream msg;
  msg << "max variance " << summary->max_variance << " (p = " << p << ") on "
      << summary->support.size() << " support poses after " << summary->rounds
      << " rounds, " << summary->inner_iterations << " inner iterations";
  summary->termination_type = summary->max_variance <= target
                                  ? TerminationType::kConvergence
                                  : TerminationType::kNoConvergence;
  if (summary->termination_type != TerminationType::kConvergence) {
    msg << "; tolerance not reached within the round bound (bounds still "
           "hold)";
  }
  summary->message = msg.str();
  return true;
}

std::string ApproximateDesignSummary::BriefReport() const {
  std::ostringstream out;
  out << "activecal approximate D-optimal design: "
      << TerminationTypeToString(termination_type) << "\n  " << message
      << "\n  log10 det M(w) = " << log_det / std::log(10.0)
      << ", upper bound on log10 det M* = "
      << log_det_upper_bound / std::log(10.0)
      << ", efficiency of w >= " << efficiency_lower_bound << ", " << seconds
      << " s\n";
  return out.str();
}

bool CertifyDesign(const CandidatePool& pool,
                   const DesignConstraints& constraints,
                   const ApproximateDesignSummary* approximate, int num_threads,
                   SelectionSummary* summary) {
  const int p = pool.num_parameters();
  const double N = static_cast<double>(summary->design.size());
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  for (int64_t i : summary->design) M.noalias() += Outer(pool, i);
  const double log_det = LogDetSpd(M);
  if (!std::isfinite(log_det)) return false;
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  Eigen::VectorXd d;
  ComputeVariances(pool, llt.solve(Eigen::MatrixXd::Identity(p, p)),
                   num_threads, &d);
  double max_d = 0;
  for (int64_t i = 0; i < pool.size(); ++i) {
    if (constraints.excluded && constraints.excluded(i)) continue;
    max_d = std::max(max_d, d[i]);
  }
  // Bound from the design's own variance function: w uniform on the
  // design, M(w) = M / N, d_i(w) = N d_i.
  double upper = log_det - p * std::log(N) + p * std::log(N * max_d / p);
  if (approximate && std::isfinite(approximate->log_det_upper_bound)) {
    upper = std::min(upper, approximate->log_det_upper_bound);
  }
  summary->log_det_upper_bound = upper + p * std::log(N);
  summary->efficiency_lower_bound =
      std::exp((log_det - summary->log_det_upper_bound) / p);
  return true;
}

}  // namespace activecal
