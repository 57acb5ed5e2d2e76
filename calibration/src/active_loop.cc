#include "activecal/calibration/active_loop.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "activecal/core/measurement.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/calibration/pool_builder.h"

namespace activecal {

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

// RMS over the task poses of |p(a) - p(b)|.
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

std::vector<Measurement> Plan(const Eigen::MatrixXd& pool_joints,
                              const std::vector<int64_t>& poses) {
  Eigen::MatrixXd joints(poses.size(), pool_joints.cols());
  for (size_t k = 0; k < poses.size(); ++k) {
    joints.row(k) = pool_joints.row(poses[k]);
  }
  return MeasurementPlan(joints);
}

// Simulates `poses`, appends them to *measurements, identifies from
// `start`; fills the round's errors.
bool MeasureAndIdentify(const RobotModel& model, const Eigen::VectorXd& truth,
                        const Eigen::MatrixXd& pool_joints,
                        const Eigen::MatrixXd& task_joints,
                        const std::vector<int64_t>& poses, uint64_t seed,
                        const ActiveLoopOptions& options,
                        const Eigen::VectorXd& start,
                        std::vector<Measurement>* measurements,
                        Eigen::VectorXd* estimate, ActiveRound* round,
                        std::string* error) {
  std::vector<Measurement> simulated;
  SimulationNoise noise;
  noise.position_m = options.sigma_m;
  if (!SimulateMeasurements(model, truth, Plan(pool_joints, poses), noise, seed,
                            &simulated, error)) {
    return false;
  }
  measurements->insert(measurements->end(), simulated.begin(), simulated.end());
  IdentificationSummary identified;
  Identify(model, *measurements, start, IdentificationOptions(), &identified);
  if (identified.termination_type == TerminationType::kFailure ||
      identified.termination_type == TerminationType::kUserFailure ||
      identified.parameters.size() != start.size()) {
    *error = "identification from " + std::to_string(measurements->size()) +
             " measurements: " + identified.message;
    return false;
  }
  *estimate = identified.parameters;
  Eigen::MatrixXd W;
  Eigen::MatrixXd J;
  if (!TaskMatrixAt(model, *estimate, task_joints, options.num_threads, &W,
                    error) ||
      !StackedJacobian(model, *estimate, *measurements, 1.0, &J, error)) {
    return false;
  }
  round->num_poses = static_cast<int>(measurements->size());
  round->predicted_task_rms_m = PredictedRms(W, J, options.sigma_m);
  round->true_task_rms_m =
      TaskRmsDistance(model, *estimate, truth, task_joints);
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

}  // namespace

bool RunActiveLoop(const RobotModel& model,
                   const Eigen::VectorXd& true_parameters,
                   const Eigen::MatrixXd& pool_joints,
                   const Eigen::MatrixXd& task_joints,
                   const ActiveLoopOptions& options,
                   const BatchSelector& select_batch,
                   ActiveLoopSummary* summary) {
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
  if (true_parameters.size() != model.num_parameters() ||
      task_joints.rows() == 0 || pool_joints.rows() == 0) {
    return finish(TerminationType::kUserFailure,
                  "the true parameters, the pool and the task must be given");
  }
  Eigen::VectorXd estimate = model.nominal;
  summary->nominal_true_task_rms_m =
      TaskRmsDistance(model, estimate, true_parameters, task_joints);
  std::vector<Measurement> measurements;
  std::vector<char> taken(pool_joints.rows(), 0);
  for (int r = 0; r < options.max_rounds; ++r) {
    // Linearise at the current estimate.
    CandidatePoolOptions pool_options;
    pool_options.num_threads = options.num_threads;
    RobotModel pool_model = model;
    CandidatePool pool;
    CandidatePoolSummary pool_summary;
    Eigen::MatrixXd W;
    RowMatrixXd prior(0, model.num_free());
    if (!BuildCandidatePool(&pool_model, estimate, pool_joints, pool_options,
                            &pool, &pool_summary)) {
      return finish(
          TerminationType::kFailure,
          "round " + std::to_string(r) + ": pool: " + pool_summary.message);
    }
    if (!TaskMatrixAt(model, estimate, task_joints, options.num_threads, &W,
                      &error) ||
        (!measurements.empty() &&
         !MeasuredInformationRows(model, estimate, measurements, 1.0,
                                  options.sigma_m, &prior, &error))) {
      return finish(TerminationType::kFailure,
                    "round " + std::to_string(r) + ": " + error);
    }
    const int want = r == 0 ? options.first_batch : options.batch_size;
    const int64_t left = pool_joints.rows() - summary->measured.size();
    if (left <= 0) {
      return finish(TerminationType::kNoConvergence,
                    "every pool pose is measured");
    }
    std::vector<int64_t> batch;
    if (!select_batch(r, pool, W, prior, summary->measured,
                      static_cast<int>(std::min<int64_t>(want, left)), &batch,
                      &error)) {
      return finish(TerminationType::kFailure,
                    "round " + std::to_string(r) + ": selection: " + error);
    }
    for (int64_t i : batch) {
      CHECK(i >= 0 && i < pool_joints.rows() && !taken[i])
          << "the selector returned pose " << i
          << ", outside the pool or measured already";
      taken[i] = 1;
    }
    ActiveRound round;
    round.batch = batch;
    Eigen::VectorXd next;
    if (!MeasureAndIdentify(model, true_parameters, pool_joints, task_joints,
                            batch, Random::StreamSeed(options.seed, r), options,
                            estimate, &measurements, &next, &round, &error)) {
      return finish(TerminationType::kFailure,
                    "round " + std::to_string(r) + ": " + error);
    }
    summary->measured.insert(summary->measured.end(), batch.begin(),
                             batch.end());
    estimate = next;
    summary->estimate = estimate;
    summary->rounds.push_back(round);
    if (round.predicted_task_rms_m <= options.target_rms_m &&
        round.residuals_exceed_noise) {
      std::ostringstream msg;
      msg << "the predicted task RMS " << round.predicted_task_rms_m
          << " m meets the target " << options.target_rms_m
          << " m, but the residual sigma " << round.residual_sigma_m << " m is "
          << round.residual_sigma_m / options.sigma_m << " times the noise "
          << options.sigma_m
          << " m: the model does not fit the measurements (a wrong local "
             "minimum or an error the model lacks), so the prediction does "
             "not hold";
      return finish(TerminationType::kNoConvergence, msg.str());
    }
    if (round.predicted_task_rms_m <= options.target_rms_m) {
      std::ostringstream msg;
      msg << "the predicted task RMS " << round.predicted_task_rms_m
          << " m meets the target " << options.target_rms_m << " m after "
          << r + 1 << " rounds, " << round.num_poses << " poses";
      return finish(TerminationType::kConvergence, msg.str());
    }
  }
  return finish(TerminationType::kNoConvergence,
                "max_rounds reached before the target");
}

bool EvaluateOneShot(const RobotModel& model,
                     const Eigen::VectorXd& true_parameters,
                     const Eigen::MatrixXd& pool_joints,
                     const Eigen::MatrixXd& task_joints,
                     const std::vector<int64_t>& design,
                     const ActiveLoopOptions& options, ActiveRound* result,
                     std::string* error) {
  std::vector<Measurement> measurements;
  Eigen::VectorXd estimate;
  *result = ActiveRound();
  result->batch = design;
  return MeasureAndIdentify(model, true_parameters, pool_joints, task_joints,
                            design, Random::StreamSeed(options.seed, 0),
                            options, model.nominal, &measurements, &estimate,
                            result, error);
}

}  // namespace activecal
