// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// RunMonteCarloStudy: checks the identification's statistics on one design
// (what activecal_monte_carlo runs and prints). The design is a poses CSV
// or, without one, the exchange-add-exchange design of the paper's 5-level
// lattice (Section V-D); RunMonteCarlo (estimation/monte_carlo.h) measures
// it again and again with fresh simulated noise, identifies each time and
// compares the scatter of the estimates with the predicted covariance
// sigma^2 (J^T J)^-1 (per-parameter std ratio, determinant ratio, bias).
//
//   MonteCarloStudyOptions options;
//   options.num_trials = 1000;
//   MonteCarloStudySummary summary;
//   const bool ok = RunMonteCarloStudy(robot.model, robot.true_parameters,
//                                      options, &summary);
//   std::printf("%s", summary.report.c_str());  // also on a failure
//   if (!ok) LOG(ERROR) << summary.message;

#ifndef ACTIVECAL_CALIBRATION_MONTE_CARLO_STUDY_H_
#define ACTIVECAL_CALIBRATION_MONTE_CARLO_STUDY_H_

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "activecal/calibration/select_workflow.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/estimation/monte_carlo.h"

namespace activecal {

struct MonteCarloStudyOptions {
  // The design: a poses CSV (e.g. from activecal_select). Empty: the
  // exchange-add-exchange design of the 5-level lattice (Random stream
  // (seed, 2)).
  std::string poses_csv;
  int num_trials = 1000;  // noise realisations (identifications)
  double noise_m = 0.01;  // on each axis (m)
  uint64_t seed = 1;      // the design's and (stream 5) the noise's
  int num_threads = 0;    // 0: all; the results do not depend on it
  // The program's name, in the result line.
  std::string program_name = "activecal_monte_carlo";
  // Progress of the long steps (may be empty): "Jacobians of the pool
  // poses" (without poses_csv), "identifications".
  StageProgress progress;
};

struct MonteCarloStudySummary {
  // CONVERGENCE when the comparison was made; FAILURE with message (one
  // line) otherwise.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  // What the program prints on stdout: the lattice's notes, the table of
  // the parameters and MonteCarloSummary::BriefReport; on a failure, what
  // was printed before it.
  std::string report;
  int num_poses = 0;              // of the design
  MonteCarloSummary monte_carlo;  // the comparison
  nlohmann::json json;            // the JSON report ("timing" varies)
  // "<program>: 1000 trials (0 failed), log det ratio ... within 2 std":
  // what --quiet prints.
  std::string result_line;
};

// `true_parameters`: the full parameter vector measured (the robot file's
// true values). Returns true (CONVERGENCE) when the comparison was made.
bool RunMonteCarloStudy(const RobotModel& model,
                        const Eigen::VectorXd& true_parameters,
                        const MonteCarloStudyOptions& options,
                        MonteCarloStudySummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_MONTE_CARLO_STUDY_H_
