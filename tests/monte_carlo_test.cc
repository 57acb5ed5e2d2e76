// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The identification's predicted covariance agrees with the scatter of its
// estimates over repeated noise, within sampling error.

#include "activecal/estimation/monte_carlo.h"

#include <gtest/gtest.h>

#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"

namespace activecal {
namespace {

std::vector<Measurement> PumaPlan(int num_poses, uint64_t seed) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(m, 5, &lattice, &error));
  Random random(seed);
  std::vector<Measurement> plan;
  for (int64_t i : random.SampleWithoutReplacement(lattice.size(), num_poses)) {
    Measurement x;
    x.joints = lattice.JointValues(i);
    plan.push_back(x);
  }
  return plan;
}

TEST(MonteCarloTest, EmpiricalCovarianceMatchesPrediction) {
  const RobotModel m = Puma560PaperModel();
  MonteCarloOptions options;
  options.num_trials = 300;
  options.noise.position_m = 1e-3;
  options.num_threads = 2;
  MonteCarloSummary s;
  RunMonteCarlo(m, Puma560TrueParameters(), PumaPlan(30, 1), options, &s);
  ASSERT_EQ(s.termination_type, TerminationType::kConvergence) << s.message;
  EXPECT_EQ(s.num_failed, 0);
  for (int i = 0; i < s.std_ratio.size(); ++i) {
    EXPECT_NEAR(s.std_ratio[i], 1.0, 5 * s.std_ratio_sd) << s.names[i];
    // s^2 (J^T J)^-1 at the estimate reports the right std on average.
    EXPECT_NEAR(s.reported_std_ratio[i], 1.0, 0.05) << s.names[i];
    // No bias beyond sampling error of the mean.
    const double sd_mean =
        std::sqrt(s.predicted_covariance(i, i) / s.num_trials);
    EXPECT_LT(std::abs(s.mean_error[i]), 5 * sd_mean) << s.names[i];
  }
  EXPECT_NEAR(s.log_det_ratio, s.expected_log_det_ratio,
              4 * s.log_det_ratio_sd);
  EXPECT_NEAR(s.fraction_within_2_std, 0.954, 0.02);
}

TEST(MonteCarloTest, SameResultForAnyThreadCount) {
  const RobotModel m = Puma560PaperModel();
  MonteCarloOptions options;
  options.num_trials = 40;
  MonteCarloSummary one, two;
  options.num_threads = 1;
  RunMonteCarlo(m, Puma560TrueParameters(), PumaPlan(30, 2), options, &one);
  ASSERT_EQ(one.termination_type, TerminationType::kConvergence);
  options.num_threads = 2;
  RunMonteCarlo(m, Puma560TrueParameters(), PumaPlan(30, 2), options, &two);
  ASSERT_EQ(two.termination_type, TerminationType::kConvergence);
  EXPECT_EQ(one.empirical_covariance, two.empirical_covariance);
}

TEST(MonteCarloTest, BadRequestsAreRefused) {
  const RobotModel m = Puma560PaperModel();
  MonteCarloOptions options;
  options.num_trials = 2;
  MonteCarloSummary s;
  RunMonteCarlo(m, Puma560TrueParameters(), PumaPlan(30, 1), options, &s);
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);
  EXPECT_NE(s.message.find("num_trials must be >= 3"), std::string::npos);
  options.num_trials = 10;
  RunMonteCarlo(m, Puma560TrueParameters(), PumaPlan(5, 1), options, &s);
  EXPECT_NE(s.termination_type, TerminationType::kConvergence);
  EXPECT_NE(s.message.find("too few equations"), std::string::npos)
      << s.message;
}

}  // namespace
}  // namespace activecal
