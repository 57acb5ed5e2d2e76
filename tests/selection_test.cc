// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/design.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/information_matrix.h"
#include "activecal/selection/random_designs.h"
#include "test_util.h"

namespace activecal {
namespace {

class SelectionTest : public testing::PumaPoolSuite {};

TEST_F(SelectionTest, IncrementalLogDetMatchesScratchOver10000Updates) {
  const CandidatePool& pool = *puma_;
  Design design(pool);
  Random random(5);
  // Start from 20 poses, then random adds and removes around 15-40 poses.
  for (int64_t i : random.SampleWithoutReplacement(pool.size(), 20)) {
    design.Add(i);
  }
  double worst = 0;
  int removals_refused = 0;
  for (int step = 0; step < 10000; ++step) {
    const bool add =
        design.size() < 15 || (design.size() < 40 && random.Uniform() < 0.5);
    if (add) {
      testing::AddRandomNewPose(&design, &random);
    } else {
      const int64_t i = design.poses()[random.UniformInt(design.size())];
      if (!design.Remove(i)) {
        // A refusal must be right: without i the design is singular.
        ++removals_refused;
        std::vector<int64_t> rest = design.poses();
        rest.erase(std::find(rest.begin(), rest.end(), i));
        EXPECT_EQ(LogDetFromScratch(pool, rest),
                  -std::numeric_limits<double>::infinity());
      }
    }
    const double scratch = LogDetFromScratch(pool, design.poses());
    ASSERT_TRUE(std::isfinite(scratch));
    worst = std::max(worst,
                     std::abs(design.log_det() - scratch) / std::abs(scratch));
  }
  EXPECT_LT(worst, 1e-9);
  // The 3-level pool has poses that alone see some direction: some
  // removals must be refused (so the refusal path ran and was checked
  // above), but only a few.
  EXPECT_GT(removals_refused, 0);
  EXPECT_LT(removals_refused, 100);
}

TEST_F(SelectionTest, InverseStaysCurrent) {
  const CandidatePool& pool = *puma_;
  Design design(pool);
  for (int64_t i = 0; i < 60; ++i) design.Add(i * 7);
  for (int64_t i = 0; i < 20; ++i) ASSERT_TRUE(design.Remove(i * 7));
  const Eigen::MatrixXd& M = design.information().matrix();
  const Eigen::MatrixXd I = M * design.information().inverse();
  EXPECT_LT((I - Eigen::MatrixXd::Identity(27, 27)).norm(), 1e-8);
}

TEST_F(SelectionTest, GainsAndLossesEqualBruteForce) {
  const CandidatePool& pool = *puma_;
  Design design(pool);
  for (int64_t i : Random(8).SampleWithoutReplacement(pool.size(), 30)) {
    design.Add(i);
  }
  const Eigen::MatrixXd M = design.information().matrix();
  const double base = testing::CholeskyLogDet(M);
  Eigen::VectorXd gains;
  ComputeAddGains(pool, design.information(), 2, &gains);
  for (int64_t i = 0; i < pool.size(); i += 13) {
    const auto X = pool.block(i);
    const double brute = testing::CholeskyLogDet(M + X.transpose() * X) - base;
    EXPECT_NEAR(gains[i], brute, 1e-9 * std::max(1.0, std::abs(brute)));
    EXPECT_NEAR(design.information().AddGain(X), brute,
                1e-9 * std::max(1.0, std::abs(brute)));
  }
  for (int64_t i : design.poses()) {
    const auto Y = pool.block(i);
    const double brute = testing::CholeskyLogDet(M - Y.transpose() * Y) - base;
    EXPECT_NEAR(design.information().RemoveLoss(Y), brute,
                1e-9 * std::max(1.0, std::abs(brute)));
  }
  // Thread count does not change the gains.
  Eigen::VectorXd gains1;
  ComputeAddGains(pool, design.information(), 1, &gains1);
  EXPECT_TRUE(gains == gains1);
}

TEST_F(SelectionTest, RemovalThatWouldMakeSingularIsRefused) {
  const CandidatePool& pool = *puma_;
  InformationMatrix info(pool.num_parameters());
  // Exactly nine poses (27 rows): removing any makes M singular.
  std::vector<int64_t> poses;
  Random random(3);
  do {
    poses = random.SampleWithoutReplacement(pool.size(), 9);
  } while (!std::isfinite(LogDetFromScratch(pool, poses)));
  for (int64_t i : poses) info.Add(pool.block(i));
  ASSERT_TRUE(info.positive_definite());
  const Eigen::MatrixXd before = info.matrix();
  EXPECT_FALSE(info.Remove(pool.block(poses[4])));
  EXPECT_TRUE(info.matrix() == before);
  EXPECT_TRUE(info.positive_definite());
  EXPECT_EQ(info.RemoveLoss(pool.block(poses[4])),
            -std::numeric_limits<double>::infinity());
}

TEST_F(SelectionTest, ProgrammerErrorsOnADesignAreChecked) {
  Design design(*puma_);
  design.Add(3);
  EXPECT_DEATH(design.Remove(4), "pose 4 is not in the design");
  EXPECT_DEATH(design.Add(3), "already in the design");
  EXPECT_DEATH(design.Add(puma_->size()), "is not in the pool");
}

TEST_F(SelectionTest, ObservabilityIndicesAgreeWithLogDet) {
  const CandidatePool& pool = *puma_;
  const std::vector<int64_t> design =
      Random(4).SampleWithoutReplacement(pool.size(), 30);
  const ObservabilityIndices o =
      ComputeObservabilityIndices(pool.Stack(design));
  EXPECT_EQ(o.rank, 27);
  const double log_det = LogDetFromScratch(pool, design);
  EXPECT_NEAR(o.log10_oid, log_det / std::log(10.0), 1e-9);
  EXPECT_NEAR(o.oi, OiFromLogDet(log_det, 27), 1e-12);
  EXPECT_NEAR(LogDetFromOi(o.oi, 27), log_det, 1e-9);
  EXPECT_NEAR(o.o2, o.singular_values[26] / o.singular_values[0], 1e-15);
  // The paper's check: OI = 0.096284 gives OID = 2.54e22.
  EXPECT_NEAR(LogDetFromOi(0.096284, 27) / std::log(10.0), 22.405, 0.001);
}

ExchangeAddExchangeOptions SmallEae() {
  ExchangeAddExchangeOptions o;
  o.num_poses = 20;
  o.initial_poses = 12;
  o.seed = 3;
  return o;
}

TEST_F(SelectionTest, ExchangeAddExchangeNeverLowersLogDetAndKeepsFixed) {
  DesignConstraints constraints;
  constraints.fixed = {5, 100, 600};
  ExchangeAddExchangeOptions options = SmallEae();
  options.restarts = 3;
  SelectionSummary summary;
  ASSERT_TRUE(ExchangeAddExchange(*puma_, constraints, options, &summary))
      << summary.message;
  EXPECT_EQ(summary.design.size(), 20u);
  for (int64_t f : constraints.fixed) {
    EXPECT_NE(std::find(summary.design.begin(), summary.design.end(), f),
              summary.design.end());
  }
  for (size_t k = 1; k < summary.history.size(); ++k) {
    EXPECT_GT(summary.history[k].log_det, summary.history[k - 1].log_det)
        << summary.history[k].name();
  }
  EXPECT_NEAR(summary.log_det, LogDetFromScratch(*puma_, summary.design),
              1e-12);
  // No removed pose is fixed.
  for (const SelectionStep& s : summary.history) {
    EXPECT_EQ(std::count(constraints.fixed.begin(), constraints.fixed.end(),
                         s.removed),
              0);
  }
}

TEST_F(SelectionTest, ExcludedPosesNeverAppear) {
  DesignConstraints constraints;
  // Exclude every pose whose first level is 0 or whose index is even.
  constraints.excluded = [](int64_t i) { return i % 2 == 0 || i < 243; };
  SelectionSummary summary;
  ASSERT_TRUE(ExchangeAddExchange(*puma_, constraints, SmallEae(), &summary));
  for (int64_t i : summary.design) EXPECT_FALSE(constraints.excluded(i)) << i;
  for (const SelectionStep& s : summary.history) {
    if (s.added >= 0) {
      EXPECT_FALSE(constraints.excluded(s.added));
    }
  }
  RandomDesignOptions random_options;
  random_options.num_poses = 20;
  random_options.num_designs = 50;
  ASSERT_TRUE(
      SelectRandomDesigns(*puma_, constraints, random_options, &summary));
  for (int64_t i : summary.design) EXPECT_FALSE(constraints.excluded(i)) << i;
}

TEST_F(SelectionTest, AlgorithmsReproducibleForSeedAndThreadCount) {
  ExchangeAddExchangeOptions options = SmallEae();
  options.restarts = 2;
  SelectionSummary a, b, c;
  options.num_threads = 1;
  ASSERT_TRUE(ExchangeAddExchange(*puma_, {}, options, &a));
  options.num_threads = 3;
  ASSERT_TRUE(ExchangeAddExchange(*puma_, {}, options, &b));
  EXPECT_EQ(a.design, b.design);
  EXPECT_EQ(a.log_det, b.log_det);
  options.seed = 4;
  ASSERT_TRUE(ExchangeAddExchange(*puma_, {}, options, &c));
  EXPECT_NE(a.design, c.design);

  RandomDesignOptions ro;
  ro.num_poses = 20;
  ro.num_designs = 200;
  std::vector<double> v1, v2;
  ro.num_threads = 1;
  ASSERT_TRUE(SelectRandomDesigns(*puma_, {}, ro, &a, &v1));
  ro.num_threads = 4;
  ASSERT_TRUE(SelectRandomDesigns(*puma_, {}, ro, &b, &v2));
  EXPECT_EQ(a.design, b.design);
  EXPECT_EQ(v1, v2);
  EXPECT_EQ(a.log_det, *std::max_element(v1.begin(), v1.end()));
}

TEST_F(SelectionTest, SingularInitialDesignIsCompletedGreedily) {
  ExchangeAddExchangeOptions options = SmallEae();
  options.initial_poses = 4;  // 12 rows < 27 parameters
  SelectionSummary summary;
  ASSERT_TRUE(ExchangeAddExchange(*puma_, {}, options, &summary))
      << summary.message;
  EXPECT_NE(summary.message.find("singular start was completed greedily"),
            std::string::npos)
      << summary.message;
  EXPECT_TRUE(std::isfinite(summary.history.front().log_det));
  EXPECT_EQ(summary.design.size(), 20u);
}

TEST_F(SelectionTest, DeterminantAndEigenvalueCriteriaPickTheSamePoses) {
  ExchangeAddExchangeOptions options = SmallEae();
  options.num_poses = 16;
  SelectionSummary det, eig;
  ASSERT_TRUE(ExchangeAddExchange(*puma_, {}, options, &det));
  options.criterion = SelectionCriterion::kEigenvalueOi;
  ASSERT_TRUE(ExchangeAddExchange(*puma_, {}, options, &eig));
  EXPECT_EQ(det.design, eig.design);
  ASSERT_EQ(det.history.size(), eig.history.size());
  for (size_t k = 0; k < det.history.size(); ++k) {
    EXPECT_NEAR(det.history[k].log_det, eig.history[k].log_det,
                1e-8 * std::abs(det.history[k].log_det));
  }
}

// The swap loops call ParallelFor once per swap on a reused thread pool:
// every index exactly once with the static partition, also when calls
// nest or come from several threads at once.
TEST(ParallelForTest, PoolCoversEveryIndexOnceNestedAndConcurrent) {
  auto check = [](int threads) {
    std::vector<int> hits(1000, 0);
    std::vector<int> owner(1000, -1);
    ParallelFor(1000, threads, [&](int64_t b, int64_t e, int t) {
      for (int64_t i = b; i < e; ++i) {
        ++hits[i];
        owner[i] = t;
        // Nested: inline or threads of its own, never a deadlock.
        if (i == b) ParallelFor(4, 2, [](int64_t, int64_t, int) {});
      }
    });
    const int64_t chunk = (1000 + threads - 1) / threads;
    for (int i = 0; i < 1000; ++i) {
      EXPECT_EQ(hits[i], 1) << i;
      EXPECT_EQ(owner[i], i / chunk) << i;
    }
  };
  for (int threads : {1, 2, 3, 8}) check(threads);
  std::thread other([&] { check(3); });
  check(2);
  other.join();
}

// An exception in any part reaches the caller after every part has
// finished (no thread left on a dead stack; ASan checks that), and the pool
// works afterwards.
TEST(ParallelForTest, ExceptionsReachTheCallerAfterEveryPartEnds) {
  for (int thrower : {0, 1}) {
    std::vector<int> done(4, 0);
    EXPECT_THROW(ParallelFor(4, 4,
                             [&](int64_t b, int64_t, int t) {
                               if (t == thrower) throw std::runtime_error("x");
                               std::this_thread::sleep_for(
                                   std::chrono::milliseconds(20));
                               done[b] = 1;
                             }),
                 std::runtime_error);
    EXPECT_EQ(std::count(done.begin(), done.end(), 1), 3);
  }
  std::vector<int> hits(100, 0);
  ParallelFor(100, 4, [&](int64_t b, int64_t e, int) {
    for (int64_t i = b; i < e; ++i) ++hits[i];
  });
  EXPECT_EQ(std::count(hits.begin(), hits.end(), 1), 100);
}

TEST_F(SelectionTest, BadRequestsGiveMessages) {
  SelectionSummary summary;
  ExchangeAddExchangeOptions options = SmallEae();
  options.num_poses = 8;  // 24 rows < 27
  options.initial_poses = 8;
  EXPECT_FALSE(ExchangeAddExchange(*puma_, {}, options, &summary));
  EXPECT_NE(summary.message.find("fewer than the 27 parameters"),
            std::string::npos)
      << summary.message;
  options = SmallEae();
  options.num_poses = 1000;
  EXPECT_FALSE(ExchangeAddExchange(*puma_, {}, options, &summary));
  EXPECT_NE(summary.message.find("only 729 usable poses"), std::string::npos)
      << summary.message;
  DesignConstraints constraints;
  constraints.fixed = {3, 3};
  EXPECT_FALSE(ExchangeAddExchange(*puma_, constraints, SmallEae(), &summary));
  EXPECT_NE(summary.message.find("listed twice"), std::string::npos);
  constraints.fixed = {9999};
  EXPECT_FALSE(ExchangeAddExchange(*puma_, constraints, SmallEae(), &summary));
  EXPECT_NE(summary.message.find("outside the pool"), std::string::npos);
  CandidatePool bad;
  std::string error;
  RowMatrixXd stacked = RowMatrixXd::Ones(7, 4);
  EXPECT_FALSE(CandidatePool::Create(stacked, 3, &bad, &error));
  EXPECT_NE(error.find("not a multiple"), std::string::npos);
  stacked = RowMatrixXd::Ones(6, 4);
  stacked(4, 2) = std::nan("");
  EXPECT_FALSE(CandidatePool::Create(stacked, 3, &bad, &error));
  EXPECT_NE(error.find("pose 1"), std::string::npos) << error;
}

}  // namespace
}  // namespace activecal
