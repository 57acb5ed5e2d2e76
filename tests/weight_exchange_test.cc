// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The inner solver of the approximate design (selection/src/weight_exchange.h):
// the exchange step against a brute-force search, the Woodbury update of
// V against recomputation, and the solver's result against the
// equivalence theorem.

#include "weight_exchange.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numeric>

#include "activecal/core/random.h"
#include "test_util.h"

namespace activecal {
namespace {

RowMatrixXd RandomBlocks(int num_blocks, int t, int p, uint64_t seed) {
  Random random(seed);
  RowMatrixXd X(num_blocks * t, p);
  for (int i = 0; i < X.rows(); ++i) {
    for (int j = 0; j < p; ++j) X(i, j) = random.Gaussian();
  }
  return X;
}

Eigen::MatrixXd Information(const RowMatrixXd& X, int t,
                            const std::vector<double>& w) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(X.cols(), X.cols());
  for (size_t k = 0; k < w.size(); ++k) {
    const auto B = X.middleRows(k * t, t);
    M += w[k] * B.transpose() * B;
  }
  return M;
}

// G of the pair (a gains, b loses) under V.
Eigen::MatrixXd PairG(const RowMatrixXd& X, int t, int a, int b,
                      const Eigen::MatrixXd& V) {
  Eigen::MatrixXd U(X.cols(), 2 * t);
  U << X.middleRows(a * t, t).transpose(), X.middleRows(b * t, t).transpose();
  return U.transpose() * V * U;
}

// Orders the pair so that a has the larger variance (it gains); G of the
// ordered pair and B = A_a - A_b, the direction of the exchange in M.
void OrderPair(const RowMatrixXd& X, int t, const Eigen::MatrixXd& V, int* a,
               int* b, Eigen::MatrixXd* G, Eigen::MatrixXd* B) {
  *G = PairG(X, t, *a, *b, V);
  if (G->topLeftCorner(t, t).trace() < G->bottomRightCorner(t, t).trace()) {
    std::swap(*a, *b);
    *G = PairG(X, t, *a, *b, V);
  }
  *B = X.middleRows(*a * t, t).transpose() * X.middleRows(*a * t, t) -
       X.middleRows(*b * t, t).transpose() * X.middleRows(*b * t, t);
}

TEST(WeightExchangeTest, StepMaximisesLogDetAlongTheExchange) {
  for (int t : {1, 3, 6}) {
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      const int p = 8, m = 2 * p / t + 2;  // M(w) non-singular
      const RowMatrixXd X = RandomBlocks(m, t, p, seed);
      std::vector<double> w(m, 1.0 / m);
      const Eigen::MatrixXd M = Information(X, t, w);
      const Eigen::MatrixXd V = M.inverse();
      int a = static_cast<int>(seed % m), b = static_cast<int>((seed + 1) % m);
      Eigen::MatrixXd G, B;
      OrderPair(X, t, V, &a, &b, &G, &B);
      auto f = [&](double alpha) {
        return testing::CholeskyLogDet(M + alpha * B) -
               testing::CholeskyLogDet(M);
      };
      double ratio = 0;
      const double alpha = internal::ExchangeStep(G, t, w[b], &ratio);
      ASSERT_GE(alpha, 0.0);
      ASSERT_LE(alpha, w[b]);
      // A fine grid never beats the step by more than the grid's own
      // resolution costs, and the step is on the grid's best cell.
      double best = 0, best_f = 0;
      constexpr int kGrid = 20000;
      for (int k = 1; k < kGrid; ++k) {
        const double x = w[b] * k / kGrid;
        const double v = f(x);
        if (std::isfinite(v) && v > best_f) {
          best_f = v;
          best = x;
        }
      }
      EXPECT_GE(f(alpha), best_f - 1e-9) << "t " << t << " seed " << seed;
      EXPECT_NEAR(alpha, best, 2.0 * w[b] / kGrid + 1e-6 * w[b])
          << "t " << t << " seed " << seed;
      EXPECT_NEAR(ratio, std::exp(f(alpha)), 1e-9 * std::exp(f(alpha)));
    }
  }
}

// The step against a brute-force search (a grid refined by golden
// section) on random and adversarial pairs: duplicate and collinear blocks,
// a zero block, a loser that alone carries a direction (the step may not
// empty it), rank-deficient blocks, scales 1e6 apart, and losing or gaining
// weights of 1e-12 and 1e-300. The step stays in [0, max_step], never
// decreases log det, and is the maximiser to 1e-9 in log det.
TEST(WeightExchangeTest, StepAgainstBruteForceOnAdversarialPairs) {
  Random random(5);
  int checked = 0;
  for (int t : {1, 2, 3, 6}) {
    for (int seed = 0; seed < 48; ++seed) {
      const int p = 4 + seed % 9, m = std::max(3, 2 * p / t + 1 + seed % 5);
      RowMatrixXd X = RandomBlocks(m, t, p, 1000 * t + seed);
      const int kind = seed % 8;
      int a = 0, b = 1;
      if (kind == 1) X.middleRows(b * t, t) = X.middleRows(a * t, t);
      if (kind == 2) X.middleRows(a * t, t) = 2.0 * X.middleRows(b * t, t);
      if (kind == 3) X.middleRows(b * t, t) = 0.5 * X.middleRows(a * t, t);
      if (kind == 4) X.middleRows(b * t, t).setZero();
      if (kind == 5) {  // only b sees the last coordinate
        for (int k = 0; k < m; ++k) {
          if (k != b) X.block(k * t, p - 1, t, 1).setZero();
        }
      }
      if (kind == 6) X.middleRows(a * t, t).rightCols(p - 1).setZero();
      if (kind == 7) {
        X *= 1e6;
        X.middleRows(b * t, t) *= 1e-6;
      }
      std::vector<double> w(m);
      for (double& x : w) x = 0.01 + random.Uniform();
      const double total = std::accumulate(w.begin(), w.end(), 0.0);
      for (double& x : w) x /= total;
      if (seed % 3 == 0) w[b] = seed % 6 == 0 ? 1e-300 : 1e-12;
      const Eigen::MatrixXd M = Information(X, t, w);
      if (Eigen::LLT<Eigen::MatrixXd>(M).info() != Eigen::Success) continue;
      const Eigen::MatrixXd V = M.inverse();
      Eigen::MatrixXd G, B;
      OrderPair(X, t, V, &a, &b, &G, &B);
      const double l0 = testing::CholeskyLogDet(M);
      auto f = [&](double x) {
        const Eigen::LLT<Eigen::MatrixXd> llt(M + x * B);
        if (llt.info() != Eigen::Success) return -HUGE_VAL;
        const double v = testing::CholeskyLogDet(M + x * B) - l0;
        return std::isfinite(v) ? v : -HUGE_VAL;
      };
      const double ms = w[b];
      double ratio = 0;
      const double alpha = internal::ExchangeStep(G, t, ms, &ratio);
      ASSERT_GE(alpha, 0.0) << "t " << t << " seed " << seed;
      ASSERT_LE(alpha, ms) << "t " << t << " seed " << seed;
      double best = 0, best_f = 0;
      constexpr int kGrid = 1000;
      for (int k = 1; k <= kGrid; ++k) {
        const double v = f(ms * k / kGrid);
        if (v > best_f) {
          best_f = v;
          best = ms * k / kGrid;
        }
      }
      double lo = std::max(0.0, best - ms / kGrid);
      double hi = std::min(ms, best + ms / kGrid);
      for (int k = 0; k < 200; ++k) {
        const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
        if (f(m1) < f(m2)) {
          lo = m1;
        } else {
          hi = m2;
        }
      }
      best_f = std::max(best_f, f(0.5 * (lo + hi)));
      const double fa = f(alpha);
      EXPECT_GE(fa, -1e-12 * std::max(1.0, std::fabs(l0)))
          << "t " << t << " seed " << seed;
      EXPECT_GE(fa, best_f - 1e-9 * std::max(1.0, best_f))
          << "t " << t << " seed " << seed << " alpha " << alpha << " best "
          << best;
      EXPECT_TRUE(std::isfinite(ratio));
      ++checked;
    }
  }
  EXPECT_GT(checked, 150);
}

TEST(WeightExchangeTest, StepTakesTheWholeWeightOrNothing) {
  // b = 0.5 a: moving all of b's weight to a only adds information.
  const int p = 3, t = 1;
  RowMatrixXd X(4, p);
  X << 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, 0, 0;
  std::vector<double> w = {0.25, 0.25, 0.25, 0.25};
  const Eigen::MatrixXd V = Information(X, t, w).inverse();
  double ratio = 0;
  EXPECT_EQ(internal::ExchangeStep(PairG(X, t, 0, 3, V), t, w[3], &ratio),
            w[3]);
  EXPECT_GT(ratio, 1.0);
  // The other way round (weight from the stronger to the weaker) nothing
  // moves.
  EXPECT_EQ(internal::ExchangeStep(PairG(X, t, 3, 0, V), t, w[0], &ratio), 0.0);
  EXPECT_EQ(ratio, 1.0);
}

TEST(WeightExchangeTest, PairUpdateOfVMatchesRecomputation) {
  for (int t : {1, 3, 6}) {
    const int p = 10, m = 12;
    const RowMatrixXd X = RandomBlocks(m, t, p, 7 + t);
    std::vector<double> w(m);
    Random random(3);
    for (double& x : w) x = 0.5 + random.Uniform();
    const double total = std::accumulate(w.begin(), w.end(), 0.0);
    for (double& x : w) x /= total;
    Eigen::MatrixXd V = Information(X, t, w).inverse();
    internal::PairWorkspace work;
    int moved = 0;
    for (int k = 0; k < 200; ++k) {
      const int a = static_cast<int>(random.UniformInt(m));
      const int b = static_cast<int>(random.UniformInt(m));
      if (a == b) continue;
      const double before = testing::CholeskyLogDet(Information(X, t, w));
      moved += internal::ExchangePair(X, t, a, b, &w, &V, &work);
      const Eigen::MatrixXd M = Information(X, t, w);
      // Every step increases log det M(w) (or leaves it).
      ASSERT_GE(testing::CholeskyLogDet(M), before - 1e-12);
      const Eigen::MatrixXd V_exact = M.inverse();
      ASSERT_LE((V - V_exact).norm(), 1e-8 * V_exact.norm())
          << "t " << t << " step " << k;
    }
    EXPECT_GT(moved, 50);
    for (double x : w) EXPECT_GE(x, 0.0);
    EXPECT_NEAR(std::accumulate(w.begin(), w.end(), 0.0), 1.0, 1e-12);
  }
}

// The fallback: an iteration whose weights M(w) fails the singularity
// test (here the relative empty-column test of LogDetSpd: the optimum
// (1/2, 1/2) puts 1.5e-15 on a column against 0.5 on the other) ends the
// solve on the last good weights, reported as success (the caller's
// whole-pool sweep judges them), with M, V and d recomputed from them.
TEST(WeightExchangeTest, SingularIterationFallsBackToTheLastGoodWeights) {
  const int t = 1, p = 2;
  RowMatrixXd X(2, p);
  X << std::sqrt(3e-15), 0, 0, 1;
  std::vector<double> w = {0.99, 0.01};
  const std::vector<double> start = w;
  internal::WeightExchangeOptions options;
  options.target = p * (1 + 1e-6);
  options.max_iterations = 100;
  options.num_top = p;
  Random random(1);
  internal::WeightedInformation info;
  Eigen::VectorXd d;
  int64_t iterations = 0;
  std::string error;
  ASSERT_TRUE(internal::ExchangeWeights(X, t, options, &random, &w, &info, &d,
                                        &iterations, &error))
      << error;
  EXPECT_EQ(iterations, 1);
  EXPECT_EQ(w, start);
  EXPECT_GT(d.maxCoeff(), options.target);  // not converged
  const Eigen::MatrixXd M = Information(X, t, w);
  EXPECT_LE((info.M - M).norm(), 1e-12 * M.norm());
  EXPECT_NEAR(d[0], 1 / w[0], 1e-9);
  EXPECT_NEAR(d[1], 1 / w[1], 1e-9);
}

TEST(WeightExchangeTest, SolverReachesTheEquivalenceTheoremAndIsSeeded) {
  const int t = 3, p = 12, m = 150;
  const RowMatrixXd X = RandomBlocks(m, t, p, 11);
  internal::WeightExchangeOptions options;
  options.target = p * (1 + 1e-6);
  options.max_iterations = 100000;
  options.num_top = p;
  auto solve = [&](uint64_t seed, std::vector<double>* w,
                   internal::WeightedInformation* info, Eigen::VectorXd* d) {
    w->assign(m, 1.0 / m);
    Random random(seed);
    int64_t iterations = 0;
    std::string error;
    EXPECT_TRUE(internal::ExchangeWeights(X, t, options, &random, w, info, d,
                                          &iterations, &error))
        << error;
    return iterations;
  };
  std::vector<double> w, w2, w3;
  internal::WeightedInformation info, info2, info3;
  Eigen::VectorXd d, d2, d3;
  const int64_t iterations = solve(1, &w, &info, &d);
  EXPECT_GT(iterations, 1);
  // Kiefer-Wolfowitz: max d = p at the optimum.
  EXPECT_LE(d.maxCoeff(), options.target);
  // sum_k w_k d_k = tr(M^-1 M) = p: the variances belong to the weights.
  double weighted = 0;
  for (int k = 0; k < m; ++k) weighted += w[k] * d[k];
  EXPECT_NEAR(weighted, p, 1e-9);
  // What is returned is recomputed from the weights.
  const Eigen::MatrixXd M = Information(X, t, w);
  EXPECT_LE((info.M - M).norm(), 1e-12 * M.norm());
  EXPECT_LE((info.V - M.inverse()).norm(), 1e-9 * info.V.norm());
  EXPECT_NEAR(info.log_det, testing::CholeskyLogDet(M), 1e-10);
  for (int k = 0; k < m; ++k) {
    const auto B = X.middleRows(k * t, t);
    EXPECT_NEAR(d[k], (B * M.inverse() * B.transpose()).trace(), 1e-8);
  }
  // The same seed, the same weights; another seed, the same optimum M*
  // (log det is strictly concave in M).
  solve(1, &w2, &info2, &d2);
  EXPECT_EQ(w, w2);
  solve(2, &w3, &info3, &d3);
  EXPECT_NE(w, w3);
  EXPECT_NEAR(info.log_det, info3.log_det, 1e-5);
}

}  // namespace
}  // namespace activecal
