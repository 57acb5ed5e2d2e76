// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The task criterion: its update formulas against recomputation, the
// exchange and greedy algorithms, the approximate design, its certificate
// against exhaustive search, and the meaning of the predicted RMS.

#include "activecal/selection/task_criterion.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "activecal/calibration/pool_builder.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/task_approximate.h"
#include "activecal/selection/task_exchange.h"
#include "test_util.h"

namespace activecal {
namespace {

class TaskCriterionTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    puma_ = new CandidatePool(testing::PumaPool(3));
    w_ = new Eigen::MatrixXd(TaskMatrix(*puma_));
  }
  static void TearDownTestSuite() {
    delete puma_;
    delete w_;
  }
  static CandidatePool* puma_;
  static Eigen::MatrixXd* w_;
};
CandidatePool* TaskCriterionTest::puma_ = nullptr;
Eigen::MatrixXd* TaskCriterionTest::w_ = nullptr;

double RelativeError(double a, double b) {
  return std::abs(a - b) / std::max(std::abs(b), 1e-300);
}

// 10,000 random adds, removes and swaps: the predicted change of phi
// against phi recomputed from scratch after the change, and the value the
// design keeps against recomputation, to 1e-9 relative. With and without
// prior rows.
TEST_F(TaskCriterionTest, UpdateFormulasMatchRecomputation) {
  const CandidatePool& pool = *puma_;
  const Eigen::MatrixXd& W = *w_;
  Random random(7);
  // Prior: the rows of 12 pool poses, scaled as measurements of unequal
  // precision would be.
  RowMatrixXd prior(36, pool.num_parameters());
  for (int k = 0; k < 12; ++k) {
    prior.middleRows(3 * k, 3) =
        (0.5 + random.Uniform()) * pool.block(random.UniformInt(pool.size()));
  }
  int checked = 0;
  double worst = 0;
  for (const RowMatrixXd& rows :
       {RowMatrixXd(0, pool.num_parameters()), prior}) {
    TaskDesign design(pool, W, rows);
    for (int64_t i : random.SampleWithoutReplacement(pool.size(), 25)) {
      design.Add(i);
    }
    ASSERT_TRUE(design.positive_definite());
    for (int step = 0; step < 5000; ++step) {
      const double before = design.value();
      ASSERT_LE(RelativeError(before, TaskCriterionFromScratch(pool, W, rows,
                                                               design.poses())),
                1e-9);
      const int kind = static_cast<int>(random.UniformInt(3));
      int64_t x;
      do {
        x = random.UniformInt(pool.size());
      } while (design.Contains(x));
      const int64_t y =
          design.poses()[random.UniformInt(design.poses().size())];
      std::vector<int64_t> next = design.poses();
      double predicted;
      if ((kind == 0 && design.size() < 40) || design.size() <= 20) {
        predicted = before + design.AddChange(x);
        next.push_back(x);
        design.Add(x);
      } else if (kind == 1) {
        predicted = before + design.RemoveChange(y);
        next.erase(std::find(next.begin(), next.end(), y));
        ASSERT_TRUE(design.Remove(y));
      } else {
        predicted = before + design.SwapChange(x, y);
        next.erase(std::find(next.begin(), next.end(), y));
        next.push_back(x);
        design.Add(x);
        ASSERT_TRUE(design.Remove(y));
      }
      const double scratch = TaskCriterionFromScratch(pool, W, rows, next);
      const double e = RelativeError(predicted, scratch);
      worst = std::max(worst, e);
      ASSERT_LE(e, 1e-9) << "step " << step << " kind " << kind;
      ASSERT_LE(RelativeError(design.value(), scratch), 1e-9);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 10000);
  RecordProperty("worst_relative_error", std::to_string(worst));
}

// W = I is the A-criterion: phi = tr(M^-1).
TEST_F(TaskCriterionTest, IdentityTaskMatrixIsTheACriterion) {
  const int p = puma_->num_parameters();
  const std::vector<int64_t> d = {0, 5, 17, 40, 77, 120, 300, 512, 700, 11};
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  for (int64_t i : d) M += puma_->block(i).transpose() * puma_->block(i);
  const double a = M.inverse().trace();
  EXPECT_LE(RelativeError(TaskCriterionFromScratch(
                              *puma_, Eigen::MatrixXd::Identity(p, p),
                              RowMatrixXd(0, p), d),
                          a),
            1e-8);
  // And a singular design has phi = +infinity.
  EXPECT_EQ(TaskCriterionFromScratch(*puma_, *w_, RowMatrixXd(0, p), {0, 1}),
            std::numeric_limits<double>::infinity());
}

// The predicted RMS means what it says: parameter errors drawn from
// N(0, sigma^2 M^-1) give task position errors J_x delta whose RMS over
// the task poses and the draws is sigma sqrt(phi).
TEST_F(TaskCriterionTest, PredictedRmsIsTheRmsOfSimulatedTaskErrors) {
  const CandidatePool& pool = *puma_;
  const int p = pool.num_parameters();
  Random random(3);
  const std::vector<int64_t> d =
      random.SampleWithoutReplacement(pool.size(), 30);
  const double phi = TaskCriterionFromScratch(pool, *w_, RowMatrixXd(0, p), d);
  const double sigma = 1e-4;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  for (int64_t i : d) M += pool.block(i).transpose() * pool.block(i);
  // delta = sigma L^-T z has covariance sigma^2 M^-1 for M = L L^T.
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  double sum_sq = 0;
  const int draws = 4000;
  for (int k = 0; k < draws; ++k) {
    Eigen::VectorXd z(p);
    for (int j = 0; j < p; ++j) z[j] = random.Gaussian();
    const Eigen::VectorXd delta = sigma * llt.matrixU().solve(z);  // U = L^T
    sum_sq += (pool.stacked() * delta).squaredNorm() / pool.size();
  }
  const double rms = std::sqrt(sum_sq / draws);
  EXPECT_NEAR(rms / PredictedTaskRms(phi, sigma), 1.0, 0.03);
}

TEST_F(TaskCriterionTest, ExchangeEndsAtASwapLocalOptimumBelowItsStart) {
  const CandidatePool& pool = *puma_;
  const int p = pool.num_parameters();
  TaskExchangeOptions options;
  options.num_poses = 20;
  options.restarts = 2;
  SelectionSummary s;
  ASSERT_TRUE(
      TaskExchange(pool, *w_, RowMatrixXd(0, p), {}, options, nullptr, &s))
      << s.message;
  EXPECT_EQ(s.termination_type, TerminationType::kConvergence);
  ASSERT_EQ(s.design.size(), 20u);
  const double phi =
      TaskCriterionFromScratch(pool, *w_, RowMatrixXd(0, p), s.design);
  EXPECT_LE(RelativeError(s.task_criterion, phi), 1e-12);
  // No single swap lowers phi by more than the threshold (checked from
  // scratch on every pair).
  for (size_t k = 0; k < s.design.size(); ++k) {
    for (int64_t x = 0; x < pool.size(); ++x) {
      if (std::find(s.design.begin(), s.design.end(), x) != s.design.end()) {
        continue;
      }
      std::vector<int64_t> d = s.design;
      d[k] = x;
      ASSERT_GE(TaskCriterionFromScratch(pool, *w_, RowMatrixXd(0, p), d),
                phi * (1 - 1e-8));
    }
  }
  // Same design for any thread count.
  for (int threads : {1, 2, 3}) {
    options.num_threads = threads;
    SelectionSummary t;
    ASSERT_TRUE(
        TaskExchange(pool, *w_, RowMatrixXd(0, p), {}, options, nullptr, &t));
    EXPECT_EQ(t.design, s.design) << threads << " threads";
  }
  // A random 20-pose design is worse, and so is greedy.
  SelectionSummary g;
  ASSERT_TRUE(TaskGreedy(pool, *w_, RowMatrixXd(0, p), {}, 20, 2, &g));
  EXPECT_LE(phi, g.task_criterion * (1 + 1e-12));
}

TEST_F(TaskCriterionTest, GreedyCurveIsNestedAndNonIncreasing) {
  const CandidatePool& pool = *puma_;
  const int p = pool.num_parameters();
  SelectionSummary g;
  std::vector<double> curve;
  ASSERT_TRUE(TaskGreedy(pool, *w_, RowMatrixXd(0, p), {}, 30, 2, &g, &curve));
  ASSERT_EQ(curve.size(), 30u);
  int finite = 0;
  for (size_t k = 0; k < curve.size(); ++k) {
    const std::vector<int64_t> prefix(g.design.begin(),
                                      g.design.begin() + k + 1);
    const double scratch =
        TaskCriterionFromScratch(pool, *w_, RowMatrixXd(0, p), prefix);
    if (std::isfinite(curve[k])) {
      ++finite;
      EXPECT_LE(RelativeError(curve[k], scratch), 1e-9) << k;
    } else {
      EXPECT_FALSE(std::isfinite(scratch)) << k;
    }
    if (k > 0) {
      EXPECT_LE(curve[k], curve[k - 1]) << k;
    }
  }
  EXPECT_GT(finite, 15);
}

TEST_F(TaskCriterionTest, ApproximateDesignSatisfiesEquivalenceTheorem) {
  const CandidatePool& pool = *puma_;
  TaskApproximateSummary a;
  TaskApproximateOptions options;
  options.tolerance = 1e-2;
  ASSERT_TRUE(SolveTaskApproximateDesign(pool, *w_, {}, options, &a))
      << a.message;
  EXPECT_EQ(a.termination_type, TerminationType::kConvergence) << a.message;
  const int p = pool.num_parameters();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  double total = 0;
  for (size_t k = 0; k < a.support.size(); ++k) {
    M += a.weights[k] * pool.block(a.support[k]).transpose() *
         pool.block(a.support[k]);
    total += a.weights[k];
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  const Eigen::MatrixXd V = M.inverse();
  const double phi = (*w_ * V).trace();
  EXPECT_LE(RelativeError(a.criterion, phi), 1e-8);
  const Eigen::MatrixXd G = V * *w_ * V;
  double max_b = 0, weighted = 0;
  for (int64_t i = 0; i < pool.size(); ++i) {
    max_b = std::max(max_b,
                     (pool.block(i) * G * pool.block(i).transpose()).trace());
  }
  for (size_t k = 0; k < a.support.size(); ++k) {
    weighted += a.weights[k] * (pool.block(a.support[k]) * G *
                                pool.block(a.support[k]).transpose())
                                   .trace();
  }
  EXPECT_LE(RelativeError(weighted, phi), 1e-8);  // sum w_i b_i = phi
  EXPECT_LE(max_b, phi * (1 + 1e-2) * (1 + 1e-9));
  EXPECT_GE(a.efficiency_lower_bound, 1 / (1 + 1e-2) - 1e-9);
  EXPECT_LE(a.efficiency_lower_bound, 1.0);
  // Tolerance crossed: one round of few sweeps stops early, and says so.
  options.max_rounds = 1;
  options.inner_iterations = 2;
  TaskApproximateSummary b;
  ASSERT_TRUE(SolveTaskApproximateDesign(pool, *w_, {}, options, &b));
  EXPECT_EQ(b.termination_type, TerminationType::kNoConvergence);
  EXPECT_LE(b.criterion_lower_bound, a.criterion * (1 + 1e-9));
}

double ExhaustiveBestPhi(const CandidatePool& pool, const Eigen::MatrixXd& W) {
  double best = std::numeric_limits<double>::infinity();
  const int64_t n = pool.size();
  const RowMatrixXd none(0, pool.num_parameters());
  for (int64_t a = 0; a < n; ++a) {
    for (int64_t b = a + 1; b < n; ++b) {
      for (int64_t c = b + 1; c < n; ++c) {
        best =
            std::min(best, TaskCriterionFromScratch(pool, W, none, {a, b, c}));
      }
    }
  }
  return best;
}

TEST(TaskCertificateTest, NeverAboveTheTrueEfficiencyFoundByExhaustiveSearch) {
  const CandidatePool pool = testing::PlanarPool();
  const int p = pool.num_parameters();
  ASSERT_EQ(p, 6);
  // The task: the whole pool.
  const Eigen::MatrixXd W = TaskMatrix(pool);
  const double optimum = ExhaustiveBestPhi(pool, W);
  ASSERT_TRUE(std::isfinite(optimum));
  TaskApproximateSummary approx;
  ASSERT_TRUE(SolveTaskApproximateDesign(pool, W, {}, TaskApproximateOptions(),
                                         &approx))
      << approx.message;
  // phi* / N bounds the exhaustive optimum from below.
  EXPECT_LE(approx.criterion_lower_bound / 3, optimum * (1 + 1e-12));
  const RowMatrixXd none(0, p);
  std::vector<std::vector<int64_t>> designs;
  TaskExchangeOptions fo;
  fo.num_poses = 3;
  SelectionSummary s;
  ASSERT_TRUE(TaskExchange(pool, W, none, {}, fo, &approx, &s)) << s.message;
  designs.push_back(s.design);
  // Fedorov with restarts finds the exhaustive optimum on this pool.
  EXPECT_LE(RelativeError(s.task_criterion, optimum), 1e-9);
  ASSERT_TRUE(TaskGreedy(pool, W, none, {}, 3, 1, &s));
  designs.push_back(s.design);
  Random random(2);
  while (designs.size() < 40) {
    std::vector<int64_t> d = random.SampleWithoutReplacement(pool.size(), 3);
    if (std::isfinite(TaskCriterionFromScratch(pool, W, none, d))) {
      designs.push_back(d);
    }
  }
  int tight = 0;
  testing::CheckEachDesign(
      designs, approx,
      [&](const TaskApproximateSummary* a, SelectionSummary* summary) {
        ASSERT_TRUE(CertifyTaskDesign(pool, W, {}, a, 1, summary));
        const double phi =
            TaskCriterionFromScratch(pool, W, none, summary->design);
        const double true_efficiency = optimum / phi;
        EXPECT_LE(summary->efficiency_lower_bound, true_efficiency + 1e-12);
        EXPECT_LE(summary->task_criterion_lower_bound, optimum * (1 + 1e-12));
        EXPECT_GT(summary->efficiency_lower_bound, 0.0);
        if (summary->efficiency_lower_bound > 0.5 * true_efficiency) ++tight;
      });
  EXPECT_GT(tight, 0);
}

// A pool larger than the reduced-pool threshold: the restarts swap within
// the poses of largest b_i, the best is polished over the whole pool. The
// result must be a swap local optimum of the full problem (checked from
// scratch on every pair), keep the fixed poses, name the reduction, and
// be within a few percent of the full-pool exchange.
TEST_F(TaskCriterionTest, ReducedPoolExchangeIsPolishedToAFullPoolOptimum) {
  const CandidatePool& pool = *puma_;
  const int p = pool.num_parameters();
  const RowMatrixXd none(0, p);
  TaskApproximateSummary approx;
  TaskApproximateOptions ao;
  ao.tolerance = 1e-2;
  ASSERT_TRUE(SolveTaskApproximateDesign(pool, *w_, {}, ao, &approx))
      << approx.message;
  DesignConstraints constraints;
  constraints.fixed = {7, 500};
  TaskExchangeOptions full;
  full.num_poses = 20;
  full.restarts = 2;
  full.reduced_pool_size = 0;  // always the whole pool
  SelectionSummary f;
  ASSERT_TRUE(TaskExchange(pool, *w_, none, constraints, full, &approx, &f))
      << f.message;
  EXPECT_EQ(f.message.find("reduced pool"), std::string::npos) << f.message;
  TaskExchangeOptions reduced = full;
  reduced.reduced_pool_size = 60;  // 729 poses > max(60, 2 * 20)
  reduced.reduced_pool_per_pose = 2;
  SelectionSummary r;
  ASSERT_TRUE(TaskExchange(pool, *w_, none, constraints, reduced, &approx, &r))
      << r.message;
  EXPECT_NE(r.message.find("reduced pool"), std::string::npos) << r.message;
  ASSERT_EQ(r.design.size(), 20u);
  std::vector<int64_t> sorted = r.design;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::unique(sorted.begin(), sorted.end()), sorted.end());
  for (int64_t i : constraints.fixed) {
    EXPECT_NE(std::find(r.design.begin(), r.design.end(), i), r.design.end())
        << "fixed pose " << i << " lost";
  }
  for (int64_t i : r.design) ASSERT_TRUE(i >= 0 && i < pool.size()) << i;
  const double phi = TaskCriterionFromScratch(pool, *w_, none, r.design);
  EXPECT_LE(RelativeError(r.task_criterion, phi), 1e-12);
  EXPECT_LE(phi, f.task_criterion * 1.05);
  for (size_t k = 0; k < r.design.size(); ++k) {
    if (r.design[k] == 7 || r.design[k] == 500) continue;
    for (int64_t x = 0; x < pool.size(); ++x) {
      if (std::find(r.design.begin(), r.design.end(), x) != r.design.end()) {
        continue;
      }
      std::vector<int64_t> d = r.design;
      d[k] = x;
      ASSERT_GE(TaskCriterionFromScratch(pool, *w_, none, d), phi * (1 - 1e-8))
          << "swap " << r.design[k] << " -> " << x;
    }
  }
}

// With poses already measured, a batch smaller than a non-singular design
// has exactly the size asked, and lowers phi below the prior's own.
TEST_F(TaskCriterionTest, ABatchWithAPriorHasTheSizeAsked) {
  const CandidatePool& pool = *puma_;
  Random random(11);
  RowMatrixXd prior(45, pool.num_parameters());
  for (int k = 0; k < 15; ++k) {
    prior.middleRows(3 * k, 3) = pool.block(random.UniformInt(pool.size()));
  }
  const double alone = TaskCriterionFromScratch(pool, *w_, prior, {});
  ASSERT_TRUE(std::isfinite(alone));
  for (int n : {1, 3, 6}) {
    TaskExchangeOptions options;
    options.num_poses = n;
    options.restarts = 2;
    SelectionSummary s;
    ASSERT_TRUE(TaskExchange(pool, *w_, prior, {}, options, nullptr, &s))
        << s.message;
    EXPECT_EQ(s.design.size(), static_cast<size_t>(n));
    EXPECT_LT(s.task_criterion, alone);
    SelectionSummary g;
    ASSERT_TRUE(TaskGreedy(pool, *w_, prior, {}, n, 1, &g)) << g.message;
    EXPECT_EQ(g.design.size(), static_cast<size_t>(n));
    EXPECT_LE(s.task_criterion, g.task_criterion * (1 + 1e-12));
  }
}

// The rows of poses already measured are whitened to the reference sigma:
// a measurement giving its own sigma counts (sigma_ref / sigma)^2 as much.
TEST(MeasuredInformationRowsTest, MeasuredRowsAreWhitenedBySigma) {
  const RobotModel model = Puma560PaperModel();
  Random random(5);
  std::vector<Measurement> measured;
  for (int k = 0; k < 4; ++k) {
    Measurement m;
    m.joints = testing::RandomJoints(model, &random);
    measured.push_back(m);
  }
  measured[1].sigma_m = Eigen::Vector3d(1e-3, 2e-4, 0);  // z not given
  Measurement pose;
  pose.type = MeasurementType::kPose;
  pose.joints = testing::RandomJoints(model, &random);
  pose.sigma_m = Eigen::Vector3d(5e-4, 5e-4, 5e-4);
  pose.sigma_rad = 1e-3;
  measured.push_back(pose);
  RowMatrixXd rows, plain;
  std::string error;
  const double sigma = 1e-4, rotation_weight = 0.5;
  ASSERT_TRUE(MeasuredInformationRows(model, model.nominal, measured,
                                      rotation_weight, sigma, &rows, &error))
      << error;
  Eigen::MatrixXd J;
  ASSERT_TRUE(StackedJacobian(model, model.nominal, measured, rotation_weight,
                              &J, &error));
  ASSERT_EQ(rows.rows(), 4 * 3 + 6);
  const double scale[18] = {1, 1, 1, 0.1, 0.5, 1,   1,   1,   1,
                            1, 1, 1, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2};
  for (int r = 0; r < 18; ++r) {
    EXPECT_LE((rows.row(r) - scale[r] * J.row(r)).norm(),
              1e-15 * J.row(r).norm() + 1e-300)
        << "row " << r;
  }
  // Fewer equations than a design needs are fine with the prior.
}

}  // namespace
}  // namespace activecal
