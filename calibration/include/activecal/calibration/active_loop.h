// The active calibration loop on a simulated robot: design a batch, measure
// it (simulated from the true parameters), identify from everything
// measured, re-design the next batch at the new estimate, until the
// predicted task RMS position error meets a target.
//
//   ActiveLoopOptions options;
//   options.sigma_m = 1e-4;
//   options.target_rms_m = 5e-5;
//   ActiveLoopSummary summary;
//   RunActiveLoop(model, truth, pool_joints, task_joints, options,
//                 select_batch, &summary);
//
// Every round linearises at the current estimate: the pool's and the task
// poses' Jacobians and the rows of the poses already measured. Which poses
// to measure next is the caller's BatchSelector (the selection library
// sits above this one): activecal_active passes a D-optimal first batch
// and task-optimal batches after it.
//
// Per round the summary records the poses measured so far, the predicted
// task RMS sigma sqrt(tr(W M^-1)) at the new estimate, the true task RMS
// error of the estimate (known in simulation: RMS over the task poses of
// |p(estimate) - p(true)|), and how far the estimate moved (the RMS over
// the task poses of the predicted point's change, m, and the largest change
// of a free parameter in its own unit).

#ifndef ACTIVECAL_CALIBRATION_ACTIVE_LOOP_H_
#define ACTIVECAL_CALIBRATION_ACTIVE_LOOP_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"

namespace activecal {

struct ActiveLoopOptions {
  double sigma_m = 1e-4;       // simulated noise per axis (m), > 0
  double target_rms_m = 5e-5;  // stop when the prediction meets it, > 0
  int first_batch = 12;        // poses of round 0
  int batch_size = 6;          // poses of each later round
  int max_rounds = 30;
  uint64_t seed = 1;    // noise of round r from StreamSeed(seed, r)
  int num_threads = 0;  // Jacobians; results do not depend on it
  // A round whose identification leaves residuals of standard deviation
  // s = sqrt(SSR / (rows - free)) above residual_ratio_limit * sigma_m is
  // flagged: the model does not explain the data (a wrong local minimum,
  // or an error the model lacks), so its predicted task RMS, which assumes
  // the estimate is near the truth, does not hold. When a flagged round
  // predicts the target the loop ends NO_CONVERGENCE, saying why, instead
  // of CONVERGENCE. <= 0: no check.
  double residual_ratio_limit = 2.0;

  bool IsValid(std::string* error) const;
};

// Chooses `num_poses` pool poses to measure next (pool indices, none of
// `measured`), given the pool's Jacobians, the task matrix W and the
// whitened rows of the poses measured so far, all at the current
// estimate. Returns false with a message on failure.
using BatchSelector = std::function<bool(
    int round, const CandidatePool& pool, const Eigen::MatrixXd& W,
    const RowMatrixXd& prior_rows, const std::vector<int64_t>& measured,
    int num_poses, std::vector<int64_t>* batch, std::string* error)>;

struct ActiveRound {
  int num_poses = 0;  // measured so far, this round's included
  std::vector<int64_t> batch;
  double predicted_task_rms_m = std::numeric_limits<double>::infinity();
  double true_task_rms_m = std::numeric_limits<double>::infinity();
  double parameter_change_task_rms_m = 0.0;
  double parameter_change_max_abs = 0.0;
  // s = sqrt(SSR / (rows - free)) of the identification, m (NaN while
  // rows <= free parameters), and whether it exceeds
  // residual_ratio_limit * sigma_m.
  double residual_sigma_m = std::numeric_limits<double>::quiet_NaN();
  bool residuals_exceed_noise = false;
};

struct ActiveLoopSummary {
  // CONVERGENCE: the target was met; NO_CONVERGENCE: max_rounds or the
  // pool ran out first, or the target was predicted by a round whose
  // residuals exceed the noise (the message says so); FAILURE: a batch or an
  // identification failed; USER_FAILURE: bad options or input.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  std::vector<ActiveRound> rounds;
  std::vector<int64_t> measured;         // pool indices, in measuring order
  Eigen::VectorXd estimate;              // full parameter vector
  double nominal_true_task_rms_m = 0.0;  // error of the starting model
  double seconds = 0.0;
};

// The loop. `model` holds the nominal values (the start) and the free
// parameters; `true_parameters` the simulated robot.
bool RunActiveLoop(const RobotModel& model,
                   const Eigen::VectorXd& true_parameters,
                   const Eigen::MatrixXd& pool_joints,
                   const Eigen::MatrixXd& task_joints,
                   const ActiveLoopOptions& options,
                   const BatchSelector& select_batch,
                   ActiveLoopSummary* summary);

// One round without selection: measure `design` (pool indices; simulated
// with options.sigma_m and the seed of round 0), identify from the nominal
// values, and report as a round (the one-shot designs the loop is
// compared with).
bool EvaluateOneShot(const RobotModel& model,
                     const Eigen::VectorXd& true_parameters,
                     const Eigen::MatrixXd& pool_joints,
                     const Eigen::MatrixXd& task_joints,
                     const std::vector<int64_t>& design,
                     const ActiveLoopOptions& options, ActiveRound* result,
                     std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_ACTIVE_LOOP_H_
