// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Fedorov at scale (issue #17): the pair scan's bound and batched products,
// single-precision pools, and results for any thread count.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/information_matrix.h"
#include "test_util.h"

namespace activecal {
namespace {

Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937_64* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd A(rows, cols);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) A(i, j) = n(*rng);
  }
  return A;
}

// The exact log det ratio of swapping x in for y, from scratch.
double ExactSwapLogRatio(const Eigen::MatrixXd& Dx, const Eigen::MatrixXd& Dxy,
                         const Eigen::MatrixXd& Dy) {
  const int t = static_cast<int>(Dx.rows());
  const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(t, t) + Dx;
  const Eigen::MatrixXd T = Eigen::MatrixXd::Identity(t, t) - Dy +
                            Dxy.transpose() * S.inverse() * Dxy;
  return LogDetSpd(S) + LogDetSpd(T);
}

// A random instance: a design M = sum of design blocks (y among them), a
// candidate x; D blocks under V = M^-1.
struct Instance {
  Eigen::MatrixXd Dx, Dxy, Dy;
};

Instance MakeInstance(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y,
                      const Eigen::MatrixXd& others) {
  const Eigen::MatrixXd M = others.transpose() * others + Y.transpose() * Y;
  const Eigen::MatrixXd V = M.inverse();
  return {X * V * X.transpose(), X * V * Y.transpose(), Y * V * Y.transpose()};
}

TEST(FedorovScaleTest, SwapBoundIsAnUpperBoundOnRandomInstances) {
  std::mt19937_64 rng(17);
  int strictly_tighter = 0, finite = 0;
  for (int t : {1, 2, 3, 4, 6}) {
    for (int trial = 0; trial < 400; ++trial) {
      const int p = t + 2 + trial % 7;
      const int n = p / t + 1 + trial % 4;  // design poses besides y
      const Eigen::MatrixXd others = RandomMatrix(n * t, p, &rng);
      const Eigen::MatrixXd Y = RandomMatrix(t, p, &rng);
      Eigen::MatrixXd X = RandomMatrix(t, p, &rng);
      switch (trial % 4) {
        case 1:  // x near y: the bound's tight regime
          X = 1.3 * Y + 1e-3 * X;
          break;
        case 2:  // a strong candidate
          X *= 10.0;
          break;
        case 3:  // x a duplicate of y
          X = Y;
          break;
      }
      const Instance in = MakeInstance(X, Y, others);
      const double exact = ExactSwapLogRatio(in.Dx, in.Dxy, in.Dy);
      const double bound = internal::SwapLogRatioBound(in.Dx, in.Dy);
      if (!std::isfinite(exact)) continue;
      ++finite;
      ASSERT_GE(bound, exact - 1e-10 * (1.0 + std::abs(exact)))
          << "t " << t << " trial " << trial;
      const double trace_bound = in.Dx.trace() - in.Dy.trace();
      if (bound < trace_bound - 1e-6) ++strictly_tighter;
    }
  }
  EXPECT_GT(finite, 1500);
  // Not the trace bound in disguise.
  EXPECT_GT(strictly_tighter, finite / 2);
}

TEST(FedorovScaleTest, SwapBoundIsAttainedForCollinearSingleRows) {
  // t = 1, x = a y: D_xy^2 = D_x D_y, so T = 1 - D_y + D_y D_x / (1 + D_x)
  // = 1 - D_y / (1 + D_x) and the bound is exact. A bound without the
  // 1 + lambda_max(D_x) (i.e. log(1 + D_x) + log(1 - D_y)) would be below.
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const int p = 4;
    const Eigen::MatrixXd others = RandomMatrix(6, p, &rng);
    const Eigen::MatrixXd Y = RandomMatrix(1, p, &rng);
    const Eigen::MatrixXd X = (0.5 + 0.1 * trial) * Y;
    const Instance in = MakeInstance(X, Y, others);
    const double exact = ExactSwapLogRatio(in.Dx, in.Dxy, in.Dy);
    ASSERT_TRUE(std::isfinite(exact));
    EXPECT_NEAR(internal::SwapLogRatioBound(in.Dx, in.Dy), exact,
                1e-10 * (1.0 + std::abs(exact)));
  }
}

TEST(FedorovScaleTest, SwapBoundIsMinusInfinityWhenTheSwapIsSingular) {
  // mu(D_y) >= 1 + lambda_max(D_x): removing y cannot be made up for.
  Eigen::MatrixXd Dx = Eigen::MatrixXd::Zero(3, 3);
  Dx(0, 0) = 0.1;
  Eigen::MatrixXd Dy = 0.5 * Eigen::MatrixXd::Identity(3, 3);
  EXPECT_TRUE(std::isfinite(internal::SwapLogRatioBound(Dx, Dy)));
  Dy(2, 2) = 1.2;
  EXPECT_EQ(internal::SwapLogRatioBound(Dx, Dy),
            -std::numeric_limits<double>::infinity());
}

// A random pool of m poses with t-row blocks and p parameters.
CandidatePool RandomPool(int64_t m, int t, int p, uint64_t seed) {
  std::mt19937_64 rng(seed);
  RowMatrixXd stacked = RandomMatrix(static_cast<int>(m * t), p, &rng);
  // Uneven pose strengths, so that the bounds prune some pairs.
  std::uniform_real_distribution<double> u(0.2, 2.0);
  for (int64_t i = 0; i < m; ++i) stacked.middleRows(i * t, t) *= u(rng);
  CandidatePool pool;
  std::string error;
  EXPECT_TRUE(CandidatePool::Create(std::move(stacked), t, &pool, &error))
      << error;
  return pool;
}

// Without KL exchange and excursions, every step of Fedorov's history must
// be the best swap (by log det from scratch) of the design before it, for
// any block size (the t = 3 fast path and the dynamic one). Replays the
// history backwards from the final design.
TEST(FedorovScaleTest, EveryStepIsTheBestSwapForAnyBlockSize) {
  for (int t : {1, 2, 3, 4, 6}) {
    SCOPED_TRACE("t = " + std::to_string(t));
    const int p = 10;
    const CandidatePool pool = RandomPool(160, t, p, 100 + t);
    FedorovOptions fo;
    fo.num_poses = 12 / t + 4;
    fo.restarts = 2;
    fo.kl_exchange = false;
    fo.max_excursion = 0;
    fo.refresh_interval = 3;
    fo.num_threads = 2;
    SelectionSummary s;
    ASSERT_TRUE(FedorovExchange(pool, {}, fo, nullptr, &s)) << s.message;
    ASSERT_GT(s.history.size(), 3u);
    std::vector<int64_t> design = s.design;
    for (size_t h = s.history.size() - 1; h >= 1; --h) {
      const SelectionStep& step = s.history[h];
      ASSERT_EQ(step.kind, SelectionStep::kExchange);
      // The design before the step.
      auto it = std::find(design.begin(), design.end(), step.added);
      ASSERT_NE(it, design.end());
      *it = step.removed;
      const double before = LogDetFromScratch(pool, design);
      double best = -std::numeric_limits<double>::infinity();
      for (size_t k = 0; k < design.size(); ++k) {
        for (int64_t x = 0; x < pool.size(); ++x) {
          if (std::count(design.begin(), design.end(), x)) continue;
          std::vector<int64_t> d = design;
          d[k] = x;
          best = std::max(best, LogDetFromScratch(pool, d));
        }
      }
      std::vector<int64_t> after = design;
      *std::find(after.begin(), after.end(), step.removed) = step.added;
      const double taken = LogDetFromScratch(pool, after);
      EXPECT_GT(taken, before);
      EXPECT_NEAR(taken, best, 1e-9 * (1.0 + std::abs(best)))
          << "step " << h << ": swap " << step.removed << " -> " << step.added;
    }
    // And the end is a swap local optimum.
    for (size_t k = 0; k < s.design.size(); ++k) {
      for (int64_t x = 0; x < pool.size(); ++x) {
        if (std::count(s.design.begin(), s.design.end(), x)) continue;
        std::vector<int64_t> d = s.design;
        d[k] = x;
        ASSERT_LE(LogDetFromScratch(pool, d),
                  s.log_det + 1e-9 * std::max(1.0, std::abs(s.log_det)));
      }
    }
  }
}

// The PUMA pool of 4^6 = 4096 poses, in double and in float, and its
// approximate design (solved on the double pool: the same poses).
class FedorovFloatTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    pool_ = new CandidatePool(testing::PumaPool(4));
    float_pool_ = new CandidatePool;
    std::string error;
    ASSERT_TRUE(CandidatePool::Create(
        RowMatrixXf(pool_->stacked().cast<float>()), 3, float_pool_, &error))
        << error;
    approximate_ = new ApproximateDesignSummary;
    ApproximateDesignOptions ao;
    ao.tolerance = 1e-2;  // a rough design is enough to start from
    ASSERT_TRUE(SolveApproximateDesign(*pool_, {}, ao, approximate_))
        << approximate_->message;
  }
  static void TearDownTestSuite() {
    delete pool_;
    delete float_pool_;
    delete approximate_;
  }
  static FedorovOptions Options() {
    FedorovOptions fo;
    fo.num_poses = 30;
    fo.restarts = 4;
    fo.reduced_pool_per_pose = 0;
    return fo;
  }
  static CandidatePool* pool_;
  static CandidatePool* float_pool_;
  static ApproximateDesignSummary* approximate_;
};
CandidatePool* FedorovFloatTest::pool_ = nullptr;
CandidatePool* FedorovFloatTest::float_pool_ = nullptr;
ApproximateDesignSummary* FedorovFloatTest::approximate_ = nullptr;

void ExpectValidDesign(const SelectionSummary& s, int n, int64_t pool_size) {
  ASSERT_EQ(static_cast<int>(s.design.size()), n);
  std::vector<int64_t> d = s.design;
  std::sort(d.begin(), d.end());
  EXPECT_TRUE(std::adjacent_find(d.begin(), d.end()) == d.end());
  EXPECT_GE(d.front(), 0);
  EXPECT_LT(d.back(), pool_size);
}

TEST_F(FedorovFloatTest, FloatPoolNeedsAnApproximateDesign) {
  SelectionSummary s;
  EXPECT_FALSE(FedorovExchange(*float_pool_, {}, Options(), nullptr, &s));
  EXPECT_EQ(s.termination_type, TerminationType::kFailure);
  EXPECT_NE(s.message.find("single-precision pool needs an approximate"),
            std::string::npos)
      << s.message;
  // The double pool needs none.
  EXPECT_TRUE(FedorovExchange(*pool_, {}, Options(), nullptr, &s)) << s.message;
}

TEST_F(FedorovFloatTest, FloatPoolGivesNearlyTheDoubleLogDet) {
  FedorovOptions fo = Options();
  fo.reduced_pool_size = 800;
  fo.polish_pool_size = 2000;
  SelectionSummary d, f;
  ASSERT_TRUE(FedorovExchange(*pool_, {}, fo, approximate_, &d)) << d.message;
  ASSERT_TRUE(FedorovExchange(*float_pool_, {}, fo, approximate_, &f))
      << f.message;
  ExpectValidDesign(f, 30, pool_->size());
  // Without an exact source the log det is the widened float blocks'.
  RowMatrixXd buffer;
  double widened = 0;
  {
    Eigen::MatrixXd M =
        Eigen::MatrixXd::Zero(pool_->num_parameters(), pool_->num_parameters());
    for (int64_t i : f.design) {
      const RowMatrixXd X = float_pool_->CopyBlock(i);
      M += X.transpose() * X;
    }
    widened = LogDetSpd(M);
  }
  EXPECT_NEAR(f.log_det, widened, 1e-12 * std::abs(widened));
  // In double, the float run's design is within 1e-5 (natural log det) of
  // the double run's (measured on this pool: the same design, difference 0).
  const double f_in_double = LogDetFromScratch(*pool_, f.design);
  EXPECT_NEAR(f_in_double, d.log_det, 1e-5)
      << "float design " << f_in_double << " double design " << d.log_det;
}

TEST_F(FedorovFloatTest, FloatPoolLogDetComesFromTheExactSource) {
  CandidatePool with_exact = *float_pool_;
  const CandidatePool* exact = pool_;
  with_exact.set_exact_source(
      [exact](int64_t begin, int64_t count, RowMatrixXd* rows) {
        exact->CopyRows(begin, count, rows);
      });
  FedorovOptions fo = Options();
  fo.reduced_pool_size = 800;
  fo.polish_pool_size = 2000;
  SelectionSummary f;
  ASSERT_TRUE(FedorovExchange(with_exact, {}, fo, approximate_, &f))
      << f.message;
  // The double blocks' log det, not the widened float ones' (which differ
  // by ~1e-7 relative).
  const double in_double = LogDetFromScratch(*pool_, f.design);
  EXPECT_NEAR(f.log_det, in_double, 1e-12 * std::abs(in_double));
}

// The reduced pool and the polish thresholds, crossed: a double pool takes
// the whole pool at pool.size() <= threshold, a float pool never does.
TEST_F(FedorovFloatTest, FloatPoolAlwaysRunsOnSubPools) {
  const int64_t m = pool_->size();
  struct Case {
    int64_t reduced, polish;
    bool double_reduced;       // the double pool takes the reduced path
    bool double_rounds;        // ... and polishes in rounds
    std::string float_rounds;  // the float pool's rounds text
  };
  const std::vector<Case> cases = {
      {m - 1, m, true, false, "rounds over the " + std::to_string(m)},
      {m - 1, m - 1, true, true, "rounds over the " + std::to_string(m - 1)},
      {m, m, false, false, "rounds over the " + std::to_string(m)},
      {0, 0, false, false, "rounds over the " + std::to_string(m)},
      {600, 0, true, false, "rounds over the " + std::to_string(m)},
      {600, 1500, true, true, "rounds over the 1500"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE("reduced " + std::to_string(c.reduced) + " polish " +
                 std::to_string(c.polish));
    FedorovOptions fo = Options();
    fo.restarts = 2;
    fo.reduced_pool_size = c.reduced;
    fo.polish_pool_size = c.polish;
    SelectionSummary d, f;
    ASSERT_TRUE(FedorovExchange(*pool_, {}, fo, approximate_, &d)) << d.message;
    ASSERT_TRUE(FedorovExchange(*float_pool_, {}, fo, approximate_, &f))
        << f.message;
    EXPECT_EQ(d.message.find("reduced pool") != std::string::npos,
              c.double_reduced)
        << d.message;
    if (c.double_reduced) {
      EXPECT_EQ(d.message.find("in rounds") != std::string::npos,
                c.double_rounds)
          << d.message;
    }
    EXPECT_NE(f.message.find("restarts on a reduced pool"), std::string::npos)
        << f.message;
    EXPECT_NE(f.message.find(c.float_rounds), std::string::npos) << f.message;
    ExpectValidDesign(f, 30, m);
    EXPECT_NEAR(LogDetFromScratch(*pool_, f.design), d.log_det, 1e-3);
  }
}

// Identical designs and log dets for 1, 2 and 4 threads, through the
// reduced pool and the polish in rounds, in double and in float.
TEST_F(FedorovFloatTest, SameResultForAnyThreadCount) {
  for (const CandidatePool* pool : {pool_, float_pool_}) {
    SCOPED_TRACE(pool->single_precision() ? "float" : "double");
    FedorovOptions fo = Options();
    fo.reduced_pool_size = 500;
    fo.polish_pool_size = 1200;
    SelectionSummary first;
    for (int threads : {1, 2, 4}) {
      fo.num_threads = threads;
      SelectionSummary s;
      ASSERT_TRUE(FedorovExchange(*pool, {}, fo, approximate_, &s))
          << s.message;
      ASSERT_NE(s.message.find("in rounds"), std::string::npos) << s.message;
      if (threads == 1) {
        first = s;
        continue;
      }
      EXPECT_EQ(s.design, first.design) << threads << " threads";
      EXPECT_EQ(s.log_det, first.log_det) << threads << " threads";
      ASSERT_EQ(s.history.size(), first.history.size());
      for (size_t h = 0; h < s.history.size(); ++h) {
        EXPECT_EQ(s.history[h].added, first.history[h].added);
        EXPECT_EQ(s.history[h].removed, first.history[h].removed);
        EXPECT_EQ(s.history[h].log_det, first.history[h].log_det);
      }
    }
  }
}

}  // namespace
}  // namespace activecal
