// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "weight_exchange.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <utility>

#include "activecal/selection/information_matrix.h"

namespace activecal {
namespace internal {

bool WeightedInformation::Factor() {
  // A relative pivot test (LogDetSpd): a numerically singular M(w) would
  // give a meaningless inverse.
  const double ld = LogDetSpd(M);
  if (!std::isfinite(ld)) return false;
  log_det = ld;
  V = Eigen::LLT<Eigen::MatrixXd>(M).solve(
      Eigen::MatrixXd::Identity(M.rows(), M.cols()));
  return true;
}

double ExchangeStep(const Eigen::MatrixXd& G, int t, double max_step,
                    double* det_ratio) {
  // The search ends when the gain still possible is below this (in log
  // det): f' decreases, so f(a*) - f(lo) <= f'(lo) (hi - lo) and
  // f(a*) - f(hi) <= -f'(hi) (hi - lo) for a* in [lo, hi]. (A tolerance
  // relative to f'(0) stopped far short of the maximiser when f' falls
  // steeply, as log(1 + a g) with g ~ 1e12 for a pose of near-zero weight
  // in a direction the support hardly covers.)
  constexpr double kGainTolerance = 1e-12;
  // f(a) = log det(I + a S G): f'(a) = tr(B), f''(a) = -tr(B B) with
  // B = (I + a S G)^-1 S G; f' decreases in a. Safeguarded Newton on f'
  // inside a bracket [lo, hi] with f'(lo) > 0.
  const int n = 2 * t;
  Eigen::MatrixXd SG = G;
  SG.bottomRows(t) *= -1.0;
  Eigen::MatrixXd A(n, n), B(n, n);
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(n);
  double det = 1.0, f1 = 0.0, f2 = 0.0;
  // f' and f'' at a; false where I + a S G is singular or not positive
  // (beyond the step that would make M(w) singular).
  auto evaluate = [&](double a) {
    A = a * SG;
    A.diagonal().array() += 1.0;
    lu.compute(A);
    det = lu.determinant();
    if (!(det > 1e-12)) return false;
    B = lu.solve(SG);
    f1 = B.trace();
    f2 = -B.cwiseProduct(B.transpose()).sum();
    return true;
  };
  *det_ratio = 1.0;
  evaluate(0.0);
  if (!(f1 > 0)) return 0.0;
  // M + a (A+ - A-) >= (1 - a / max_step) M for a <= max_step (the weight
  // of A- is max_step): non-singular below max_step, maybe singular at it.
  if (evaluate(max_step) && f1 >= 0) {
    *det_ratio = det;
    return max_step;
  }
  evaluate(0.0);
  double lo = 0.0, hi = max_step, a = 0.0;
  double lo_det = 1.0;
  for (int k = 0; k < 200; ++k) {
    double next = f2 < 0 ? a - f1 / f2 : hi;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) break;  // the bracket is one ulp wide
    a = next;
    if (evaluate(a) && f1 > 0) {
      lo = a;
      lo_det = det;
      if (f1 * (hi - lo) <= kGainTolerance) break;
    } else {
      hi = a;
      if (!std::isfinite(det) || !(det > 1e-12)) {
        // No derivative here: continue from the bracket's left end.
        evaluate(lo);
        a = lo;
      } else if (-f1 * (hi - lo) <= kGainTolerance) {
        // Converged from the right: a is the maximiser to the tolerance.
        *det_ratio = det;
        return a;
      }
    }
  }
  *det_ratio = lo_det;
  return lo;
}

bool ExchangePair(const RowMatrixXd& Xw, int t, int64_t a, int64_t b,
                  std::vector<double>* w, Eigen::MatrixXd* V,
                  PairWorkspace* work) {
  const int p = static_cast<int>(Xw.cols());
  Eigen::MatrixXd& U = work->U;
  Eigen::MatrixXd& VU = work->VU;
  Eigen::MatrixXd& G = work->G;
  U.resize(p, 2 * t);
  U.leftCols(t) = Xw.middleRows(a * t, t).transpose();
  U.rightCols(t) = Xw.middleRows(b * t, t).transpose();
  // Small products: coefficient-based (lazy) products beat the blocked
  // kernel at these sizes.
  VU.noalias() = V->lazyProduct(U);
  G.noalias() = U.transpose().lazyProduct(VU);
  if (G.topLeftCorner(t, t).trace() < G.bottomRightCorner(t, t).trace()) {
    // b has the larger variance: it gains; put it first.
    std::swap(a, b);
    work->C.resize(2 * t, 2 * t);
    work->C.topLeftCorner(t, t) = G.bottomRightCorner(t, t);
    work->C.bottomRightCorner(t, t) = G.topLeftCorner(t, t);
    work->C.topRightCorner(t, t) = G.bottomLeftCorner(t, t);
    work->C.bottomLeftCorner(t, t) = G.topRightCorner(t, t);
    G.swap(work->C);
    VU.leftCols(t).swap(VU.rightCols(t));
  }
  const double available = (*w)[b];
  if (!(available > 0)) return false;
  double ratio = 1.0;
  const double alpha = ExchangeStep(G, t, available, &ratio);
  if (!(alpha > 0)) return false;
  (*w)[a] += alpha;
  (*w)[b] = alpha >= available ? 0.0 : available - alpha;
  // V' = V - VU (S / alpha + G)^-1 VU^T (Woodbury, S^-1 = S).
  work->C = G;
  work->C.diagonal().head(t).array() += 1.0 / alpha;
  work->C.diagonal().tail(t).array() -= 1.0 / alpha;
  work->K = work->C.inverse();
  work->C.noalias() = VU.lazyProduct(work->K);  // p x 2t
  V->noalias() -= work->C.lazyProduct(VU.transpose());
  return true;
}

bool ExchangeWeights(const RowMatrixXd& Xw, int t,
                     const WeightExchangeOptions& options, Random* random,
                     std::vector<double>* w_ptr, WeightedInformation* info,
                     Eigen::VectorXd* d, int64_t* iterations,
                     std::string* error) {
  std::vector<double>& w = *w_ptr;
  const int64_t nw = static_cast<int64_t>(w.size());
  const int p = static_cast<int>(Xw.cols());
  RowMatrixXd Xs, P;
  // M(w), V and the variances from the weights.
  auto recompute = [&]() {
    int64_t support = 0;
    for (int64_t k = 0; k < nw; ++k) support += w[k] > 0;
    Xs.resize(support * t, p);
    int64_t row = 0;
    for (int64_t k = 0; k < nw; ++k) {
      if (!(w[k] > 0)) continue;
      Xs.middleRows(row, t) = std::sqrt(w[k]) * Xw.middleRows(k * t, t);
      row += t;
    }
    info->M.noalias() = Xs.transpose() * Xs;
    if (!info->Factor()) return false;
    P.noalias() = Xw * info->V;
    const Eigen::VectorXd rows = P.cwiseProduct(Xw).rowwise().sum();
    d->resize(nw);
    for (int64_t k = 0; k < nw; ++k) (*d)[k] = rows.segment(k * t, t).sum();
    return true;
  };
  if (!recompute()) {
    *error = "the information matrix of the working set is singular";
    return false;
  }
  std::vector<double> w_good = w;
  PairWorkspace work;
  std::vector<int64_t> pairs;
  std::vector<char> in_pairs(nw);
  for (int it = 0; it < options.max_iterations; ++it) {
    int64_t kp = 0, km = -1;
    for (int64_t k = 0; k < nw; ++k) {
      if ((*d)[k] > (*d)[kp]) kp = k;
      if (w[k] > 0 && (km < 0 || (*d)[k] < (*d)[km])) km = k;
    }
    if ((*d)[kp] <= options.target) break;
    ++*iterations;
    Eigen::MatrixXd& V = info->V;
    auto step = [&](int64_t a, int64_t b) {
      if (a != b) ExchangePair(Xw, t, a, b, &w, &V, &work);
    };
    step(kp, km);
    // The random pairs: the support and the num_top poses of largest
    // variance, shuffled (Fisher-Yates), paired in turn.
    pairs.clear();
    std::fill(in_pairs.begin(), in_pairs.end(), 0);
    for (int64_t k = 0; k < nw; ++k) {
      if (w[k] > 0) {
        pairs.push_back(k);
        in_pairs[k] = 1;
      }
    }
    std::vector<int64_t> order(nw);
    for (int64_t k = 0; k < nw; ++k) order[k] = k;
    const int64_t top = std::min<int64_t>(options.num_top, nw);
    std::partial_sort(order.begin(), order.begin() + top, order.end(),
                      [&](int64_t x, int64_t y) {
                        return (*d)[x] > (*d)[y] ||
                               ((*d)[x] == (*d)[y] && x < y);
                      });
    for (int64_t k = 0; k < top; ++k) {
      if (!in_pairs[order[k]]) pairs.push_back(order[k]);
    }
    for (int64_t k = static_cast<int64_t>(pairs.size()) - 1; k > 0; --k) {
      std::swap(pairs[k], pairs[random->UniformInt(k + 1)]);
    }
    for (size_t k = 0; k + 1 < pairs.size(); k += 2) {
      step(pairs[k], pairs[k + 1]);
    }
    if (recompute()) {
      w_good = w;
    } else {
      // Rounding took M(w) to the edge of singularity: back to the last
      // good weights.
      w = w_good;
      if (!recompute()) {
        *error = "lost positive definiteness in the weight update";
        return false;
      }
      break;
    }
  }
  return true;
}

}  // namespace internal
}  // namespace activecal
