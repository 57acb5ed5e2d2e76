// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A Monte Carlo check of the identification's statistics: the same design
// is measured again and again with fresh noise, identified each time, and
// the scatter of the estimates is compared with the covariance the theory
// predicts, sigma^2 (J^T J)^-1 at the true values (J: the Jacobian of the
// design's measurements, sigma: the noise standard deviation).
//
//   MonteCarloOptions options;
//   options.num_trials = 1000;
//   MonteCarloSummary summary;
//   RunMonteCarlo(model, truth, plan, options, &summary);
//   // summary.std_ratio[k] ~ 1 +- 1/sqrt(2 (n - 1)) if the theory holds.
//
// Trials run in parallel; trial t draws its noise from a stream of its own,
// so the result does not depend on the thread count.

#ifndef ACTIVECAL_ESTIMATION_MONTE_CARLO_H_
#define ACTIVECAL_ESTIMATION_MONTE_CARLO_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/simulation.h"
#include "activecal/core/types.h"
#include "activecal/estimation/identification.h"

namespace activecal {

struct MonteCarloOptions {
  int num_trials = 1000;
  SimulationNoise noise = {0.01, 0.001};
  uint64_t seed = 1;
  int num_threads = 0;  // <= 0: all
  // Start of every identification: the model's nominal values.
  IdentificationOptions identification;
  ProgressCallback progress;  // trials done

  bool IsValid(std::string* error) const;
};

struct MonteCarloSummary {
  // kConvergence when the comparison was made; kUserFailure for invalid
  // options or plan, kFailure when the plan cannot identify the parameters
  // or too few trials succeeded. `message` says why.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  int num_trials = 0;
  int num_failed = 0;  // identifications that did not succeed (excluded)
  std::vector<std::string> names;
  // sigma^2 (J^T J)^-1 at the truth, and the covariance of the estimates.
  Eigen::MatrixXd predicted_covariance;
  Eigen::MatrixXd empirical_covariance;
  Eigen::VectorXd mean_error;  // mean estimate - truth
  // Empirical std / predicted std, per parameter; under the theory each is
  // 1 with a sampling standard deviation of about std_ratio_sd.
  Eigen::VectorXd std_ratio;
  double std_ratio_sd = 0.0;
  // Mean over trials of the std Identify reported / predicted std.
  Eigen::VectorXd reported_std_ratio;
  // ln det(empirical) - ln det(predicted); for Gaussian estimates with the
  // predicted covariance its expectation (a Wishart bias, not 0) and
  // standard deviation are:
  double log_det_ratio = 0.0;
  double expected_log_det_ratio = 0.0;
  double log_det_ratio_sd = 0.0;
  // Each estimate's errors within +-2 predicted std, averaged over the
  // parameters (0.954 under the theory).
  double fraction_within_2_std = 0.0;
  double seconds = 0.0;

  std::string BriefReport() const;
};

// Repeats the identification of `model` from measurements of `plan` (types
// and joints; measured values ignored) simulated from `true_parameters`.
void RunMonteCarlo(const RobotModel& model,
                   const Eigen::VectorXd& true_parameters,
                   const std::vector<Measurement>& plan,
                   const MonteCarloOptions& options,
                   MonteCarloSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_MONTE_CARLO_H_
