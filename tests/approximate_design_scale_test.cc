// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The approximate design on pools larger than its subsample (column
// generation: issue #17), on single-precision pools, and the certificate
// over a pool's exact blocks.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "activecal/core/random.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/design.h"
#include "activecal/selection/information_matrix.h"
#include "test_util.h"

namespace activecal {
namespace {

// M(w) of an approximate design, from the pool's blocks.
Eigen::MatrixXd WeightedInformationOf(const CandidatePool& pool,
                                      const ApproximateDesignSummary& a) {
  const int p = pool.num_parameters();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  for (size_t k = 0; k < a.support.size(); ++k) {
    const RowMatrixXd X = pool.CopyBlock(a.support[k]);
    M += a.weights[k] * X.transpose() * X;
  }
  return M;
}

// max_i d_i(w) over the whole pool, recomputed from the weights.
double MaxVarianceFromScratch(const CandidatePool& pool,
                              const ApproximateDesignSummary& a) {
  const Eigen::MatrixXd M = WeightedInformationOf(pool, a);
  const int p = pool.num_parameters();
  Eigen::VectorXd d;
  ComputeVariances(
      pool,
      Eigen::LLT<Eigen::MatrixXd>(M).solve(Eigen::MatrixXd::Identity(p, p)), 1,
      &d);
  return d.maxCoeff();
}

CandidatePool FloatCopy(const CandidatePool& pool) {
  RowMatrixXf rows = pool.stacked().cast<float>();
  CandidatePool out;
  std::string error;
  EXPECT_TRUE(
      CandidatePool::Create(std::move(rows), pool.block_rows(), &out, &error))
      << error;
  return out;
}

class ApproximateDesignScaleTest : public testing::PumaPoolSuite {};

// A looser tolerance than the default keeps the solves short; the checks
// below do not depend on it.
ApproximateDesignOptions FastOptions() {
  ApproximateDesignOptions options;
  options.tolerance = 1e-3;
  return options;
}

void ExpectSameSolution(const ApproximateDesignSummary& a,
                        const ApproximateDesignSummary& b) {
  EXPECT_EQ(a.support, b.support);
  EXPECT_EQ(a.weights, b.weights);
  EXPECT_EQ(a.log_det, b.log_det);
  EXPECT_EQ(a.max_variance, b.max_variance);
  EXPECT_EQ(a.rounds, b.rounds);
  EXPECT_EQ(a.full_sweeps, b.full_sweeps);
}

TEST_F(ApproximateDesignScaleTest, AtMostSubsampleSizePosesSolvesOnThePool) {
  const CandidatePool& pool = *puma_;
  ApproximateDesignOptions options = FastOptions();
  ApproximateDesignSummary by_default, at_size;
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &by_default))
      << by_default.message;
  // The default subsample (>= 20000) is larger than the pool.
  EXPECT_GT(options.ResolvedSubsampleSize(pool.num_parameters()), pool.size());
  options.subsample_size = pool.size();  // not above: the whole pool
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &at_size));
  ExpectSameSolution(by_default, at_size);
  EXPECT_EQ(at_size.termination_type, TerminationType::kConvergence);
  // Every round ends with a sweep of the pool, after the start's sweep.
  EXPECT_EQ(at_size.full_sweeps, at_size.rounds + 1);
  EXPECT_EQ(at_size.message.find("subsample"), std::string::npos);
}

TEST_F(ApproximateDesignScaleTest, AboveSubsampleSizeCertifiesTheWholePool) {
  const CandidatePool& pool = *puma_;
  const int p = pool.num_parameters();
  ApproximateDesignOptions options = FastOptions();
  ApproximateDesignSummary whole, sub;
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &whole));
  for (int64_t size : {pool.size() - 1, int64_t{200}}) {
    SCOPED_TRACE(size);
    options.subsample_size = size;
    ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &sub)) << sub.message;
    EXPECT_EQ(sub.termination_type, TerminationType::kConvergence)
        << sub.message;
    EXPECT_NE(sub.message.find("subsample of " + std::to_string(size)),
              std::string::npos)
        << sub.message;
    EXPECT_GE(sub.full_sweeps, 1);
    // Weights: positive, sum 1, poses distinct and in the pool.
    double sum = 0;
    for (double w : sub.weights) {
      EXPECT_GT(w, 0);
      sum += w;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    std::vector<int64_t> support = sub.support;
    std::sort(support.begin(), support.end());
    EXPECT_EQ(std::adjacent_find(support.begin(), support.end()),
              support.end());
    // The certificate's quantities over the whole pool, from scratch.
    const double max_d = MaxVarianceFromScratch(pool, sub);
    EXPECT_NEAR(sub.max_variance, max_d, 1e-9 * p);
    EXPECT_LE(max_d, p * (1 + options.tolerance) + 1e-9);
    EXPECT_NEAR(sub.log_det, LogDetSpd(WeightedInformationOf(pool, sub)), 1e-9);
    EXPECT_NEAR(sub.log_det_upper_bound, sub.log_det + p * std::log(max_d / p),
                1e-8);
    // Both solutions are within the tolerance of the optimum, and each
    // bound holds for the other's weights.
    EXPECT_NEAR(sub.log_det, whole.log_det, p * options.tolerance);
    EXPECT_GE(sub.log_det_upper_bound, whole.log_det - 1e-9);
    EXPECT_GE(whole.log_det_upper_bound, sub.log_det - 1e-9);
  }
}

// rows x cols values drawn uniformly from [-scale, scale], row by row.
RowMatrixXd UniformRows(int64_t rows, int cols, double scale, Random* random) {
  RowMatrixXd m(rows, cols);
  for (int64_t r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c)
      m(r, c) = scale * (2 * random->Uniform() - 1);
  }
  return m;
}

// The candidate pool of those rows, t to a pose; a failure with the error.
::testing::AssertionResult PoolOf(RowMatrixXd rows, int t,
                                  CandidatePool* pool) {
  std::string error;
  if (CandidatePool::Create(std::move(rows), t, pool, &error)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << error;
}

// A few strong poses hidden among many weak ones: a subsample of 1 in 20
// very likely misses most of them, and the optimum lies on them.
TEST(ApproximateDesignColumnGenerationTest, FindsStrongPosesOutsideSubsample) {
  const int p = 5, t = 3;
  const int64_t n = 6000;
  Random random(7);
  RowMatrixXd rows = UniformRows(n * t, p, 0.1, &random);
  std::vector<int64_t> strong = random.SampleWithoutReplacement(n, 8);
  for (int64_t i : strong) {
    rows.middleRows(i * t, t) = UniformRows(t, p, 1.0, &random);
  }
  CandidatePool pool;
  ASSERT_TRUE(PoolOf(std::move(rows), t, &pool));
  ApproximateDesignOptions options;
  ApproximateDesignSummary whole, sub;
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &whole));
  ASSERT_EQ(whole.full_sweeps, whole.rounds + 1);  // the whole-pool path
  double strong_weight = 0;
  for (size_t k = 0; k < whole.support.size(); ++k) {
    if (std::count(strong.begin(), strong.end(), whole.support[k])) {
      strong_weight += whole.weights[k];
    }
  }
  ASSERT_GT(strong_weight, 0.9);  // the optimum lies on the strong poses
  options.subsample_size = 300;
  options.max_added_per_sweep = 3;  // a few per sweep: several sweeps
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &sub)) << sub.message;
  EXPECT_EQ(sub.termination_type, TerminationType::kConvergence) << sub.message;
  // The subsample's solution failed the whole-pool check at least once.
  EXPECT_GE(sub.full_sweeps, 2) << sub.message;
  EXPECT_NEAR(sub.log_det, whole.log_det, p * options.tolerance);
  EXPECT_NEAR(sub.max_variance, MaxVarianceFromScratch(pool, sub), 1e-9 * p);
  EXPECT_GE(sub.log_det_upper_bound, whole.log_det - 1e-9);
}

// A subsample that cannot identify every parameter (the last one is seen
// by a few poses only): the solver falls back to the whole pool.
TEST(ApproximateDesignColumnGenerationTest, SingularSubsampleFallsBack) {
  const int p = 4, t = 2;
  const int64_t n = 2000;
  Random random(11);
  RowMatrixXd rows = RowMatrixXd::Zero(n * t, p);
  rows.leftCols(p - 1) = UniformRows(n * t, p - 1, 1.0, &random);
  for (int64_t i : {int64_t{17}, int64_t{900}, int64_t{1999}}) {
    for (int r = 0; r < t; ++r) rows(i * t + r, p - 1) = 1.0;
  }
  CandidatePool pool;
  ASSERT_TRUE(PoolOf(std::move(rows), t, &pool));
  ApproximateDesignOptions options;
  ApproximateDesignSummary whole, sub;
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &whole));
  options.subsample_size = 40;
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, options, &sub)) << sub.message;
  EXPECT_EQ(sub.termination_type, TerminationType::kConvergence);
  // Solved on the whole pool: the same solution as without a subsample.
  EXPECT_EQ(sub.message.find("subsample"), std::string::npos) << sub.message;
  EXPECT_EQ(sub.support, whole.support);
  EXPECT_EQ(sub.log_det, whole.log_det);
}

// The round bound reached on the subsampled path: NO_CONVERGENCE, with the
// bounds still over the whole pool.
TEST_F(ApproximateDesignScaleTest, RoundBoundOnSubsampleKeepsWholePoolBound) {
  ApproximateDesignOptions options = FastOptions();
  options.subsample_size = 100;
  options.max_rounds = 1;
  ApproximateDesignSummary sub;
  ASSERT_TRUE(SolveApproximateDesign(*puma_, {}, options, &sub)) << sub.message;
  EXPECT_EQ(sub.termination_type, TerminationType::kNoConvergence)
      << sub.message;
  EXPECT_EQ(sub.rounds, 1);
  EXPECT_EQ(sub.full_sweeps, 1);
  const int p = puma_->num_parameters();
  EXPECT_NEAR(sub.max_variance, MaxVarianceFromScratch(*puma_, sub), 1e-9 * p);
  ApproximateDesignSummary whole;
  ASSERT_TRUE(SolveApproximateDesign(*puma_, {}, FastOptions(), &whole));
  EXPECT_GE(sub.log_det_upper_bound, whole.log_det - 1e-9);
}

TEST_F(ApproximateDesignScaleTest, SubsampledSolveIsTheSameForAnyThreadCount) {
  ApproximateDesignOptions options = FastOptions();
  options.subsample_size = 150;
  ApproximateDesignSummary one;
  options.num_threads = 1;
  ASSERT_TRUE(SolveApproximateDesign(*puma_, {}, options, &one));
  for (int threads : {2, 4}) {
    SCOPED_TRACE(threads);
    options.num_threads = threads;
    ApproximateDesignSummary other;
    ASSERT_TRUE(SolveApproximateDesign(*puma_, {}, options, &other));
    ExpectSameSolution(one, other);
  }
  // Another seed draws another subsample: still a certified solution.
  options.seed = 2;
  ApproximateDesignSummary seeded;
  ASSERT_TRUE(SolveApproximateDesign(*puma_, {}, options, &seeded));
  EXPECT_EQ(seeded.termination_type, TerminationType::kConvergence);
  EXPECT_NEAR(seeded.log_det, one.log_det,
              puma_->num_parameters() * options.tolerance);
}

// Single-precision storage changes the blocks by a relative 6e-8 and so
// log det M* by about 2 p 6e-8 (< 1e-5 here); both solutions are within
// p * tolerance of their pool's optimum.
TEST_F(ApproximateDesignScaleTest, FloatPoolMatchesDoublePool) {
  const CandidatePool single = FloatCopy(*puma_);
  const int p = puma_->num_parameters();
  for (int64_t size : {int64_t{0}, int64_t{150}}) {
    SCOPED_TRACE(size);
    ApproximateDesignOptions options = FastOptions();
    options.subsample_size = size;
    ApproximateDesignSummary d, f;
    ASSERT_TRUE(SolveApproximateDesign(*puma_, {}, options, &d));
    ASSERT_TRUE(SolveApproximateDesign(single, {}, options, &f)) << f.message;
    EXPECT_EQ(f.termination_type, TerminationType::kConvergence);
    EXPECT_NEAR(f.log_det, d.log_det, p * options.tolerance + 1e-5);
    // Its bound, for the float pool, holds for the double pool's weights
    // up to the rounding.
    EXPECT_GE(f.log_det_upper_bound, d.log_det - 1e-5);
    // Its max variance is over the whole float pool.
    EXPECT_NEAR(f.max_variance, MaxVarianceFromScratch(single, f), 1e-9 * p);
  }
}

TEST_F(ApproximateDesignScaleTest, CertificateReadsTheExactBlocks) {
  const CandidatePool& pool = *puma_;
  CandidatePool single = FloatCopy(pool);
  const int t = pool.block_rows();
  auto stacked = std::make_shared<RowMatrixXd>(pool.stacked());
  single.set_exact_source(
      [stacked, t](int64_t begin, int64_t count, RowMatrixXd* rows) {
        *rows = stacked->middleRows(begin * t, count * t);
      });
  CandidatePool inexact = FloatCopy(pool);  // no exact source
  ApproximateDesignSummary approx;
  ASSERT_TRUE(
      SolveApproximateDesign(pool, {}, ApproximateDesignOptions(), &approx));
  Random random(3);
  const std::vector<int64_t> design =
      random.SampleWithoutReplacement(pool.size(), 40);
  for (const ApproximateDesignSummary* a :
       {static_cast<const ApproximateDesignSummary*>(nullptr),
        static_cast<const ApproximateDesignSummary*>(&approx)}) {
    SelectionSummary on_double, on_single, on_inexact;
    on_double.design = on_single.design = on_inexact.design = design;
    double log_det_double = 0, log_det_single = 0, log_det_inexact = 0;
    ASSERT_TRUE(CertifyDesign(pool, {}, a, 1, &on_double, &log_det_double));
    ASSERT_TRUE(CertifyDesign(single, {}, a, 1, &on_single, &log_det_single));
    ASSERT_TRUE(
        CertifyDesign(inexact, {}, a, 1, &on_inexact, &log_det_inexact));
    EXPECT_NEAR(log_det_double, LogDetFromScratch(pool, design), 1e-10);
    EXPECT_NEAR(log_det_single, log_det_double, 1e-12);
    EXPECT_NEAR(on_single.efficiency_lower_bound,
                on_double.efficiency_lower_bound, 1e-12);
    EXPECT_NEAR(on_single.log_det_upper_bound, on_double.log_det_upper_bound,
                1e-10);
    // Without the exact source the float blocks are certified: the
    // difference is visible, so the comparison above can fail.
    EXPECT_GT(std::abs(log_det_inexact - log_det_double), 1e-9);
    // The streamed sweep is the same for any thread count.
    for (int threads : {2, 4}) {
      SelectionSummary again;
      again.design = design;
      ASSERT_TRUE(CertifyDesign(single, {}, a, threads, &again));
      EXPECT_EQ(again.efficiency_lower_bound, on_single.efficiency_lower_bound);
      EXPECT_EQ(again.log_det_upper_bound, on_single.log_det_upper_bound);
    }
  }
  // The approximate bound is used: it is tighter than the design's own.
  SelectionSummary own, with;
  own.design = with.design = design;
  ASSERT_TRUE(CertifyDesign(single, {}, nullptr, 1, &own));
  ASSERT_TRUE(CertifyDesign(single, {}, &approx, 1, &with));
  EXPECT_GT(with.efficiency_lower_bound, own.efficiency_lower_bound);
}

}  // namespace
}  // namespace activecal

namespace activecal {
namespace {

// Constraints on the column-generation path (a subsample, warm starts, the
// quarter-excess inner target) and tiny p: no excluded pose in the
// support, weights >= 0 summing to 1, and the certificate is the maximum
// over the eligible poses of the whole pool, recomputed from the weights.
TEST(ApproximateDesignColumnGenerationTest, ExcludedPosesAndSmallP) {
  for (int p : {1, 2, 5}) {
    for (int t : {1, 3}) {
      const int64_t n = 3000;
      Random random(100 * p + t);
      RowMatrixXd rows(n * t, p);
      for (int64_t r = 0; r < rows.rows(); ++r) {
        for (int c = 0; c < p; ++c) rows(r, c) = 0.1 * random.Gaussian();
      }
      // Strong poses, every third one excluded.
      const std::vector<int64_t> strong =
          random.SampleWithoutReplacement(n, 30);
      std::vector<char> excluded(n, 0);
      for (size_t k = 0; k < strong.size(); ++k) {
        rows.middleRows(strong[k] * t, t) *= 10.0;
        if (k % 3 == 0) excluded[strong[k]] = 1;
      }
      CandidatePool pool;
      std::string error;
      ASSERT_TRUE(CandidatePool::Create(std::move(rows), t, &pool, &error));
      DesignConstraints constraints;
      constraints.excluded = [&](int64_t i) { return excluded[i] != 0; };
      for (int64_t subsample : {int64_t{0}, int64_t{200}}) {
        ApproximateDesignOptions options;
        options.subsample_size = subsample;
        options.max_added_per_sweep = 5;
        options.seed = 3;
        ApproximateDesignSummary s;
        ASSERT_TRUE(SolveApproximateDesign(pool, constraints, options, &s))
            << s.message;
        EXPECT_EQ(s.termination_type, TerminationType::kConvergence)
            << s.message;
        EXPECT_EQ(subsample > 0,
                  s.message.find("subsample") != std::string::npos)
            << s.message;
        double total = 0;
        for (size_t k = 0; k < s.support.size(); ++k) {
          EXPECT_FALSE(excluded[s.support[k]]) << "p " << p << " t " << t;
          EXPECT_GT(s.weights[k], 0.0);
          total += s.weights[k];
        }
        EXPECT_NEAR(total, 1.0, 1e-12);
        const Eigen::MatrixXd M = WeightedInformationOf(pool, s);
        Eigen::VectorXd d;
        ComputeVariances(pool,
                         Eigen::LLT<Eigen::MatrixXd>(M).solve(
                             Eigen::MatrixXd::Identity(p, p)),
                         1, &d);
        double eligible_max = 0;
        for (int64_t i = 0; i < n; ++i) {
          if (!excluded[i]) eligible_max = std::max(eligible_max, d[i]);
        }
        EXPECT_NEAR(s.max_variance, eligible_max, 1e-9 * p)
            << "p " << p << " t " << t << " subsample " << subsample;
        EXPECT_LE(s.max_variance, p * (1 + options.tolerance));
      }
    }
  }
}

}  // namespace
}  // namespace activecal
