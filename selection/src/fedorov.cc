// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Fedorov exchange (fast form of Nguyen & Miller 1992), with the reduced
// pool and the polish over the whole pool.

#include "activecal/selection/fedorov.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/core/validation.h"
#include "activecal/selection/criteria.h"
#include "selection_internal.h"
#include "sub_pool.h"

namespace activecal {

bool FedorovOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (internal::PositivePosesAndRestarts(*this, &msg)) {
    if (max_swaps < 0)
      msg << "max_swaps must be >= 0";
    else if (refresh_interval <= 0)
      msg << "refresh_interval must be > 0";
    else if (reduced_pool_per_pose < 0)
      msg << "reduced_pool_per_pose must be >= 0";
    else if (max_polish_rounds <= 0)
      msg << "max_polish_rounds must be > 0";
    else if (!(min_improvement >= 0))
      msg << "min_improvement must be >= 0";
  }
  return FinishValidation(msg, error);
}

namespace {

using internal::RestartResult;

struct YEntry {
  double trace;
  int64_t pose;
};

// The pair scan's bound beyond the trace bound. For a candidate x and a
// design pose y, with S = I + D_x, the swap's log det ratio is
//   lr = log det S + log det T,  T = I - D_y + D_yx S^-1 D_xy.
// Claim: D_yx S^-1 D_xy <= (l / (1 + l)) D_y, l = lambda_max(D_x). Proof:
// with F = V^1/2 X_x^T and H = V^1/2 X_y^T (V = M^-1 is positive definite),
// D_x = F^T F, D_xy = F^T H, D_y = H^T H, so D_yx S^-1 D_xy = H^T P H with
// P = F (I + F^T F)^-1 F^T. P's eigenvalues are s^2 / (1 + s^2) for the
// singular values s of F (and 0), i.e. l_i / (1 + l_i) for the eigenvalues
// l_i of D_x, all <= l / (1 + l) (s -> s / (1 + s) increases); hence
// P <= (l / (1 + l)) I and H^T P H <= (l / (1 + l)) H^T H. So
//   T <= U = I - D_y / (1 + l).
// If T is positive definite (otherwise the swap is singular and cannot
// win), so is U, and det T <= det U (det is monotone on the positive
// definite cone), i.e.
//   lr <= log det S + sum_i log(1 - mu_i / (1 + l)),  mu_i = eig(D_y);
// when some factor is <= 0, U (hence T) is not positive definite. The scan
// uses min(this, the trace bound tr D_x - tr D_y): the trace bound orders
// the design poses (a break), this one skips pairs and whole candidates.

// det U = prod_i (1 - mu_i inv_c), inv_c = 1 / (1 + l) (l an upper
// estimate); 0 when a factor is <= 0 (U, hence T, not positive definite).
inline double DetBoundFactor(const double* mu, int t, double inv_c) {
  double prod = 1.0;
  for (int i = 0; i < t; ++i) {
    const double f = 1.0 - mu[i] * inv_c;
    if (!(f > 0)) return 0.0;
    prod *= f;
  }
  return prod;
}

// An upper estimate of lambda_max(D) (D positive semidefinite): the 3 x 3
// closed form is cheap but can be off by ~sqrt(eps) ||D|| near repeated
// eigenvalues, hence the margin (over-estimating only loosens the bound);
// never above tr D, which always bounds it.
template <int kT>
double MaxEigenvalueUpper(const Eigen::Matrix<double, kT, kT>& D) {
  const double tr = D.trace();
  if (D.rows() == 1) return D(0, 0);
  double l;
  if constexpr (kT == 3) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(D, Eigen::EigenvaluesOnly);
    l = es.eigenvalues()(2);
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(
        D, Eigen::EigenvaluesOnly);
    l = es.eigenvalues()(D.rows() - 1);
  }
  const double upper = l + 1e-6 * tr;
  return upper < tr ? upper : tr;  // NaN: tr
}

// The eigenvalues of D_y (accurate: once per design pose and scan).
void EigenvaluesOf(const Eigen::MatrixXd& D, double* mu) {
  if (D.rows() == 1) {
    mu[0] = D(0, 0);
    return;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(
      D, Eigen::EigenvaluesOnly);
  for (Eigen::Index i = 0; i < D.rows(); ++i) mu[i] = es.eigenvalues()(i);
}

// Relative slack on the bound, against rounding in det T and det U.
constexpr double kBoundSlack = 1e-9;

// det T if T is positive definite (Sylvester's criterion for t = 3, as
// LogDetSpd), else 0.
template <int kT>
double DetIfSpd(const Eigen::Matrix<double, kT, kT>& T) {
  if constexpr (kT == 3) {
    const double a = T(0, 0), b = T(0, 1), c = T(0, 2);
    const double d = T(1, 1), e = T(1, 2), f = T(2, 2);
    const double m2 = a * d - b * b;
    const double det =
        a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d);
    return a > 0 && m2 > 0 && det > 0 ? det : 0.0;
  } else {
    if (T.rows() == 1) return T(0, 0) > 0 ? T(0, 0) : 0.0;
    const Eigen::LLT<Eigen::MatrixXd> llt(T);
    if (llt.info() != Eigen::Success) return 0.0;
    const auto diag = llt.matrixLLT().diagonal();
    if (!(diag.array() > 0).all()) return 0.0;
    const double r = diag.prod();
    return r * r;
  }
}

// Hints the cache to fetch n doubles from x on.
inline void Prefetch(const double* x, int64_t n) {
#if defined(__GNUC__)
  for (int64_t i = 0; i < n; i += 8) __builtin_prefetch(x + i);
#else
  (void)x;
  (void)n;
#endif
}
constexpr int64_t kPrefetch = 4;

// What one scan knows of the design poses, in ys order.
struct ScanData {
  const CandidatePool* pool;
  const double* D;  // every pose's t x t block D_j (column-major)
  const YEntry* xs;
  const std::vector<YEntry>* ys;
  size_t num_y;
  Eigen::MatrixXd G;       // p x |ys| t: V Y_j^T, side by side
  std::vector<double> A;   // |ys| blocks I - D_y (column-major)
  std::vector<double> mu;  // |ys| x t eigenvalues of D_y
  double threshold;
  double min_try;
};

// Best design pose to swap for each candidate k in [kb, ke) of xs (item_lr,
// item_y; -inf / -1 when none can beat the threshold): the bounds first,
// then the D_xy of the surviving candidates by one product, as
// E = (L_x^-1 X_x) [V Y_1^T ... V Y_n^T] (S = L_x L_x^T), so that
// T = (I - D_y) + E_xy^T E_xy. The candidates of a batch are fixed by
// position, so the result does not depend on the thread count.
template <int kT>
void ScanBatch(const ScanData& c, int t, int64_t kb, int64_t ke,
               double* item_lr, int64_t* item_y) {
  using MatT = Eigen::Matrix<double, kT, kT>;
  const int tt = t * t;
  const int p = c.pool->num_parameters();
  const std::vector<YEntry>& ys = *c.ys;
  struct Survivor {
    int64_t k;
    double gain;
    size_t ny;
    size_t pass;  // offset of its pass flags (one per design pose < ny)
    MatT L;
  };
  std::vector<Survivor> survivors;
  survivors.reserve(ke - kb);
  std::vector<char> pass;
  size_t prefix = 0;
  for (int64_t k = kb; k < ke; ++k) {
    item_lr[k] = -std::numeric_limits<double>::infinity();
    item_y[k] = -1;
    const YEntry& xe = c.xs[k];
    if (xe.trace - c.min_try <= c.threshold) continue;
    // xs are in trace order, so D_x and X_x are read at random: fetch the
    // next candidates' ahead (a cache miss each otherwise).
    if (k + kPrefetch < ke) Prefetch(c.D + c.xs[k + kPrefetch].pose * tt, tt);
    const MatT Dx = Eigen::Map<const MatT>(c.D + xe.pose * tt, t, t);
    MatT Sx = Dx;
    Sx.diagonal().array() += 1.0;
    const double gain = LogDetSpd(Sx);
    if (!(gain > c.threshold)) continue;
    // The trace bound: ys ascend by trace, so a prefix passes.
    size_t ny = 0;
    while (ny < c.num_y && xe.trace - ys[ny].trace > c.threshold) ++ny;
    const double inv_c = 1.0 / (1.0 + MaxEigenvalueUpper<kT>(Dx));
    const double ex = std::exp(c.threshold - gain);
    const size_t offset = pass.size();
    size_t last = 0;
    for (size_t j = 0; j < ny; ++j) {
      const bool ok =
          DetBoundFactor(&c.mu[j * t], t, inv_c) * (1.0 + kBoundSlack) > ex;
      pass.push_back(ok);
      if (ok) last = j + 1;
    }
    const Eigen::LLT<MatT> llt(Sx);
    if (last == 0 || llt.info() != Eigen::Success) {
      pass.resize(offset);
      continue;
    }
    survivors.push_back({k, gain, last, offset, llt.matrixL()});
    Prefetch(c.pool->block(xe.pose).data(), t * p);  // read after the loop
    prefix = std::max(prefix, last);
  }
  if (survivors.empty()) return;
  const int64_t n = static_cast<int64_t>(survivors.size());
  RowMatrixXd Xh(n * t, p);
  for (int64_t i = 0; i < n; ++i) {
    Xh.middleRows(i * t, t) =
        survivors[i].L.template triangularView<Eigen::Lower>().solve(
            c.pool->block(c.xs[survivors[i].k].pose));
  }
  const Eigen::MatrixXd E = Xh * c.G.leftCols(prefix * t);
  const Eigen::Index ld = E.rows();
  MatT T(t, t);
  for (int64_t i = 0; i < n; ++i) {
    const Survivor& s = survivors[i];
    double best = 0.0;
    int64_t best_y = -1;
    for (size_t j = 0; j < s.ny; ++j) {
      if (!pass[s.pass + j]) continue;
      double det;
      if constexpr (kT == 3) {
        // T = A_y + E_xy^T E_xy: its upper triangle from the columns u of
        // E_xy (contiguous), summed in the order of Eigen's 3 x 3 product.
        const double* u0 = E.data() + (j * 3) * ld + i * 3;
        const double* u1 = u0 + ld;
        const double* u2 = u1 + ld;
        const double* A = c.A.data() + j * 9;  // column-major
        const auto dot = [](const double* x, const double* y) {
          return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        };
        const double a = A[0] + dot(u0, u0), b = A[3] + dot(u0, u1);
        const double cc = A[6] + dot(u0, u2), d = A[4] + dot(u1, u1);
        const double e = A[7] + dot(u1, u2), f = A[8] + dot(u2, u2);
        const double m2 = a * d - b * b;
        const double dt =
            a * (d * f - e * e) - b * (b * f - cc * e) + cc * (b * e - cc * d);
        det = a > 0 && m2 > 0 && dt > 0 ? dt : 0.0;
      } else {
        const auto Exy = E.block(i * t, j * t, t, t);
        T = Eigen::Map<const MatT>(c.A.data() + j * tt, t, t);
        T.noalias() += Exy.transpose() * Exy;
        det = DetIfSpd<kT>(T);
      }
      if (det > best) {  // ties: the first design pose in ys order
        best = det;
        best_y = ys[j].pose;
      }
    }
    if (best_y >= 0) {
      item_lr[s.k] = s.gain + std::log(best);
      item_y[s.k] = best_y;
    }
  }
}

}  // namespace

namespace internal {

double SwapLogRatioBound(const Eigen::MatrixXd& Dx, const Eigen::MatrixXd& Dy) {
  const int t = static_cast<int>(Dx.rows());
  Eigen::MatrixXd S = Dx;
  S.diagonal().array() += 1.0;
  const double inv_c =
      1.0 / (1.0 + (t == 3 ? MaxEigenvalueUpper<3>(Eigen::Matrix3d(Dx))
                           : MaxEigenvalueUpper<Eigen::Dynamic>(Dx)));
  std::vector<double> mu(t);
  EigenvaluesOf(Dy, mu.data());
  return LogDetSpd(S) + std::log(DetBoundFactor(mu.data(), t, inv_c));
}

}  // namespace internal

namespace {

RestartResult FedorovRestart(const CandidatePool& pool,
                             const std::vector<char>& eligible,
                             const std::vector<char>& is_fixed,
                             std::vector<int64_t> initial,
                             const FedorovOptions& options, int threads) {
  internal::RestartResult result;
  const int t = pool.block_rows();
  const int p = pool.num_parameters();
  const int tt = t * t;
  const int64_t m = pool.size();
  Design design(pool);
  for (int64_t i : initial) design.Add(i);
  if (!design.information().positive_definite()) return result;
  std::vector<double> D(m * tt);
  auto refresh_all = [&]() {
    design.Rebuild();
    internal::ForEachQuadraticForm(
        pool, design.information().inverse(), threads,
        [&](int64_t i, const Eigen::MatrixXd& S) {
          Eigen::Map<Eigen::MatrixXd>(D.data() + i * tt, t, t) = S;
        });
  };
  auto trace_of = [&](int64_t i) {
    double s = 0;
    for (int k = 0; k < t; ++k) s += D[i * tt + k * t + k];
    return s;
  };
  refresh_all();
  result.history.push_back({SelectionStep::kInitial, -1, -1, design.log_det()});
  int since_refresh = 0;
  constexpr int64_t kBlock = 256;
  constexpr int64_t kBatch = 16;
  int swaps = 0;
  for (;;) {
    for (; swaps < options.max_swaps; ++swaps) {
      std::vector<YEntry> ys;
      for (int64_t y : design.poses()) {
        if (!is_fixed[y]) ys.push_back({trace_of(y), y});
      }
      if (ys.empty()) break;
      std::sort(ys.begin(), ys.end(), [](const YEntry& a, const YEntry& b) {
        return a.trace < b.trace || (a.trace == b.trace && a.pose < b.pose);
      });
      const double min_try = ys[0].trace;
      const double threshold0 = internal::ImprovementThreshold(
          design.log_det(), options.min_improvement);
      std::vector<YEntry> xs;
      for (int64_t x = 0; x < m; ++x) {
        if (!eligible[x] || design.Contains(x)) continue;
        const double tr = trace_of(x);
        if (tr - min_try > threshold0) xs.push_back({tr, x});
      }
      std::sort(xs.begin(), xs.end(), [](const YEntry& a, const YEntry& b) {
        return a.trace > b.trace || (a.trace == b.trace && a.pose < b.pose);
      });
      const Eigen::MatrixXd& V = design.information().inverse();
      double best_lr = threshold0;
      int64_t best_x = -1, best_y = -1;
      // The design poses' data for the scans, in ys order.
      ScanData data;
      data.pool = &pool;
      data.D = D.data();
      data.xs = xs.data();
      data.ys = &ys;
      data.min_try = min_try;
      {
        const int64_t ny = static_cast<int64_t>(ys.size());
        RowMatrixXd Ys(ny * t, p);
        data.A.resize(ny * tt);
        data.mu.resize(ny * t);
        for (int64_t j = 0; j < ny; ++j) {
          Ys.middleRows(j * t, t) = pool.block(ys[j].pose);
          const Eigen::Map<const Eigen::MatrixXd> Dy(D.data() + ys[j].pose * tt,
                                                     t, t);
          EigenvaluesOf(Dy, data.mu.data() + j * t);
          Eigen::Map<Eigen::MatrixXd> Aj(data.A.data() + j * tt, t, t);
          Aj = -Dy;
          Aj.diagonal().array() += 1.0;
        }
        data.G.noalias() = V * Ys.transpose();
      }
      std::vector<double> item_lr(kBlock);
      std::vector<int64_t> item_y(kBlock);
      // Best swap among the first num_x candidates and num_y design poses.
      auto scan = [&](size_t num_x, size_t num_y) {
        data.num_y = num_y;
        for (size_t b = 0; b < num_x; b += kBlock) {
          if (xs[b].trace - min_try <= best_lr) break;
          data.threshold = best_lr;
          data.xs = xs.data() + b;
          const int64_t count = std::min<int64_t>(kBlock, num_x - b);
          const int64_t batches = (count + kBatch - 1) / kBatch;
          ParallelFor(batches, threads, [&](int64_t bb, int64_t be, int) {
            for (int64_t q = bb; q < be; ++q) {
              const int64_t kb = q * kBatch;
              const int64_t ke = std::min(count, kb + kBatch);
              if (t == 3) {
                ScanBatch<3>(data, t, kb, ke, item_lr.data(), item_y.data());
              } else {
                ScanBatch<Eigen::Dynamic>(data, t, kb, ke, item_lr.data(),
                                          item_y.data());
              }
            }
          });
          for (int64_t k = 0; k < count; ++k) {
            if (item_lr[k] > best_lr) {
              best_lr = item_lr[k];
              best_x = xs[b + k].pose;
              best_y = item_y[k];
            }
          }
        }
      };
      // KL exchange first (Atkinson & Donev): the weakest design poses
      // against the strongest candidates. Only when no such swap helps is
      // every pair scanned, so the result is a local optimum over all swaps.
      const size_t kl_y =
          std::min<size_t>(ys.size(), std::max<size_t>(4, ys.size() / 8));
      const size_t kl_x = std::min<size_t>(xs.size(), 64 * kl_y);
      if (options.kl_exchange) scan(kl_x, kl_y);
      if (best_x < 0) scan(xs.size(), ys.size());
      if (best_x < 0) break;

      // The update terms, from V before the swap.
      const auto X = pool.block(best_x);
      const auto Y = pool.block(best_y);
      const Eigen::MatrixXd Wa = V * X.transpose();
      Eigen::MatrixXd Sa = X * Wa;
      Sa.diagonal().array() += 1.0;
      const Eigen::MatrixXd Sa_inv = Sa.inverse();
      const Eigen::MatrixXd V1 = V - Wa * Sa_inv * Wa.transpose();
      const Eigen::MatrixXd Wr = V1 * Y.transpose();
      Eigen::MatrixXd Sr = -(Y * Wr);
      Sr.diagonal().array() += 1.0;
      const Eigen::MatrixXd Sr_inv = Sr.inverse();

      design.Add(best_x);
      if (!design.Remove(best_y)) {
        // Cannot happen for an improving swap; stop rather than loop.
        design.Remove(best_x);
        break;
      }
      result.history.push_back(
          {SelectionStep::kExchange, best_x, best_y, design.log_det()});
      if (++since_refresh >= options.refresh_interval) {
        refresh_all();
        since_refresh = 0;
        continue;
      }
      Eigen::MatrixXd Wb(p, 2 * t);
      Wb.leftCols(t) = Wa;
      Wb.rightCols(t) = Wr;
      internal::ForEachPoseChunk(m, threads, [&](int64_t begin, int64_t n) {
        Eigen::Map<const RowMatrixXd> Xc(pool.stacked().data() + begin * t * p,
                                         n * t, p);
        RowMatrixXd P;
        P.noalias() = Xc * Wb;
        for (int64_t k = 0; k < n; ++k) {
          Eigen::Map<Eigen::MatrixXd> Dj(D.data() + (begin + k) * tt, t, t);
          const auto Pa = P.block(k * t, 0, t, t);
          const auto Pr = P.block(k * t, t, t, t);
          Dj.noalias() -= Pa * Sa_inv * Pa.transpose();
          Dj.noalias() += Pr * Sr_inv * Pr.transpose();
        }
      });
    }
    // No single swap helps: try larger excursions, and swap again after one.
    // Each counts as a step against max_swaps.
    if (swaps >= options.max_swaps) {
      result.hit_bound = options.max_swaps > 0;  // 0: rounding only
      break;
    }
    if (options.max_excursion < 2) break;
    std::vector<int64_t> poses = design.poses();
    SelectionStep step;
    if (!internal::TryExcursion(pool, eligible, is_fixed, 2,
                                options.max_excursion, options.min_improvement,
                                threads, &poses, &step)) {
      break;
    }
    Design next(pool);
    for (int64_t i : poses) next.Add(i);
    design = std::move(next);
    refresh_all();
    since_refresh = 0;
    ++swaps;
    step.log_det = design.log_det();
    result.history.push_back(step);
  }
  internal::FinishRestart(pool, design.poses(), &result);
  return result;
}

// Swaps over the polish_pool_size poses of largest variance under the
// current design, re-ranked after each round, until a round makes no swap
// or max_polish_rounds have run.
RestartResult PolishInRounds(const CandidatePool& pool,
                             const std::vector<char>& eligible,
                             const std::vector<char>& is_fixed,
                             std::vector<int64_t> design,
                             const FedorovOptions& options) {
  RestartResult result;
  std::vector<SelectionStep> history;
  // <= 0 (a single-precision pool): every eligible pose.
  const int64_t polish_size =
      options.polish_pool_size > 0 ? options.polish_pool_size : pool.size();
  for (int round = 0;; ++round) {
    if (round >= options.max_polish_rounds) {
      result.hit_bound = true;
      break;
    }
    const int p = pool.num_parameters();
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
    for (int64_t i : design) {
      const RowMatrixXd X = pool.CopyBlock(i);
      M.noalias() += X.transpose() * X;
    }
    Eigen::VectorXd d;
    if (!internal::VariancesUnder(pool, M, options.num_threads, &d)) break;
    // The design, the fixed poses and the eligible poses of largest
    // variance outside them.
    std::vector<char> keep = is_fixed, candidate(pool.size());
    for (int64_t i : design) keep[i] = 1;
    for (int64_t i = 0; i < pool.size(); ++i) {
      candidate[i] = eligible[i] && !keep[i];
    }
    for (int64_t i : internal::TopByVariance(d, candidate, polish_size)) {
      keep[i] = 1;
    }
    const internal::SubPool sub(pool, keep);
    RestartResult r = FedorovRestart(sub.pool(), sub.Restrict(eligible),
                                     sub.Restrict(is_fixed), sub.ToSub(design),
                                     options, options.num_threads);
    if (!r.ok) break;
    r.design = sub.ToFull(r.design);
    sub.ToFull(&r.history);
    const bool changed = r.history.size() > 1;
    history.insert(history.end(), r.history.begin() + 1, r.history.end());
    design = r.design;
    r.history.clear();
    r.history.push_back(SelectionStep());  // the caller skips entry 0
    r.history.insert(r.history.end(), history.begin(), history.end());
    result = std::move(r);
    if (!changed) break;
  }
  return result;
}

}  // namespace

bool FedorovExchange(const CandidatePool& pool,
                     const DesignConstraints& constraints,
                     const FedorovOptions& options,
                     const ApproximateDesignSummary* approximate,
                     SelectionSummary* summary) {
  internal::SelectionStart start;
  if (!internal::PrepareSelection(pool, constraints, options, "fedorov",
                                  summary, &start)) {
    return false;
  }
  const std::vector<char>& eligible = start.eligible;
  const std::vector<char>& is_fixed = start.is_fixed;
  // With an approximate design and a large pool, the restarts swap within
  // a reduced pool first: the approximate design's support and the poses of
  // largest variance under it, where good exact designs live. The best
  // result is then polished by swaps over the whole pool, so it is a local
  // optimum of the full problem either way.
  // A single-precision pool is only ever read through Rows/CopyBlock here:
  // the restarts need the approximate design's reduced (double) pool, and
  // the polish runs in rounds on (double) sub-pools.
  const bool single = pool.single_precision();
  const bool have_approximate = approximate && !approximate->support.empty();
  if (single && !have_approximate) {
    summary->message =
        "fedorov on a single-precision pool needs an approximate design (its "
        "restarts run on the reduced double pool it gives)";
    return false;
  }
  const int64_t reduced_size =
      options.reduced_pool_size > 0
          ? std::max<int64_t>(options.reduced_pool_size,
                              options.reduced_pool_per_pose *
                                  static_cast<int64_t>(options.num_poses))
          : pool.size();
  std::unique_ptr<internal::SubPool> reduced;
  ApproximateDesignSummary reduced_approximate;
  if (have_approximate && (single || (options.reduced_pool_size > 0 &&
                                      pool.size() > reduced_size))) {
    const int p = pool.num_parameters();
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
    for (size_t k = 0; k < approximate->support.size(); ++k) {
      const RowMatrixXd X = pool.CopyBlock(approximate->support[k]);
      M.noalias() += approximate->weights[k] * X.transpose() * X;
    }
    Eigen::VectorXd d;
    if (internal::VariancesUnder(pool, M, options.num_threads, &d)) {
      // The fixed poses, the eligible support and the eligible poses of
      // largest variance.
      std::vector<char> keep = is_fixed;
      for (int64_t i : approximate->support) keep[i] = keep[i] || eligible[i];
      for (int64_t i : internal::TopByVariance(d, eligible, reduced_size)) {
        keep[i] = 1;
      }
      reduced = std::make_unique<internal::SubPool>(pool, keep);
      reduced_approximate = reduced->Restrict(*approximate);
    }
  }
  if (single && !reduced) {
    summary->message =
        "fedorov on a single-precision pool: the approximate design's "
        "information matrix is singular";
    return false;
  }
  const internal::WorkingSet work(pool, reduced.get(), constraints, eligible,
                                  is_fixed);
  const ApproximateDesignSummary* work_approximate =
      reduced ? &reduced_approximate : approximate;
  std::vector<std::string> notes(options.restarts);
  RestartResult best = internal::BestOfRestarts(
      options.restarts, options.num_threads,
      [&](int r, int threads) {
        const std::vector<int64_t> initial = internal::InitialDesign(
            work, options.num_poses, Random::StreamSeed(options.seed, r),
            work_approximate, r > 0, threads, &notes[r]);
        if (initial.empty()) return RestartResult();
        return FedorovRestart(work.pool, work.eligible, work.is_fixed, initial,
                              options, threads);
      },
      options.progress);
  const auto restarts_done = std::chrono::steady_clock::now();
  std::string timing;
  if (reduced && best.ok) {
    const std::vector<int64_t> initial = reduced->ToFull(best.design);
    RestartResult polished;
    const bool whole_pool =
        !single && (options.polish_pool_size <= 0 ||
                    pool.size() <= options.polish_pool_size);
    if (options.max_swaps == 0) {
      // Rounding only: the polish could make no swap, and would build a
      // double sub-pool (of the whole eligible pool at polish_pool_size <= 0:
      // a single-precision pool held twice).
      polished.ok = true;
      polished.design = initial;
      polished.history.push_back(SelectionStep());  // skipped below
    } else if (whole_pool) {
      polished = FedorovRestart(pool, eligible, is_fixed, initial, options,
                                options.num_threads);
    } else {
      polished = PolishInRounds(pool, eligible, is_fixed, initial, options);
    }
    std::vector<SelectionStep> history = best.history;
    reduced->ToFull(&history);
    if (!polished.history.empty()) {
      history.insert(history.end(), polished.history.begin() + 1,
                     polished.history.end());
    }
    polished.history = std::move(history);
    polished.restart = best.restart;
    const size_t reduced_steps = best.history.size();
    polished.hit_bound = polished.hit_bound || best.hit_bound;
    if (polished.ok) {
      best = std::move(polished);
    } else {
      best.design = initial;  // the reduced pool's best, in full indices
      reduced->ToFull(&best.history);
    }
    std::ostringstream msg;
    msg.precision(3);
    msg << "restarts on a reduced pool of " << reduced->size() << " poses "
        << std::chrono::duration<double>(restarts_done - start.time).count()
        << " s, then " << best.history.size() - reduced_steps
        << (whole_pool ? " swaps over the whole pool "
                       : " swaps in rounds over the " +
                             std::to_string(options.polish_pool_size > 0
                                                ? options.polish_pool_size
                                                : pool.size()) +
                             " poses of largest variance ")
        << std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         restarts_done)
               .count()
        << " s";
    timing = msg.str();
  }
  if (best.ok) {
    // In double from the exact blocks (the stored ones of a double pool
    // without an exact source), whatever pool the swaps ran on.
    best.log_det = internal::LogDetOfExactBlocks(pool, best.design);
    best.ok = std::isfinite(best.log_det);
  }
  std::string note = internal::NoteOf(notes, best.restart);
  if (!timing.empty()) note = note.empty() ? timing : note + "; " + timing;
  internal::FinishSummary(best, options.restarts, start.time, note, summary);
  return summary->IsSolutionUsable();
}

}  // namespace activecal
