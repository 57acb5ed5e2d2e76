// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Numerical robustness of the selector: long update chains, near-singular
// designs, duplicated poses, parameters some poses cannot see, and pools
// read from files with such poses.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "activecal/core/random.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/design.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/information_matrix.h"
#include "test_util.h"

namespace activecal {
namespace {

TEST(RobustnessTest, HundredThousandAlternatingUpdatesStayWithin1e8) {
  const CandidatePool pool = testing::PumaPool(3);
  Design design(pool);
  Random random(11);
  for (int64_t i : random.SampleWithoutReplacement(pool.size(), 30)) {
    design.Add(i);
  }
  double worst = 0;
  for (int step = 0; step < 100000; ++step) {
    if (step % 2 == 0) {
      testing::AddRandomNewPose(&design, &random);
    } else {
      // Remove a random pose; a refused removal is retried with another.
      testing::RemoveRandomPose(&design, &random);
    }
    if (step % 97 == 0 || step >= 99990) {
      const double scratch = LogDetFromScratch(pool, design.poses());
      worst = std::max(
          worst, std::abs(design.log_det() - scratch) / std::abs(scratch));
    }
  }
  EXPECT_LT(worst, 1e-8);
  EXPECT_EQ(design.size(), 30);
}

TEST(RobustnessTest, NearSingularDesignKeepsLogDetAccurate) {
  // 9 poses (27 rows for 27 parameters) plus one that barely differs from
  // one of them: M is nearly singular along few directions.
  const CandidatePool base = testing::PumaPool(3);
  Random random(4);
  std::vector<int64_t> poses;
  do {
    poses = random.SampleWithoutReplacement(base.size(), 9);
  } while (!std::isfinite(LogDetFromScratch(base, poses)));
  InformationMatrix info(base.num_parameters());
  for (int64_t i : poses) info.Add(base.block(i));
  ASSERT_TRUE(info.positive_definite());
  // Add then remove 1000 times a scaled copy of a design pose: each
  // removal returns M to the near-singular design exactly in exact
  // arithmetic.
  const Eigen::MatrixXd X = base.block(poses[0]) * 1e-3;
  for (int k = 0; k < 1000; ++k) {
    info.Add(X);
    ASSERT_TRUE(info.Remove(X));
  }
  const double scratch = LogDetFromScratch(base, poses);
  EXPECT_NEAR(info.log_det(), scratch, 1e-8 * std::abs(scratch));
}

TEST(RobustnessTest, DuplicatedPosesAndBlindParameters) {
  // A pool where every pose appears twice and one parameter (the last
  // column) is seen by only a quarter of the poses.
  const CandidatePool base = testing::PumaPool(3);
  const int p = base.num_parameters();
  const int64_t n = base.size();
  RowMatrixXd stacked(2 * 3 * n, p);
  for (int64_t i = 0; i < n; ++i) {
    Eigen::MatrixXd b = base.block(i);
    if (i % 4 != 0) b.col(p - 1).setZero();
    stacked.middleRows(3 * i, 3) = b;
    stacked.middleRows(3 * (n + i), 3) = b;
  }
  CandidatePool pool;
  std::string error;
  ASSERT_TRUE(CandidatePool::Create(std::move(stacked), 3, &pool, &error));
  // Duplicates: a design may hold both copies; log det stays consistent.
  Design design(pool);
  Random random(5);
  for (int64_t i : random.SampleWithoutReplacement(n, 30)) {
    design.Add(i);
    if (design.size() < 34) design.Add(n + i);
  }
  EXPECT_NEAR(design.log_det(), LogDetFromScratch(pool, design.poses()),
              1e-9 * std::abs(design.log_det()));
  // The algorithms still work and keep seeing the blind parameter.
  FedorovOptions options;
  options.num_poses = 30;
  options.restarts = 2;
  SelectionSummary summary;
  ASSERT_TRUE(FedorovExchange(pool, {}, options, nullptr, &summary))
      << summary.message;
  EXPECT_TRUE(std::isfinite(summary.log_det));
  int seeing = 0;
  for (int64_t i : summary.design) {
    if (pool.block(i).col(p - 1).norm() > 0) ++seeing;
  }
  EXPECT_GT(seeing, 0);
  EXPECT_NEAR(summary.log_det, LogDetFromScratch(pool, summary.design),
              1e-9 * std::abs(summary.log_det));
}

TEST(RobustnessTest, PoolBlindToAParameterIsRefusedWithAMessage) {
  const CandidatePool base = testing::PumaPool(3);
  RowMatrixXd stacked(3 * base.size(), base.num_parameters());
  for (int64_t i = 0; i < base.size(); ++i) {
    Eigen::MatrixXd b = base.block(i);
    b.col(4).setZero();
    stacked.middleRows(3 * i, 3) = b;
  }
  CandidatePool pool;
  std::string error;
  ASSERT_TRUE(CandidatePool::Create(std::move(stacked), 3, &pool, &error));
  ExchangeAddExchangeOptions options;
  SelectionSummary summary;
  EXPECT_FALSE(ExchangeAddExchange(pool, {}, options, &summary));
  EXPECT_NE(summary.message.find("singular"), std::string::npos)
      << summary.message;
}

}  // namespace
}  // namespace activecal

namespace activecal {
namespace {

// The selector on blocks of 6 rows (6D pose measurements) and of 1 row
// (one scalar per candidate, as a distance): updates match recomputation
// and the algorithms run.
TEST(RobustnessTest, SelectorWorksForBlocksOfAnyRowCount) {
  const CandidatePool position = testing::PumaPool(3);
  for (int rows : {1, 6}) {
    RowMatrixXd stacked;
    if (rows == 1) {
      stacked = position.stacked();  // every scalar row a candidate
    } else {
      // Pairs of consecutive position blocks as one 6-row candidate.
      const int64_t n = position.size() / 2;
      stacked = position.stacked().topRows(6 * n);
    }
    CandidatePool pool;
    std::string error;
    ASSERT_TRUE(CandidatePool::Create(std::move(stacked), rows, &pool, &error))
        << error;
    Design design(pool);
    Random random(rows);
    for (int64_t i : random.SampleWithoutReplacement(pool.size(), 60)) {
      design.Add(i);
    }
    for (int step = 0; step < 2000; ++step) {
      if (step % 2 == 0) {
        testing::AddRandomNewPose(&design, &random);
      } else {
        testing::RemoveRandomPose(&design, &random);
      }
    }
    const double scratch = LogDetFromScratch(pool, design.poses());
    EXPECT_NEAR(design.log_det(), scratch, 1e-9 * std::abs(scratch)) << rows;
    FedorovOptions options;
    options.num_poses = rows == 1 ? 40 : 10;
    options.restarts = 2;
    SelectionSummary summary;
    ASSERT_TRUE(FedorovExchange(pool, {}, options, nullptr, &summary))
        << rows << ": " << summary.message;
    EXPECT_NEAR(summary.log_det, LogDetFromScratch(pool, summary.design),
                1e-9 * std::abs(summary.log_det))
        << rows;
  }
}

}  // namespace
}  // namespace activecal
