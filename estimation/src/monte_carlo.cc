// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/monte_carlo.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/residuals/jacobians.h"

namespace activecal {
namespace {

// Digamma and trigamma by recurrence up to x >= 6, then the asymptotic
// series (error < 1e-12 there).
double Digamma(double x) {
  double r = 0.0;
  while (x < 6.0) {
    r -= 1.0 / x;
    x += 1.0;
  }
  const double f = 1.0 / (x * x);
  return r + std::log(x) - 0.5 / x -
         f * (1.0 / 12 - f * (1.0 / 120 - f * (1.0 / 252 - f * (1.0 / 240))));
}

double Trigamma(double x) {
  double r = 0.0;
  while (x < 6.0) {
    r += 1.0 / (x * x);
    x += 1.0;
  }
  const double f = 1.0 / (x * x);
  return r + 1.0 / x + f / 2 +
         f / x * (1.0 / 6 - f * (1.0 / 30 - f * (1.0 / 42 - f / 30)));
}

double LogDetSpd(const Eigen::MatrixXd& A, bool* ok) {
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  *ok = llt.info() == Eigen::Success;
  if (!*ok) return 0.0;
  return 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
}

}  // namespace

bool MonteCarloOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (num_trials < 3) {
    msg << "num_trials must be >= 3, got " << num_trials;
  } else if (!(noise.position_m > 0) || !std::isfinite(noise.position_m)) {
    msg << "the position noise must be finite and > 0, got "
        << noise.position_m;
  } else if (!(noise.rotation_rad >= 0) || !std::isfinite(noise.rotation_rad)) {
    msg << "the rotation noise must be finite and >= 0";
  } else {
    std::string why;
    if (!identification.IsValid(&why)) msg << why;
  }
  if (msg.tellp() == 0) return true;
  if (error) *error = msg.str();
  return false;
}

void RunMonteCarlo(const RobotModel& model,
                   const Eigen::VectorXd& true_parameters,
                   const std::vector<Measurement>& plan,
                   const MonteCarloOptions& options,
                   MonteCarloSummary* summary) {
  CHECK(summary != nullptr);
  const auto start = std::chrono::steady_clock::now();
  *summary = MonteCarloSummary();
  auto fail = [summary](const std::string& why) {
    summary->termination_type = TerminationType::kFailure;
    summary->message = why;
  };
  auto user_failure = [summary](const std::string& why) {
    summary->termination_type = TerminationType::kUserFailure;
    summary->message = why;
  };
  std::string error;
  if (!options.IsValid(&error)) return user_failure(error);
  // Every row must carry noise of one standard deviation: pose rows are
  // weighted by the rotation weight.
  for (const Measurement& m : plan) {
    if (m.type == MeasurementType::kPose &&
        std::abs(options.noise.rotation_rad *
                     options.identification.rotation_weight_m_per_rad -
                 options.noise.position_m) > 1e-12 * options.noise.position_m) {
      return user_failure(
          "pose measurements: set rotation_weight_m_per_rad = position noise "
          "/ rotation noise so every residual row has the same noise");
    }
  }
  Eigen::MatrixXd J;
  if (!StackedJacobian(model, true_parameters, plan,
                       options.identification.rotation_weight_m_per_rad, &J,
                       &error)) {
    return user_failure(error);
  }
  const IdentifiabilityReport report =
      AnalyzeIdentifiability(model, J, options.identification.rank_tolerance);
  if (!report.identifiable()) return fail(report.Message());
  const int p = model.num_free();
  const double sigma = options.noise.position_m;
  const Eigen::MatrixXd information = J.transpose() * J;
  summary->predicted_covariance =
      sigma * sigma * information.ldlt().solve(Eigen::MatrixXd::Identity(p, p));
  summary->names = model.FreeParameterNames();
  const Eigen::VectorXd truth = ExtractFree(model, true_parameters);
  const Eigen::VectorXd predicted_std =
      summary->predicted_covariance.diagonal().cwiseSqrt();

  const int n = options.num_trials;
  Eigen::MatrixXd errors(p, n);
  Eigen::MatrixXd reported(p, n);
  std::vector<char> ok(n, 0);
  std::atomic<int64_t> done{0};
  IdentificationOptions id_options = options.identification;
  ParallelFor(n, options.num_threads, [&](int64_t b, int64_t e, int) {
    for (int64_t t = b; t < e; ++t) {
      std::vector<Measurement> measured;
      std::string why;
      IdentificationSummary s;
      if (SimulateMeasurements(model, true_parameters, plan, options.noise,
                               Random::StreamSeed(options.seed, t), &measured,
                               &why)) {
        Identify(model, measured, model.nominal, id_options, &s);
      }
      if (s.termination_type == TerminationType::kConvergence) {
        errors.col(t) = s.estimates - truth;
        reported.col(t) = s.standard_deviations;
        ok[t] = 1;
      }
      if (options.progress) options.progress(++done, n);
    }
  });
  std::vector<int> good;
  for (int t = 0; t < n; ++t) {
    if (ok[t]) good.push_back(t);
  }
  summary->num_trials = n;
  summary->num_failed = n - static_cast<int>(good.size());
  const int m = static_cast<int>(good.size());
  if (m < 3) return fail("fewer than 3 identifications succeeded");
  Eigen::MatrixXd E(p, m), R(p, m);
  for (int k = 0; k < m; ++k) {
    E.col(k) = errors.col(good[k]);
    R.col(k) = reported.col(good[k]);
  }
  summary->mean_error = E.rowwise().mean();
  const Eigen::MatrixXd centered = E.colwise() - summary->mean_error;
  summary->empirical_covariance = centered * centered.transpose() / (m - 1);
  summary->std_ratio =
      summary->empirical_covariance.diagonal().cwiseSqrt().cwiseQuotient(
          predicted_std);
  summary->std_ratio_sd = 1.0 / std::sqrt(2.0 * (m - 1));
  summary->reported_std_ratio = R.rowwise().mean().cwiseQuotient(predicted_std);
  int within = 0;
  for (int k = 0; k < m; ++k) {
    for (int i = 0; i < p; ++i) {
      if (std::abs(E(i, k)) <= 2 * predicted_std[i]) ++within;
    }
  }
  summary->fraction_within_2_std = static_cast<double>(within) / (m * p);
  bool ok_emp, ok_pred;
  const double ld_emp = LogDetSpd(summary->empirical_covariance, &ok_emp);
  const double ld_pred = LogDetSpd(summary->predicted_covariance, &ok_pred);
  if (!ok_emp || !ok_pred) {
    return fail("a covariance is not positive definite (too few trials for " +
                std::to_string(p) + " parameters?)");
  }
  summary->log_det_ratio = ld_emp - ld_pred;
  // (m - 1) S ~ Wishart_p(Sigma, m - 1).
  double expected = p * std::log(2.0 / (m - 1)), variance = 0.0;
  for (int i = 1; i <= p; ++i) {
    expected += Digamma(0.5 * (m - i));
    variance += Trigamma(0.5 * (m - i));
  }
  summary->expected_log_det_ratio = expected;
  summary->log_det_ratio_sd = std::sqrt(variance);
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  summary->termination_type = TerminationType::kConvergence;
  std::ostringstream msg;
  msg << m << " of " << n << " identifications succeeded";
  summary->message = msg.str();
}

std::string MonteCarloSummary::BriefReport() const {
  std::ostringstream out;
  out << "activecal Monte Carlo: " << TerminationTypeToString(termination_type)
      << "\n  " << message << "\n";
  if (termination_type != TerminationType::kConvergence) return out.str();
  out << "  empirical / predicted std: min " << std_ratio.minCoeff()
      << ", mean " << std_ratio.mean() << ", max " << std_ratio.maxCoeff()
      << " (sampling sd " << std_ratio_sd << ")\n";
  out << "  ln det(empirical) - ln det(predicted): " << log_det_ratio
      << " (expected " << expected_log_det_ratio << " +- " << log_det_ratio_sd
      << ")\n";
  out << "  errors within 2 predicted std: " << fraction_within_2_std
      << " (0.954 expected); " << seconds << " s\n";
  return out.str();
}

}  // namespace activecal
