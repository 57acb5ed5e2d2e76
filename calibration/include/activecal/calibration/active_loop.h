// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The active calibration loop: design a batch, measure it, identify from
// everything measured, re-design the next batch at the new estimate, until
// the predicted task RMS position error meets a target.
//
//   ActiveLoopOptions options;
//   options.sigma_m = 1e-4;
//   options.target_rms_m = 5e-5;
//   options.true_parameters = truth;  // optional: reports the true error
//   SimulatedMeasurer robot(model, truth, options.sigma_m, options.seed);
//   ActiveLoopSummary summary;
//   RunActiveLoop(model, pool_joints, task_joints, options, select_batch,
//                 &robot, /*resume=*/nullptr, &summary);
//
// Every round linearises at the current estimate: the pool's and the task
// poses' Jacobians and the rows of the poses already measured. Which poses
// to measure next is the caller's BatchSelector (the selection library
// sits beside this one's inputs): activecal_active passes a D-optimal first
// batch and task-optimal batches after it. The measurements come from a
// Measurer: a simulation (SimulatedMeasurer), a robot cell behind the
// driver protocol (docs/driver_protocol.md), or a session log replayed.
// What the measurer reports is identified from: its joint readings, not
// the commanded joints.
//
// A pose the measurer cannot measure (not visible, unreachable, an error
// at the cell) is excluded for the rest of the loop, and the round's design
// is repaired: the selector is asked again for the batch, with the poses
// of the round measured so far fixed and the excluded ones barred, until
// the batch is measured or the pool has no pose left.
//
// Per round the summary records the poses measured so far, the predicted
// task RMS sigma sqrt(tr(W M^-1)) at the new estimate, the true task RMS
// error of the estimate (when the truth is known, in simulation: RMS over
// the task poses of |p(estimate) - p(true)|), and how far the estimate
// moved (the RMS over the task poses of the predicted point's change, m,
// and the largest change of a free parameter in its own unit).
//
// The loop is a function of its inputs and of the measurer's answers: the
// state after each round (ActiveLoopState, handed to the round callback)
// is enough to continue it (`resume`), and continuing gives the same
// result, bit for bit, as running on, when the measurer answers the same.

#ifndef ACTIVECAL_CALIBRATION_ACTIVE_LOOP_H_
#define ACTIVECAL_CALIBRATION_ACTIVE_LOOP_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"

namespace activecal {

struct ActiveLoopState;

struct ActiveLoopOptions {
  double sigma_m = 1e-4;       // the device's noise per axis (m), > 0
  double target_rms_m = 5e-5;  // stop when the prediction meets it, > 0
  int first_batch = 12;        // poses of round 0
  int batch_size = 6;          // poses of each later round
  int max_rounds = 30;
  uint64_t seed = 1;    // recorded in the state; the selectors' and the
                        // simulation's seed (SimulatedMeasurer)
  int num_threads = 0;  // Jacobians; results do not depend on it
  // A round whose identification leaves residuals of standard deviation
  // s = sqrt(SSR / (rows - free)) above residual_ratio_limit * sigma_m is
  // flagged: the model does not explain the data (a wrong local minimum,
  // or an error the model lacks), so its predicted task RMS, which assumes
  // the estimate is near the truth, does not hold. When a flagged round
  // predicts the target the loop ends NO_CONVERGENCE, saying why, instead
  // of CONVERGENCE. <= 0: no check.
  double residual_ratio_limit = 2.0;
  // The true parameters (full vector) when they are known (simulation):
  // the rounds then report the true task RMS error. Empty: unknown (NaN).
  Eigen::VectorXd true_parameters;
  // Which pool poses may be designed at all (null: every pose), e.g. those
  // a cell's reachability and visibility test passes. Applied to every
  // batch and every repair.
  std::function<bool(int64_t pool_index)> pool_filter;
  // The markers each pool pose measures (one mask per pool pose, bit k:
  // marker k), e.g. the cell's targets seen (PoseVerdict::targets_seen):
  // the pool's blocks then hold only those markers' rows
  // (CandidatePoolOptions::marker_masks) and each MeasureBatch names them.
  // A zero mask only for a pose pool_filter bars. Empty: every pose's
  // design rows are marker 0's, and the measurer is not told.
  std::vector<uint32_t> marker_masks;
  // Called after every round with the loop's state (also after a resumed
  // round); false ends the loop FAILURE with *error (a session that cannot
  // write its state stops the loop instead of measuring on unrecorded).
  std::function<bool(const ActiveLoopState& state, std::string* error)>
      round_callback;

  bool IsValid(std::string* error) const;
};

// What the loop asks the selector for. The batch returned holds
// `num_poses` pool indices: every pose of `fixed`, the others new and not
// `excluded`.
struct BatchRequest {
  int round = 0;
  // 0: the round's design; > 0: a repair, after poses of the round could
  // not be measured (then `fixed` holds those of the round measured).
  int attempt = 0;
  int num_poses = 0;
  std::vector<int64_t> fixed;
  // Measured in the earlier rounds, in measuring order.
  std::vector<int64_t> measured;
  // The poses never to select: measured already, excluded by the measurer,
  // or refused by the pool filter. Never true for a fixed pose.
  std::function<bool(int64_t pool_index)> excluded;
};

// Chooses a batch given the pool's Jacobians, the task matrix W and the
// whitened rows of the poses measured in earlier rounds, all at the current
// estimate. Returns false with a message on failure.
using BatchSelector = std::function<bool(
    const CandidatePool& pool, const Eigen::MatrixXd& W,
    const RowMatrixXd& prior_rows, const BatchRequest& request,
    std::vector<int64_t>* batch, std::string* error)>;

// The batch being measured: its poses and the commanded joints.
struct MeasureBatch {
  int round = 0;
  int attempt = 0;             // as BatchRequest::attempt
  std::vector<int64_t> poses;  // pool indices
  Eigen::MatrixXd joints;      // one row per pose, commanded (rad, m)
  // The markers to measure at each pose (bit k: marker k), from
  // ActiveLoopOptions::marker_masks; empty: not said.
  std::vector<uint32_t> markers;
};

// The answer for one pose.
struct PoseAnswer {
  // One measurement per marker seen, with the joints read at the pose;
  // empty: not measured.
  std::vector<Measurement> measurements;
  // Not measured: why, in the driver protocol's words ("not_visible",
  // "unreachable", "error"), and what the cell said.
  std::string status = "ok";
  std::string message;

  bool measured() const { return !measurements.empty(); }
};

// The source of measurements. The loop asks for every pose of a batch in
// order, once per loop (an excluded pose is never asked again).
class Measurer {
 public:
  virtual ~Measurer() = default;
  // Measures pose k of `batch`. A pose that cannot be measured is answered
  // (true) with no measurements; false is a failure that ends the loop
  // (the cell stopped answering, answered garbage): *error says what.
  virtual bool Measure(const MeasureBatch& batch, int k, PoseAnswer* answer,
                       std::string* error) = 0;
};

// The simulated robot: the measured point from the true parameters plus
// Gaussian noise of sigma_m per axis, the joints exactly as commanded: of
// marker 0, or of each marker the batch names (MeasureBatch::markers). The
// noise of a batch is drawn for the whole batch from the stream
// StreamSeed(seed, round) (a repair's from StreamSeed of that and its
// attempt), so a pose's noise does not depend on which others are asked.
class SimulatedMeasurer : public Measurer {
 public:
  SimulatedMeasurer(const RobotModel& model, Eigen::VectorXd true_parameters,
                    double sigma_m, uint64_t seed);
  // Poses (pool indices) answered "not_visible" (tests; null: none).
  void set_not_visible(std::function<bool(int64_t pool_index)> not_visible) {
    not_visible_ = std::move(not_visible);
  }
  bool Measure(const MeasureBatch& batch, int k, PoseAnswer* answer,
               std::string* error) override;

 private:
  RobotModel model_;
  Eigen::VectorXd truth_;
  double sigma_m_;
  uint64_t seed_;
  std::function<bool(int64_t)> not_visible_;
  int cached_round_ = -1, cached_attempt_ = -1;
  std::vector<Measurement> cached_;
  std::vector<size_t> cached_first_;  // pose k's: [first[k], first[k + 1])
};

struct ActiveRound {
  int num_poses = 0;           // measured so far, this round's included
  std::vector<int64_t> batch;  // the round's poses measured, in order
  // The round's poses the measurer could not measure, in order.
  std::vector<int64_t> excluded;
  double predicted_task_rms_m = std::numeric_limits<double>::infinity();
  // NaN when the truth is not known.
  double true_task_rms_m = std::numeric_limits<double>::infinity();
  double parameter_change_task_rms_m = 0.0;
  double parameter_change_max_abs = 0.0;
  // s = sqrt(SSR / (rows - free)) of the identification, m (NaN while
  // rows <= free parameters), and whether it exceeds
  // residual_ratio_limit * sigma_m.
  double residual_sigma_m = std::numeric_limits<double>::quiet_NaN();
  bool residuals_exceed_noise = false;
};

// A pose the measurer could not measure.
struct ExcludedPose {
  int64_t pose = -1;  // pool index
  int round = 0;
  std::string status;  // "not_visible", "unreachable", "error"
  std::string message;
};

// Everything the loop carries from one round to the next.
struct ActiveLoopState {
  int round = 0;  // rounds completed; the next round's number
  uint64_t seed = 1;
  Eigen::VectorXd estimate;  // full parameter vector (the nominal at 0)
  std::vector<ActiveRound> rounds;
  std::vector<int64_t> measured;  // pool indices, in measuring order
  // What is identified from, in measuring order (one per marker seen).
  std::vector<Measurement> measurements;
  std::vector<ExcludedPose> excluded;
};

struct ActiveLoopSummary {
  // CONVERGENCE: the target was met; NO_CONVERGENCE: max_rounds or the
  // pool ran out first, or the target was predicted by a round whose
  // residuals exceed the noise (the message says so); FAILURE: a batch, a
  // measurement or an identification failed; USER_FAILURE: bad options or
  // input.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  std::vector<ActiveRound> rounds;
  std::vector<int64_t> measured;  // pool indices, in measuring order
  std::vector<ExcludedPose> excluded;
  Eigen::VectorXd estimate;  // full parameter vector
  // Error of the starting model (NaN when the truth is not known).
  double nominal_true_task_rms_m = 0.0;
  double seconds = 0.0;
};

// The loop. `model` holds the nominal values (the start) and the free
// parameters. `resume` (may be null) continues a loop from the state a
// round callback received (with the same model, pools and options).
bool RunActiveLoop(const RobotModel& model, const Eigen::MatrixXd& pool_joints,
                   const Eigen::MatrixXd& task_joints,
                   const ActiveLoopOptions& options,
                   const BatchSelector& select_batch, Measurer* measurer,
                   const ActiveLoopState* resume, ActiveLoopSummary* summary);

// The loop on a simulated robot: SimulatedMeasurer(model, true_parameters,
// options.sigma_m, options.seed), the truth reported.
bool RunActiveLoop(const RobotModel& model,
                   const Eigen::VectorXd& true_parameters,
                   const Eigen::MatrixXd& pool_joints,
                   const Eigen::MatrixXd& task_joints,
                   const ActiveLoopOptions& options,
                   const BatchSelector& select_batch,
                   ActiveLoopSummary* summary);

// RMS over the task poses (rows of task_joints) of |p(a) - p(b)|, the
// measured point of the first marker at the full parameter vectors a and b
// (m): the true task error when b is the truth.
double TaskRmsDistance(const RobotModel& model, const Eigen::VectorXd& a,
                       const Eigen::VectorXd& b,
                       const Eigen::MatrixXd& task_joints);

// One round without selection: measure `design` (pool indices; simulated
// with options.sigma_m and the stream of round 0), identify from the
// nominal values, and report as a round (the one-shot designs the loop is
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
