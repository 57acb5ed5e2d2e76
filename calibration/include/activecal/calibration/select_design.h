// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The whole design step of activecal_select on a pool already built: the
// approximate design (for the starts and the certificate), the algorithm
// chosen (DesignAlgorithm) and the criterion (DesignCriterion), the search for
// the fewest poses meeting a target, the task criterion of the design and its
// certificate.
//
//   SelectDesignOptions options;
//   options.algorithm = DesignAlgorithm::kFedorov;
//   options.num_poses = 30;
//   SelectDesignSummary summary;
//   if (!SelectDesign(pool, TaskMatrix(pool), RowMatrixXd(0, p), options,
//                     &summary)) { ...summary.message... }
//
// The same composition, defaults and messages as the program, so that the
// program and the Python module give the same designs for the same seed.

#ifndef ACTIVECAL_CALIBRATION_SELECT_DESIGN_H_
#define ACTIVECAL_CALIBRATION_SELECT_DESIGN_H_

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/types.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/design.h"
#include "activecal/selection/target_size.h"
#include "activecal/selection/task_approximate.h"

namespace activecal {

// Pools of more than this many poses get kFedorovLargePoolRestarts
// Fedorov restarts by default (their restarts agree within 0.1%:
// docs/scaling.md).
inline constexpr int64_t kFedorovLargePool = 200000;
inline constexpr int kFedorovLargePoolRestarts = 8;

// The design algorithm: the paper's exchange-add-exchange, the best of
// random designs, Fedorov's exchange, DETMAX, the greedy design, or the
// approximate design rounded to its num_poses heaviest poses.
enum class DesignAlgorithm {
  kEae,
  kRandom,
  kFedorov,
  kDetmax,
  kGreedy,
  kApprox
};

// "eae", "random", "fedorov", "detmax", "greedy", "approx".
const char* DesignAlgorithmToString(DesignAlgorithm algorithm);
// The inverse of DesignAlgorithmToString; false on any other text.
bool StringToDesignAlgorithm(const std::string& text,
                             DesignAlgorithm* algorithm);
// StringToDesignAlgorithm, or false with *error "algorithm must be one of
// eae, random, fedorov, detmax, greedy, approx; got '<text>'" (the program
// prefixes "--").
bool ParseDesignAlgorithm(const std::string& text, DesignAlgorithm* algorithm,
                          std::string* error);

// The design criterion: D-optimal (det); D-optimal with eae scoring by SVD
// (svd); the least predicted RMS position error over the task (task_rms).
enum class DesignCriterion { kDet, kSvd, kTaskRms };

// "det", "svd", "task_rms".
const char* DesignCriterionToString(DesignCriterion criterion);
// The inverse of DesignCriterionToString, with "d" for kDet too; false on
// any other text.
bool StringToDesignCriterion(const std::string& text,
                             DesignCriterion* criterion);
// StringToDesignCriterion, or false with *error "criterion must be det (d),
// svd or task_rms, got '<text>'".
bool ParseDesignCriterion(const std::string& text, DesignCriterion* criterion,
                          std::string* error);

// Whether the algorithm reads a pool stored in single precision
// (SelectionPoolOptions::reads_float): fedorov or approx with a D
// criterion.
bool ReadsFloatPool(DesignAlgorithm algorithm, DesignCriterion criterion);

struct SelectDesignOptions {
  // With criterion kTaskRms: kFedorov, kGreedy or kApprox.
  DesignAlgorithm algorithm = DesignAlgorithm::kEae;
  DesignCriterion criterion = DesignCriterion::kDet;
  int num_poses = 30;  // ignored when target_rms_m is set
  // eae, fedorov, detmax, task fedorov: restarts; 0: the default policy
  // (ResolvedRestarts).
  int restarts = 0;
  uint64_t seed = 1;
  int num_threads = 0;
  // Certify the design (efficiency_lower_bound); no certificate for the
  // task criterion with a prior.
  bool certificate = true;
  // Tolerance of the approximate D design and of the approximate task
  // design (the task design's multiplicative updates are slow near the
  // optimum: 1e-2 by default).
  double approx_tolerance = 2e-3;
  double task_approx_tolerance = 1e-2;
  int64_t polish_pool_size = 20000;  // fedorov
  int initial_poses = 12;            // eae
  int random_designs = 5000;         // random
  double noise_m = 1e-4;             // sigma per coordinate (m)
  // If set: the fewest poses whose predicted task RMS is <= this (m).
  std::optional<double> target_rms_m;
  ProgressCallback approximate_progress;  // approximate D design rounds
  ProgressCallback restarts_progress;     // restarts of the algorithm

  bool task() const { return criterion == DesignCriterion::kTaskRms; }
  // One-line messages naming the options (the program prefixes "--").
  bool IsValid(std::string* error) const;
};

// The restarts the algorithm runs (0 for those without restarts: random,
// greedy): options.restarts if > 0, else the algorithm's default, fedorov
// kFedorovLargePoolRestarts above kFedorovLargePool poses; approx 1.
int ResolvedRestarts(const SelectDesignOptions& options, int64_t pool_size);

struct SelectDesignSummary {
  // That of the design (CONVERGENCE or NO_CONVERGENCE when usable);
  // USER_FAILURE: bad options; FAILURE: message says which step failed.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  DesignAlgorithm algorithm = DesignAlgorithm::kEae;  // as run
  bool task = false;                                  // the task criterion
  int restarts = 0;                                   // ResolvedRestarts
  // The design: pool indices, log det, task_criterion (prior included),
  // certificate.
  SelectionSummary selection;
  bool with_approx = false;  // the approximate D design was solved
  ApproximateDesignSummary approx;
  bool with_task_approx = false;  // the approximate task design was solved
  TaskApproximateSummary task_approx;
  bool with_target = false;  // options.target_rms_m was set
  TargetSizeSummary target;
  bool with_prior = false;  // prior rows were given
  double predicted_task_rms_m = 0;
  double approximate_seconds = 0;  // the approximate design solved
  double total_seconds = 0;

  bool IsSolutionUsable() const {
    return termination_type == TerminationType::kConvergence ||
           termination_type == TerminationType::kNoConvergence;
  }
  // The design's report, then the approximate designs' when solved.
  std::string BriefReport() const;
};

// W: the task matrix (TaskMatrix of the task poses' position pool); prior:
// whitened information rows of poses already measured (0 rows: none; only
// with the task criterion). Returns summary->IsSolutionUsable().
bool SelectDesign(const CandidatePool& pool, const Eigen::MatrixXd& W,
                  const RowMatrixXd& prior, const SelectDesignOptions& options,
                  SelectDesignSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SELECT_DESIGN_H_
