// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Fedorov, DETMAX, greedy, the approximate design and its certificate.

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "activecal/core/lattice.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/detmax.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/greedy.h"
#include "test_util.h"

namespace activecal {
namespace {

double ExhaustiveBestLogDet(const CandidatePool& pool) {
  double best = -std::numeric_limits<double>::infinity();
  const int64_t n = pool.size();
  for (int64_t a = 0; a < n; ++a) {
    for (int64_t b = a + 1; b < n; ++b) {
      for (int64_t c = b + 1; c < n; ++c) {
        best = std::max(best, LogDetFromScratch(pool, {a, b, c}));
      }
    }
  }
  return best;
}

class DesignAlgorithmsTest : public testing::PumaPoolSuite {};

void ExpectNeverBelowStart(const SelectionSummary& s) {
  ASSERT_FALSE(s.history.empty());
  for (size_t k = 1; k < s.history.size(); ++k) {
    EXPECT_GT(s.history[k].log_det, s.history[k - 1].log_det - 1e-9)
        << s.algorithm << " step " << k << " " << s.history[k].name();
  }
  EXPECT_GE(s.log_det, s.history.front().log_det - 1e-9) << s.algorithm;
}

TEST_F(DesignAlgorithmsTest, FedorovDetmaxGreedyNeverEndBelowTheirStart) {
  FedorovOptions fo;
  fo.num_poses = 20;
  fo.restarts = 3;
  SelectionSummary s;
  ASSERT_TRUE(FedorovExchange(*puma_, {}, fo, nullptr, &s)) << s.message;
  ExpectNeverBelowStart(s);
  EXPECT_EQ(s.design.size(), 20u);
  DetmaxOptions dopt;
  dopt.num_poses = 20;
  dopt.restarts = 2;
  ASSERT_TRUE(Detmax(*puma_, {}, dopt, &s)) << s.message;
  ExpectNeverBelowStart(s);
  GreedyOptions g;
  g.num_poses = 20;
  ASSERT_TRUE(GreedyDesign(*puma_, {}, g, &s)) << s.message;
  EXPECT_EQ(s.design.size(), 20u);
  EXPECT_TRUE(std::isfinite(s.log_det));
}

TEST_F(DesignAlgorithmsTest, FedorovEndsAtASwapLocalOptimum) {
  FedorovOptions fo;
  fo.num_poses = 14;
  fo.restarts = 1;
  SelectionSummary s;
  ASSERT_TRUE(FedorovExchange(*puma_, {}, fo, nullptr, &s));
  // Brute force: no single swap raises log det.
  for (size_t k = 0; k < s.design.size(); ++k) {
    for (int64_t x = 0; x < puma_->size(); ++x) {
      if (std::count(s.design.begin(), s.design.end(), x)) continue;
      std::vector<int64_t> d = s.design;
      d[k] = x;
      ASSERT_LE(LogDetFromScratch(*puma_, d), s.log_det + 1e-8)
          << "swap " << s.design[k] << " -> " << x;
    }
  }
}

TEST_F(DesignAlgorithmsTest, FedorovRespectsConstraintsAndThreads) {
  DesignConstraints c;
  c.fixed = {1, 2};
  c.excluded = [](int64_t i) { return i % 7 == 0; };
  FedorovOptions fo;
  fo.num_poses = 16;
  fo.restarts = 4;
  SelectionSummary a, b;
  fo.num_threads = 1;
  ASSERT_TRUE(FedorovExchange(*puma_, c, fo, nullptr, &a)) << a.message;
  fo.num_threads = 3;
  ASSERT_TRUE(FedorovExchange(*puma_, c, fo, nullptr, &b)) << b.message;
  EXPECT_EQ(a.design, b.design);
  EXPECT_EQ(a.log_det, b.log_det) << a.message << " | " << b.message;
  for (int64_t f : c.fixed)
    EXPECT_EQ(std::count(a.design.begin(), a.design.end(), f), 1);
  for (int64_t i : a.design) {
    if (i != 1 && i != 2) {
      EXPECT_NE(i % 7, 0) << i;
    }
  }
}

// Issue #15 (3): fixed poses that are also in the approximate design's
// support, on a pool above the reduced size (and above the polish size).
TEST_F(DesignAlgorithmsTest, FedorovKeepsFixedPosesOfTheApproximateSupport) {
  ApproximateDesignSummary approx;
  ASSERT_TRUE(
      SolveApproximateDesign(*puma_, {}, ApproximateDesignOptions(), &approx))
      << approx.message;
  ASSERT_GE(approx.support.size(), 2u);
  DesignConstraints c;
  c.fixed = {approx.support[0], approx.support[1]};
  for (int64_t polish : {int64_t{200}, int64_t{100000}}) {
    FedorovOptions fo;
    fo.num_poses = 12;
    fo.restarts = 3;
    fo.reduced_pool_size = 100;
    fo.reduced_pool_per_pose = 0;
    fo.polish_pool_size = polish;
    ASSERT_LT(fo.reduced_pool_size, puma_->size());
    SelectionSummary s;
    ASSERT_TRUE(FedorovExchange(*puma_, c, fo, &approx, &s)) << s.message;
    EXPECT_NE(s.message.find("reduced pool of"), std::string::npos)
        << s.message;
    ASSERT_EQ(s.design.size(), 12u);
    for (int64_t f : c.fixed) {
      EXPECT_EQ(std::count(s.design.begin(), s.design.end(), f), 1) << f;
    }
    EXPECT_NEAR(s.log_det, LogDetFromScratch(*puma_, s.design), 1e-9);
  }
}

// A pool of random blocks in which one parameter is nearly a combination
// of the others (a DH base yaw seen from the robot's origin).
CandidatePool NearlyUnidentifiablePool(int64_t size, int p, uint64_t seed,
                                       double eps = 1e-4) {
  Random random(seed);
  RowMatrixXd rows(size * 3, p);
  for (int64_t r = 0; r < rows.rows(); ++r) {
    for (int c = 0; c < p - 1; ++c) rows(r, c) = 2 * random.Uniform() - 1;
    rows(r, p - 1) =
        rows(r, 0) - 0.5 * rows(r, 1) + eps * (2 * random.Uniform() - 1);
  }
  CandidatePool pool;
  std::string error;
  EXPECT_TRUE(CandidatePool::Create(std::move(rows), 3, &pool, &error))
      << error;
  return pool;
}

// Issue #15 (2): Fedorov (swaps and excursions) and DETMAX must end on a
// small pool with a nearly unidentifiable parameter, for any restart count.
TEST(ExchangeLoopsTest, EndOnANearlyUnidentifiablePool) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const CandidatePool pool = NearlyUnidentifiablePool(23, 12, seed);
    FedorovOptions fo;
    fo.num_poses = 20;
    fo.restarts = 8;
    SelectionSummary s;
    ASSERT_TRUE(FedorovExchange(pool, {}, fo, nullptr, &s)) << s.message;
    EXPECT_EQ(s.design.size(), 20u);
    EXPECT_TRUE(std::isfinite(s.log_det));
    ExpectNeverBelowStart(s);
    DetmaxOptions d;
    d.num_poses = 20;
    d.restarts = 8;
    ASSERT_TRUE(Detmax(pool, {}, d, &s)) << s.message;
    EXPECT_EQ(s.design.size(), 20u);
    ExpectNeverBelowStart(s);
  }
  // One notch closer to singular, the pool cannot identify every parameter
  // (by InformationMatrix's pivot tolerance): a FAILURE, not an endless loop.
  const CandidatePool singular = NearlyUnidentifiablePool(23, 12, 1, 1e-5);
  FedorovOptions fo;
  fo.num_poses = 20;
  fo.restarts = 8;
  SelectionSummary s;
  EXPECT_FALSE(FedorovExchange(singular, {}, fo, nullptr, &s));
  EXPECT_EQ(s.termination_type, TerminationType::kFailure) << s.message;
}

TEST_F(DesignAlgorithmsTest, IterationBoundsGiveNoConvergenceAndAValidDesign) {
  FedorovOptions fo;
  fo.num_poses = 20;
  fo.restarts = 2;
  fo.max_swaps = 1;
  SelectionSummary s;
  ASSERT_TRUE(FedorovExchange(*puma_, {}, fo, nullptr, &s)) << s.message;
  EXPECT_EQ(s.termination_type, TerminationType::kNoConvergence) << s.message;
  EXPECT_NE(s.message.find("iteration bound"), std::string::npos);
  EXPECT_EQ(s.design.size(), 20u);
  EXPECT_TRUE(std::isfinite(s.log_det));
  DetmaxOptions d;
  d.num_poses = 20;
  d.restarts = 1;
  d.max_iterations = 1;
  ASSERT_TRUE(Detmax(*puma_, {}, d, &s)) << s.message;
  EXPECT_EQ(s.termination_type, TerminationType::kNoConvergence) << s.message;
  EXPECT_EQ(s.design.size(), 20u);
  fo.max_swaps = 100000;
  ASSERT_TRUE(FedorovExchange(*puma_, {}, fo, nullptr, &s)) << s.message;
  EXPECT_EQ(s.termination_type, TerminationType::kConvergence) << s.message;
}

// Issue #15 (4): a singular start with initial_poses == num_poses is
// completed and trimmed back, never returned larger than asked.
TEST(ExchangeAddExchangeTest, SingularStartNeverGivesMorePosesThanAsked) {
  // Six parameters, three rows per pose: poses 0..34 see only the first
  // three parameters, so most random 3-pose starts are singular.
  Random random(5);
  RowMatrixXd rows = RowMatrixXd::Zero(40 * 3, 6);
  for (int64_t r = 0; r < rows.rows(); ++r) {
    const int cols = r < 35 * 3 ? 3 : 6;
    for (int c = 0; c < cols; ++c) rows(r, c) = 2 * random.Uniform() - 1;
  }
  CandidatePool pool;
  std::string error;
  ASSERT_TRUE(CandidatePool::Create(std::move(rows), 3, &pool, &error))
      << error;
  int singular_starts = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    ExchangeAddExchangeOptions o;
    o.num_poses = 3;
    o.initial_poses = 3;
    o.seed = seed;
    SelectionSummary s;
    ASSERT_TRUE(ExchangeAddExchange(pool, {}, o, &s)) << s.message;
    EXPECT_EQ(s.design.size(), 3u) << "seed " << seed << ": " << s.message;
    EXPECT_TRUE(std::isfinite(s.log_det));
    if (s.message.find("singular") != std::string::npos) ++singular_starts;
  }
  EXPECT_GT(singular_starts, 0);
}

TEST_F(DesignAlgorithmsTest, ApproximateDesignSatisfiesEquivalenceTheorem) {
  ApproximateDesignOptions options;
  options.tolerance = 1e-4;
  ApproximateDesignSummary approx;
  ASSERT_TRUE(SolveApproximateDesign(*puma_, {}, options, &approx))
      << approx.message;
  const int p = puma_->num_parameters();
  double sum = 0;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  for (size_t k = 0; k < approx.support.size(); ++k) {
    EXPECT_GT(approx.weights[k], 0);
    sum += approx.weights[k];
    const auto X = puma_->block(approx.support[k]);
    M += approx.weights[k] * X.transpose() * X;
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
  // Recompute the variance function from the weights, independently.
  const Eigen::MatrixXd V = M.inverse();
  double max_d = 0;
  for (int64_t i = 0; i < puma_->size(); ++i) {
    const auto X = puma_->block(i);
    max_d = std::max(max_d, (X * V * X.transpose()).trace());
  }
  EXPECT_LE(max_d, p * (1 + options.tolerance) + 1e-9);
  EXPECT_NEAR(max_d, approx.max_variance, 1e-8);
  // sum_i w_i d_i = tr(M^-1 M) = p, so with max d <= p(1+tol) every
  // support point's d is close to p too (weighted).
  double weighted = 0;
  for (size_t k = 0; k < approx.support.size(); ++k) {
    const auto X = puma_->block(approx.support[k]);
    weighted += approx.weights[k] * (X * V * X.transpose()).trace();
  }
  EXPECT_NEAR(weighted, p, 1e-8);
  EXPECT_NEAR(approx.log_det, std::log(M.determinant()), 1e-8);
}

TEST(CertificateTest, NeverAboveTheTrueEfficiencyFoundByExhaustiveSearch) {
  const CandidatePool pool = testing::PlanarPool();
  const int p = pool.num_parameters();
  ASSERT_EQ(p, 6);
  const double optimum = ExhaustiveBestLogDet(pool);
  ASSERT_TRUE(std::isfinite(optimum));
  ApproximateDesignSummary approx;
  ApproximateDesignOptions options;
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &approx))
      << approx.message;
  // N^p det M* bounds the exhaustive optimum.
  EXPECT_GE(approx.log_det_upper_bound + p * std::log(3.0), optimum - 1e-9);
  // For designs of every quality: Fedorov's, greedy's, and random ones.
  std::vector<std::vector<int64_t>> designs;
  FedorovOptions fo;
  fo.num_poses = 3;
  SelectionSummary s;
  ASSERT_TRUE(FedorovExchange(pool, {}, fo, &approx, &s)) << s.message;
  designs.push_back(s.design);
  GreedyOptions g;
  g.num_poses = 3;
  ASSERT_TRUE(GreedyDesign(pool, {}, g, &s));
  designs.push_back(s.design);
  Random random(2);
  while (designs.size() < 40) {
    std::vector<int64_t> d = random.SampleWithoutReplacement(pool.size(), 3);
    if (std::isfinite(LogDetFromScratch(pool, d))) designs.push_back(d);
  }
  testing::CheckEachDesign(
      designs, approx,
      [&](const ApproximateDesignSummary* a, SelectionSummary* summary) {
        ASSERT_TRUE(CertifyDesign(pool, {}, a, 1, summary));
        const double log_det = LogDetFromScratch(pool, summary->design);
        const double true_efficiency = std::exp((log_det - optimum) / p);
        EXPECT_LE(summary->efficiency_lower_bound, true_efficiency + 1e-12);
        EXPECT_GE(summary->log_det_upper_bound, optimum - 1e-9);
      });
}

}  // namespace
}  // namespace activecal
