// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/active_loop.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <utility>

#include "activecal/calibration/pool_builder.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/measurement.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/residuals/jacobians.h"

namespace activecal {

double TaskRmsDistance(const RobotModel& model, const Eigen::VectorXd& a,
                       const Eigen::VectorXd& b,
                       const Eigen::MatrixXd& task_joints) {
  double sum = 0;
  for (Eigen::Index i = 0; i < task_joints.rows(); ++i) {
    const Eigen::VectorXd q = task_joints.row(i).transpose();
    sum +=
        (MeasuredPoint(model, a, q) - MeasuredPoint(model, b, q)).squaredNorm();
  }
  return std::sqrt(sum / std::max<Eigen::Index>(1, task_joints.rows()));
}

bool ActiveLoopOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (!(sigma_m > 0) || !std::isfinite(sigma_m))
    msg << "sigma_m must be > 0, got " << sigma_m;
  else if (!(target_rms_m > 0) || !std::isfinite(target_rms_m))
    msg << "target_rms_m must be > 0, got " << target_rms_m;
  else if (first_batch <= 0)
    msg << "first_batch must be > 0, got " << first_batch;
  else if (batch_size <= 0)
    msg << "batch_size must be > 0, got " << batch_size;
  else if (max_rounds <= 0)
    msg << "max_rounds must be > 0, got " << max_rounds;
  else if (std::isnan(residual_ratio_limit))
    msg << "residual_ratio_limit must be a number";
  if (msg.tellp() == 0) return true;
  if (error) *error = msg.str();
  return false;
}

namespace {

// W = mean J_x^T J_x of the task poses at `parameters`.
bool TaskMatrixAt(const RobotModel& model, const Eigen::VectorXd& parameters,
                  const Eigen::MatrixXd& task_joints, int threads,
                  Eigen::MatrixXd* W, std::string* error) {
  PoolJacobianOptions options;
  options.num_threads = threads;
  RowMatrixXd J;
  if (!PoolJacobians(model, parameters, task_joints, options, &J, error)) {
    return false;
  }
  *W = J.transpose() * J / static_cast<double>(task_joints.rows());
  return true;
}

// sigma sqrt(tr(W M^-1)) for the measured rows; +infinity when singular.
double PredictedRms(const Eigen::MatrixXd& W, const RowMatrixXd& rows,
                    double sigma) {
  const Eigen::MatrixXd M = rows.transpose() * rows;
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  if (llt.info() != Eigen::Success) {
    return std::numeric_limits<double>::infinity();
  }
  return sigma * std::sqrt(llt.solve(W).trace());
}

MeasureBatch MakeBatch(int round, int attempt,
                       const Eigen::MatrixXd& pool_joints,
                       const std::vector<int64_t>& poses,
                       const std::vector<uint32_t>& marker_masks = {}) {
  MeasureBatch batch;
  batch.round = round;
  batch.attempt = attempt;
  batch.poses = poses;
  batch.joints.resize(poses.size(), pool_joints.cols());
  for (size_t k = 0; k < poses.size(); ++k) {
    batch.joints.row(k) = pool_joints.row(poses[k]);
    if (!marker_masks.empty()) batch.markers.push_back(marker_masks[poses[k]]);
  }
  return batch;
}

// Identifies from `measurements` (`num_poses` poses) starting at `start`;
// fills the round's errors.
bool IdentifyRound(const RobotModel& model, const Eigen::MatrixXd& task_joints,
                   const ActiveLoopOptions& options,
                   const Eigen::VectorXd& start,
                   const std::vector<Measurement>& measurements, int num_poses,
                   Eigen::VectorXd* estimate, ActiveRound* round,
                   std::string* error) {
  IdentificationSummary identified;
  Identify(model, measurements, start, IdentificationOptions(), &identified);
  if (identified.termination_type == TerminationType::kFailure ||
      identified.termination_type == TerminationType::kUserFailure ||
      identified.parameters.size() != start.size()) {
    *error = "identification from " + std::to_string(measurements.size()) +
             " measurements: " + identified.message;
    return false;
  }
  *estimate = identified.parameters;
  Eigen::MatrixXd W;
  Eigen::MatrixXd J;
  if (!TaskMatrixAt(model, *estimate, task_joints, options.num_threads, &W,
                    error) ||
      !StackedJacobian(model, *estimate, measurements, 1.0, &J, error)) {
    return false;
  }
  round->num_poses = num_poses;
  round->predicted_task_rms_m = PredictedRms(W, J, options.sigma_m);
  round->true_task_rms_m =
      options.true_parameters.size() == model.num_parameters()
          ? TaskRmsDistance(model, *estimate, options.true_parameters,
                            task_joints)
          : std::numeric_limits<double>::quiet_NaN();
  round->parameter_change_task_rms_m =
      TaskRmsDistance(model, *estimate, start, task_joints);
  double change = 0;
  for (int i : model.FreeParameterIndices()) {
    change = std::max(change, std::abs((*estimate)[i] - start[i]));
  }
  round->parameter_change_max_abs = change;
  if (identified.degrees_of_freedom > 0) {
    round->residual_sigma_m = identified.sigma_m;
    round->residuals_exceed_noise =
        options.residual_ratio_limit > 0 &&
        identified.sigma_m > options.residual_ratio_limit * options.sigma_m;
  }
  return true;
}

// Checks an answer's measurements against the model and the pose.
bool CheckAnswer(const RobotModel& model, const PoseAnswer& answer,
                 std::string* error) {
  for (const Measurement& m : answer.measurements) {
    if (m.type == MeasurementType::kDistance) {
      *error = "a distance is not a measurement of one pose";
      return false;
    }
    if (m.marker < 0 || m.marker >= model.num_markers()) {
      *error = "marker " + std::to_string(m.marker + 1) + " of a model with " +
               std::to_string(model.num_markers());
      return false;
    }
    if (!CheckMeasurement(model, m, error)) return false;
  }
  return true;
}

// Whether a round ends the loop, and how.
bool RoundEnds(const ActiveRound& round, int r,
               const ActiveLoopOptions& options, TerminationType* type,
               std::string* message) {
  if (round.predicted_task_rms_m > options.target_rms_m) return false;
  std::ostringstream msg;
  if (round.residuals_exceed_noise) {
    msg << "the predicted task RMS " << round.predicted_task_rms_m
        << " m meets the target " << options.target_rms_m
        << " m, but the residual sigma " << round.residual_sigma_m << " m is "
        << round.residual_sigma_m / options.sigma_m << " times the noise "
        << options.sigma_m
        << " m: the model does not fit the measurements (a wrong local "
           "minimum or an error the model lacks), so the prediction does "
           "not hold";
    *type = TerminationType::kNoConvergence;
  } else {
    msg << "the predicted task RMS " << round.predicted_task_rms_m
        << " m meets the target " << options.target_rms_m << " m after "
        << r + 1 << " rounds, " << round.num_poses << " poses";
    *type = TerminationType::kConvergence;
  }
  *message = msg.str();
  return true;
}

bool CheckResume(const RobotModel& model, int64_t pool_size,
                 const ActiveLoopState& state, std::string* error) {
  std::ostringstream msg;
  if (state.estimate.size() != model.num_parameters()) {
    msg << "the estimate has " << state.estimate.size() << " values, the model "
        << model.num_parameters();
  } else if (state.round < 0 ||
             static_cast<size_t>(state.round) != state.rounds.size()) {
    msg << "round " << state.round << " with " << state.rounds.size()
        << " rounds recorded";
  } else {
    std::vector<char> seen(pool_size, 0);
    auto mark = [&](int64_t i, const char* what) {
      if (i < 0 || i >= pool_size) {
        msg << what << " pose " << i << " is outside the pool [0, " << pool_size
            << ")";
        return false;
      }
      if (seen[i]) {
        msg << what << " pose " << i << " is measured or excluded twice";
        return false;
      }
      seen[i] = 1;
      return true;
    };
    for (int64_t i : state.measured) {
      if (!mark(i, "measured")) break;
    }
    if (msg.tellp() == 0) {
      for (const ExcludedPose& e : state.excluded) {
        if (!mark(e.pose, "excluded")) break;
      }
    }
    size_t in_rounds = 0;
    for (const ActiveRound& r : state.rounds) in_rounds += r.batch.size();
    if (msg.tellp() == 0 && in_rounds != state.measured.size()) {
      msg << state.measured.size() << " poses measured, " << in_rounds
          << " in the rounds";
    }
    if (msg.tellp() == 0 && !state.measured.empty() &&
        state.measurements.empty()) {
      msg << "poses measured but no measurements";
    }
  }
  if (msg.tellp() == 0) return true;
  *error = "the state to resume from: " + msg.str();
  return false;
}

}  // namespace

SimulatedMeasurer::SimulatedMeasurer(const RobotModel& model,
                                     Eigen::VectorXd true_parameters,
                                     double sigma_m, uint64_t seed)
    : model_(model),
      truth_(std::move(true_parameters)),
      sigma_m_(sigma_m),
      seed_(seed) {}

bool SimulatedMeasurer::Measure(const MeasureBatch& batch, int k,
                                PoseAnswer* answer, std::string* error) {
  CHECK(k >= 0 && k < static_cast<int>(batch.poses.size()));
  if (batch.round != cached_round_ || batch.attempt != cached_attempt_ ||
      cached_first_.size() != batch.poses.size() + 1) {
    SimulationNoise noise;
    noise.position_m = sigma_m_;
    const uint64_t round_seed = Random::StreamSeed(seed_, batch.round);
    const uint64_t seed = batch.attempt == 0
                              ? round_seed
                              : Random::StreamSeed(round_seed, batch.attempt);
    // One measurement per pose (marker 0), or per marker named.
    std::vector<Measurement> plan;
    cached_first_.assign(1, 0);
    if (batch.markers.empty()) {
      plan = MeasurementPlan(batch.joints);
      for (size_t k = 0; k < batch.poses.size(); ++k) {
        cached_first_.push_back(k + 1);
      }
    } else {
      for (size_t k = 0; k < batch.poses.size(); ++k) {
        for (int marker = 0; marker < model_.num_markers() && marker < 32;
             ++marker) {
          if (!(batch.markers[k] & (1u << marker))) continue;
          Measurement m;
          m.joints = batch.joints.row(k).transpose();
          m.marker = marker;
          plan.push_back(std::move(m));
        }
        cached_first_.push_back(plan.size());
      }
    }
    if (!SimulateMeasurements(model_, truth_, plan, noise, seed, &cached_,
                              error)) {
      cached_round_ = cached_attempt_ = -1;
      return false;
    }
    cached_round_ = batch.round;
    cached_attempt_ = batch.attempt;
  }
  *answer = PoseAnswer();
  if (not_visible_ && not_visible_(batch.poses[k])) {
    answer->status = "not_visible";
    answer->message = "simulated occlusion";
    return true;
  }
  for (size_t m = cached_first_[k]; m < cached_first_[k + 1]; ++m) {
    answer->measurements.push_back(cached_[m]);
  }
  if (!answer->measured()) {
    answer->status = "not_visible";
    answer->message = "no marker named";
  }
  return true;
}

bool RunActiveLoop(const RobotModel& model, const Eigen::MatrixXd& pool_joints,
                   const Eigen::MatrixXd& task_joints,
                   const ActiveLoopOptions& options,
                   const BatchSelector& select_batch, Measurer* measurer,
                   const ActiveLoopState* resume, ActiveLoopSummary* summary) {
  CHECK(summary != nullptr);
  const auto start_time = std::chrono::steady_clock::now();
  *summary = ActiveLoopSummary();
  auto finish = [&](TerminationType type, const std::string& message) {
    summary->termination_type = type;
    summary->message = message;
    summary->seconds = std::chrono::duration<double>(
                           std::chrono::steady_clock::now() - start_time)
                           .count();
    return type == TerminationType::kConvergence ||
           type == TerminationType::kNoConvergence;
  };
  std::string error;
  if (!options.IsValid(&error)) {
    return finish(TerminationType::kUserFailure, error);
  }
  const bool truth_known =
      options.true_parameters.size() == model.num_parameters();
  if ((options.true_parameters.size() != 0 && !truth_known) ||
      task_joints.rows() == 0 || pool_joints.rows() == 0 ||
      measurer == nullptr) {
    return finish(TerminationType::kUserFailure,
                  "the pool, the task and a measurer must be given (and the "
                  "true parameters, if any, of the model's size)");
  }
  const int64_t pool_size = pool_joints.rows();
  if (resume != nullptr && !CheckResume(model, pool_size, *resume, &error)) {
    return finish(TerminationType::kUserFailure, error);
  }
  ActiveLoopState state;
  state.seed = options.seed;
  state.estimate = model.nominal;
  if (resume != nullptr) state = *resume;
  state.seed = options.seed;
  summary->nominal_true_task_rms_m =
      truth_known ? TaskRmsDistance(model, model.nominal,
                                    options.true_parameters, task_joints)
                  : std::numeric_limits<double>::quiet_NaN();
  // taken: measured or excluded, never designed again.
  std::vector<char> taken(pool_size, 0);
  for (int64_t i : state.measured) taken[i] = 1;
  for (const ExcludedPose& e : state.excluded) taken[e.pose] = 1;
  auto sync_summary = [&]() {
    summary->rounds = state.rounds;
    summary->measured = state.measured;
    summary->excluded = state.excluded;
    if (!state.rounds.empty()) summary->estimate = state.estimate;
  };
  sync_summary();
  if (!state.rounds.empty()) {
    // A resumed loop that had ended ends the same way.
    TerminationType type;
    std::string message;
    if (RoundEnds(state.rounds.back(), state.round - 1, options, &type,
                  &message)) {
      return finish(type, message);
    }
  }
  auto barred = [&](int64_t i) {
    return taken[i] != 0 || (options.pool_filter && !options.pool_filter(i));
  };
  // The pool's marker masks: a pose the filter bars (which may see no
  // marker) gets marker 0's rows, never designed.
  std::vector<uint32_t> pool_masks = options.marker_masks;
  if (!pool_masks.empty()) {
    if (static_cast<int64_t>(pool_masks.size()) != pool_size) {
      return finish(TerminationType::kUserFailure,
                    std::to_string(pool_masks.size()) + " marker masks for " +
                        std::to_string(pool_size) + " pool poses");
    }
    for (int64_t i = 0; i < pool_size; ++i) {
      if (pool_masks[i] != 0) continue;
      if (!options.pool_filter || options.pool_filter(i)) {
        return finish(TerminationType::kUserFailure,
                      "pool pose " + std::to_string(i) +
                          " sees no marker and is not filtered out");
      }
      pool_masks[i] = 1u;
    }
  }
  for (int r = state.round; r < options.max_rounds; ++r) {
    // Linearise at the current estimate.
    const Eigen::VectorXd& estimate = state.estimate;
    CandidatePoolOptions pool_options;
    pool_options.num_threads = options.num_threads;
    pool_options.marker_masks = pool_masks;
    CandidatePool pool;
    CandidatePoolSummary pool_summary;
    Eigen::MatrixXd W;
    RowMatrixXd prior(0, model.num_free());
    if (!BuildCandidatePool(model, estimate, pool_joints, pool_options, &pool,
                            &pool_summary)) {
      return finish(
          TerminationType::kFailure,
          "round " + std::to_string(r) + ": pool: " + pool_summary.message);
    }
    if (!TaskMatrixAt(model, estimate, task_joints, options.num_threads, &W,
                      &error) ||
        (!state.measurements.empty() &&
         !MeasuredInformationRows(model, estimate, state.measurements, 1.0,
                                  options.sigma_m, &prior, &error))) {
      return finish(TerminationType::kFailure,
                    "round " + std::to_string(r) + ": " + error);
    }
    const int want = r == 0 ? options.first_batch : options.batch_size;
    int64_t left = 0;  // poses that may still be designed
    for (int64_t i = 0; i < pool_size; ++i) left += !barred(i);
    auto ran_out = [&]() -> std::string {
      return !state.excluded.empty() || options.pool_filter
                 ? "every pool pose is measured or excluded"
                 : "every pool pose is measured";
    };
    if (left <= 0) return finish(TerminationType::kNoConvergence, ran_out());

    ActiveRound round;
    std::vector<Measurement> measured_now;  // this round's
    for (int attempt = 0;; ++attempt) {
      BatchRequest request;
      request.round = r;
      request.attempt = attempt;
      request.num_poses = static_cast<int>(std::min<int64_t>(
          want, static_cast<int64_t>(round.batch.size()) + left));
      request.fixed = round.batch;
      request.measured = state.measured;
      request.excluded = barred;
      std::vector<int64_t> batch;
      const std::string where =
          "round " + std::to_string(r) +
          (attempt > 0 ? " (repair " + std::to_string(attempt) + ")" : "");
      if (!select_batch(pool, W, prior, request, &batch, &error)) {
        return finish(TerminationType::kFailure,
                      where + ": selection: " + error);
      }
      // The new poses, in the selector's order; the fixed ones must be in.
      std::vector<char> in_batch(pool_size, 0);
      std::vector<int64_t> fresh;
      for (int64_t i : batch) {
        CHECK(i >= 0 && i < pool_size && !in_batch[i])
            << "the selector returned pose " << i
            << ", outside the pool or twice";
        in_batch[i] = 1;
        if (std::find(round.batch.begin(), round.batch.end(), i) !=
            round.batch.end()) {
          continue;
        }
        CHECK(!barred(i)) << "the selector returned pose " << i
                          << ", measured, excluded or filtered out";
        fresh.push_back(i);
      }
      for (int64_t f : round.batch) {
        CHECK(in_batch[f]) << "the selector dropped the fixed pose " << f;
      }
      const MeasureBatch to_measure =
          MakeBatch(r, attempt, pool_joints, fresh, options.marker_masks);
      int newly_excluded = 0;
      for (size_t k = 0; k < fresh.size(); ++k) {
        PoseAnswer answer;
        if (!measurer->Measure(to_measure, static_cast<int>(k), &answer,
                               &error) ||
            (answer.measured() && !CheckAnswer(model, answer, &error))) {
          return finish(
              TerminationType::kFailure,
              where + ": pose " + std::to_string(fresh[k]) + ": " + error);
        }
        --left;
        // A measured pose is fixed in the round's repairs (and taken after
        // the round); an excluded one is barred at once.
        if (answer.measured()) {
          round.batch.push_back(fresh[k]);
          measured_now.insert(measured_now.end(), answer.measurements.begin(),
                              answer.measurements.end());
        } else {
          ++newly_excluded;
          taken[fresh[k]] = 1;
          round.excluded.push_back(fresh[k]);
          ExcludedPose e;
          e.pose = fresh[k];
          e.round = r;
          e.status = answer.status;
          e.message = answer.message;
          state.excluded.push_back(e);
        }
      }
      if (newly_excluded == 0 || left <= 0 ||
          static_cast<int>(round.batch.size()) >= want) {
        break;
      }
    }
    for (int64_t i : round.batch) taken[i] = 1;
    if (round.batch.empty()) {
      sync_summary();
      return finish(TerminationType::kNoConvergence, ran_out());
    }
    std::vector<Measurement> measurements = state.measurements;
    measurements.insert(measurements.end(), measured_now.begin(),
                        measured_now.end());
    Eigen::VectorXd next;
    const int num_poses =
        static_cast<int>(state.measured.size() + round.batch.size());
    if (!IdentifyRound(model, task_joints, options, estimate, measurements,
                       num_poses, &next, &round, &error)) {
      sync_summary();
      return finish(TerminationType::kFailure,
                    "round " + std::to_string(r) + ": " + error);
    }
    state.measured.insert(state.measured.end(), round.batch.begin(),
                          round.batch.end());
    state.measurements = std::move(measurements);
    state.estimate = next;
    state.rounds.push_back(round);
    state.round = r + 1;
    sync_summary();
    if (options.round_callback && !options.round_callback(state, &error)) {
      return finish(TerminationType::kFailure,
                    "round " + std::to_string(r) + ": " + error);
    }
    TerminationType type;
    std::string message;
    if (RoundEnds(round, r, options, &type, &message)) {
      return finish(type, message);
    }
  }
  return finish(TerminationType::kNoConvergence,
                "max_rounds reached before the target");
}

bool RunActiveLoop(const RobotModel& model,
                   const Eigen::VectorXd& true_parameters,
                   const Eigen::MatrixXd& pool_joints,
                   const Eigen::MatrixXd& task_joints,
                   const ActiveLoopOptions& options,
                   const BatchSelector& select_batch,
                   ActiveLoopSummary* summary) {
  CHECK(summary != nullptr);
  if (true_parameters.size() != model.num_parameters()) {
    *summary = ActiveLoopSummary();
    summary->termination_type = TerminationType::kUserFailure;
    summary->message =
        "the true parameters, the pool and the task must be given";
    return false;
  }
  ActiveLoopOptions with_truth = options;
  with_truth.true_parameters = true_parameters;
  SimulatedMeasurer robot(model, true_parameters, options.sigma_m,
                          options.seed);
  return RunActiveLoop(model, pool_joints, task_joints, with_truth,
                       select_batch, &robot, nullptr, summary);
}

bool EvaluateOneShot(const RobotModel& model,
                     const Eigen::VectorXd& true_parameters,
                     const Eigen::MatrixXd& pool_joints,
                     const Eigen::MatrixXd& task_joints,
                     const std::vector<int64_t>& design,
                     const ActiveLoopOptions& options, ActiveRound* result,
                     std::string* error) {
  *result = ActiveRound();
  result->batch = design;
  if (true_parameters.size() != model.num_parameters()) {
    *error = "the true parameters must be given";
    return false;
  }
  ActiveLoopOptions with_truth = options;
  with_truth.true_parameters = true_parameters;
  SimulatedMeasurer robot(model, true_parameters, options.sigma_m,
                          options.seed);
  const MeasureBatch batch = MakeBatch(0, 0, pool_joints, design);
  std::vector<Measurement> measurements;
  for (size_t k = 0; k < design.size(); ++k) {
    PoseAnswer answer;
    if (!robot.Measure(batch, static_cast<int>(k), &answer, error)) {
      return false;
    }
    measurements.insert(measurements.end(), answer.measurements.begin(),
                        answer.measurements.end());
  }
  Eigen::VectorXd estimate;
  return IdentifyRound(model, task_joints, with_truth, model.nominal,
                       measurements, static_cast<int>(design.size()), &estimate,
                       result, error);
}

}  // namespace activecal
