// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/learned_residual.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/estimation/model_selection.h"

namespace activecal {
namespace {

// The regression's rows: inputs, targets (robot base frame), marker, fold
// and pose of each position or pose measurement.
struct Rows {
  Eigen::MatrixXd inputs;   // N x num_inputs
  Eigen::MatrixXd targets;  // N x 3
  std::vector<int> marker, fold, pose;
  int num_poses = 0;
};

// Features of every row for one length scale, the bias column last:
// N x (D + 1).
Eigen::MatrixXd FeatureMatrix(const Eigen::MatrixXd& inputs,
                              const Eigen::MatrixXd& omega,
                              const Eigen::VectorXd& phases,
                              double length_scale) {
  const int d = static_cast<int>(phases.size());
  const double amplitude = std::sqrt(2.0 / d);
  Eigen::MatrixXd z(inputs.rows(), d + 1);
  z.leftCols(d).noalias() = inputs * omega.transpose() / length_scale;
  for (int i = 0; i < z.rows(); ++i) {
    for (int k = 0; k < d; ++k) {
      z(i, k) = amplitude * std::cos(z(i, k) + phases[k]);
    }
  }
  z.col(d).setOnes();
  return z;
}

// Normal equations of one (fold, marker) cell.
struct Cell {
  Eigen::MatrixXd gram;  // (D + 1)^2
  Eigen::MatrixXd rhs;   // (D + 1) x 3
  int count = 0;
  std::vector<int> rows;
};

// Solves for the weights ([W; b], (D + 1) x 3) of the cells whose fold is
// not excluded; zero when they hold no rows.
Eigen::MatrixXd Solve(const std::vector<Cell>& cells, int num_folds, int marker,
                      int num_markers, int exclude1, int exclude2,
                      double ridge) {
  const int size = static_cast<int>(cells[marker].gram.rows());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(size, size);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(size, 3);
  int n = 0;
  for (int f = 0; f < num_folds; ++f) {
    if (f == exclude1 || f == exclude2) continue;
    const Cell& c = cells[f * num_markers + marker];
    if (c.count == 0) continue;
    a += c.gram;
    b += c.rhs;
    n += c.count;
  }
  if (n == 0) return Eigen::MatrixXd::Zero(size, 3);
  a.diagonal().head(size - 1).array() += ridge * n;
  // The bias is not penalised; a tiny term keeps the system definite when
  // the features cannot tell it from a constant.
  a(size - 1, size - 1) += 1e-12 * n;
  return a.llt().solve(b);
}

struct ScaleResult {
  // Per ridge: each row's held-out squared error of the fit without its
  // fold; per ridge and outer fold: the inner CV's pooled squared error.
  std::vector<Eigen::VectorXd> outer;
  std::vector<Eigen::VectorXd> inner;  // [ridge](outer fold)
};

void CrossValidateScale(const Rows& rows, const Eigen::MatrixXd& omega,
                        const Eigen::VectorXd& phases, double length_scale,
                        const std::vector<double>& ridges, int num_folds,
                        int num_markers, ScaleResult* result) {
  const Eigen::MatrixXd z =
      FeatureMatrix(rows.inputs, omega, phases, length_scale);
  const int n = static_cast<int>(z.rows());
  std::vector<Cell> cells(num_folds * num_markers);
  for (int i = 0; i < n; ++i) {
    cells[rows.fold[i] * num_markers + rows.marker[i]].rows.push_back(i);
  }
  for (Cell& c : cells) {
    c.count = static_cast<int>(c.rows.size());
    const Eigen::MatrixXd zc = z(c.rows, Eigen::all);
    const Eigen::MatrixXd yc = rows.targets(c.rows, Eigen::all);
    c.gram.noalias() = zc.transpose() * zc;
    c.rhs.noalias() = zc.transpose() * yc;
  }
  // Squared errors of the rows of fold `f` predicted by `w` (marker m).
  auto errors = [&](int f, int m, const Eigen::MatrixXd& w,
                    Eigen::VectorXd* out, double* sum) {
    const Cell& c = cells[f * num_markers + m];
    if (c.count == 0) return;
    const Eigen::MatrixXd e =
        rows.targets(c.rows, Eigen::all) - z(c.rows, Eigen::all) * w;
    for (int r = 0; r < c.count; ++r) {
      const double s = e.row(r).squaredNorm();
      if (out) (*out)[c.rows[r]] = s;
      if (sum) *sum += s;
    }
  };
  result->outer.assign(ridges.size(), Eigen::VectorXd::Zero(n));
  result->inner.assign(ridges.size(), Eigen::VectorXd::Zero(num_folds));
  for (size_t r = 0; r < ridges.size(); ++r) {
    for (int m = 0; m < num_markers; ++m) {
      for (int o = 0; o < num_folds; ++o) {
        errors(o, m, Solve(cells, num_folds, m, num_markers, o, -1, ridges[r]),
               &result->outer[r], nullptr);
        for (int i = 0; i < num_folds; ++i) {
          if (i == o) continue;
          errors(i, m, Solve(cells, num_folds, m, num_markers, o, i, ridges[r]),
                 nullptr, &result->inner[r][o]);
        }
      }
    }
  }
}

// The fit on every row at one grid point: the correction's weights.
void FitAll(const Rows& rows, const Eigen::MatrixXd& omega,
            const Eigen::VectorXd& phases, double length_scale, double ridge,
            int num_markers, LearnedCorrection* c) {
  const Eigen::MatrixXd z =
      FeatureMatrix(rows.inputs, omega, phases, length_scale);
  const int d = static_cast<int>(phases.size());
  std::vector<Cell> cells(num_markers);
  for (int i = 0; i < z.rows(); ++i) cells[rows.marker[i]].rows.push_back(i);
  for (Cell& cell : cells) {
    cell.count = static_cast<int>(cell.rows.size());
    const Eigen::MatrixXd zc = z(cell.rows, Eigen::all);
    cell.gram.noalias() = zc.transpose() * zc;
    cell.rhs.noalias() = zc.transpose() * rows.targets(cell.rows, Eigen::all);
  }
  c->weights = Eigen::MatrixXd::Zero(d, 3 * num_markers);
  c->bias = Eigen::VectorXd::Zero(3 * num_markers);
  for (int m = 0; m < num_markers; ++m) {
    const Eigen::MatrixXd w = Solve(cells, 1, m, num_markers, -1, -1, ridge);
    c->weights.middleCols(3 * m, 3) = w.topRows(d);
    c->bias.segment(3 * m, 3) = w.row(d).transpose();
  }
  c->frequencies = omega / length_scale;
  c->phases = phases;
  c->length_scale = length_scale;
  c->ridge = ridge;
}

}  // namespace

constexpr const char* kLearnedResidualModeNames[] = {"off", "on", "auto"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(LearnedResidualMode, kLearnedResidualModeNames)

bool LearnedResidualOptions::IsValid(std::string* error) const {
  std::string why;
  auto positive = [](const std::vector<double>& v) {
    if (v.empty()) return false;
    for (double x : v) {
      if (!(x > 0) || !std::isfinite(x)) return false;
    }
    return true;
  };
  if (num_features < 1 || num_features > 5000) {
    why = "num_features must be in [1, 5000], got " +
          std::to_string(num_features);
  } else if (!positive(length_scales)) {
    why = "length_scales must be a non-empty list of finite values > 0";
  } else if (!positive(ridges)) {
    why = "ridges must be a non-empty list of finite values > 0";
  } else if (num_folds < 3) {
    why = "num_folds must be >= 3 (nested cross-validation), got " +
          std::to_string(num_folds);
  } else if (!(num_standard_errors >= 0) ||
             !std::isfinite(num_standard_errors)) {
    why = "num_standard_errors must be finite and >= 0";
  }
  if (why.empty()) return true;
  if (error) *error = why;
  return false;
}

void FitLearnedResidual(const RobotModel& model,
                        const Eigen::VectorXd& parameters,
                        const std::vector<Measurement>& measurements,
                        const LearnedResidualOptions& options,
                        LearnedResidualSummary* summary) {
  CHECK(summary != nullptr);
  const auto start = std::chrono::steady_clock::now();
  *summary = LearnedResidualSummary();
  summary->mode = options.mode;
  summary->num_standard_errors = options.num_standard_errors;
  auto fail = [summary](const std::string& why) {
    summary->termination_type = TerminationType::kUserFailure;
    summary->message = "learned residual: " + why;
  };
  std::string error;
  if (!options.IsValid(&error)) return fail(error);
  if (options.mode == LearnedResidualMode::kOff) {
    summary->termination_type = TerminationType::kConvergence;
    summary->message = "learned residual: off";
    return;
  }
  if (!model.Validate(&error) || !model.CheckParameters(parameters, &error)) {
    return fail(error);
  }
  // The rows.
  std::vector<Measurement> used;
  for (const Measurement& m : measurements) {
    // Distances and the rows of fixed points (their coordinates are
    // unknowns of the fit, not measured positions) are not regressed.
    if (m.type == MeasurementType::kDistance || m.involves_points()) {
      ++summary->num_skipped;
      continue;
    }
    if (!CheckMeasurement(model, m, &error)) return fail(error);
    used.push_back(m);
  }
  const int n = static_cast<int>(used.size());
  summary->num_measurements = n;
  const int num_markers = model.num_markers();
  LearnedCorrection& c = summary->correction;
  SetCorrectionInputs(model, &c);
  Rows rows;
  rows.inputs.resize(n, c.num_inputs());
  rows.targets.resize(n, 3);
  const Eigen::Matrix3d rb = BaseRotation(model, parameters);
  std::map<std::vector<double>, int> poses;
  for (int i = 0; i < n; ++i) {
    const Measurement& m = used[i];
    const Measurement p = PredictMeasurement(model, parameters, m);
    rows.inputs.row(i) = c.Inputs(m.joints).transpose();
    rows.targets.row(i) =
        (rb.transpose() * (m.position - p.position)).transpose();
    rows.marker.push_back(m.marker);
    std::vector<double> key(m.joints.data(), m.joints.data() + m.joints.size());
    rows.pose.push_back(
        poses.emplace(key, static_cast<int>(poses.size())).first->second);
  }
  rows.num_poses = static_cast<int>(poses.size());
  summary->num_poses = rows.num_poses;
  int num_poses = 0;
  if (!AssignPoseFolds(used, options.num_folds,
                       Random::StreamSeed(options.seed, 1), &rows.fold,
                       &num_poses, &error)) {
    return fail(error);
  }
  summary->num_folds = options.num_folds;

  // The random features: standard normal frequencies, uniform phases.
  const int d = options.num_features;
  Random random(Random::StreamSeed(options.seed, 0));
  Eigen::MatrixXd omega(d, c.num_inputs());
  Eigen::VectorXd phases(d);
  for (int k = 0; k < d; ++k) {
    for (int j = 0; j < omega.cols(); ++j) omega(k, j) = random.Gaussian();
    phases[k] = 2.0 * M_PI * random.Uniform();
  }

  const int num_scales = static_cast<int>(options.length_scales.size());
  const int num_ridges = static_cast<int>(options.ridges.size());
  std::vector<ScaleResult> results(num_scales);
  ParallelFor(num_scales, ResolveNumThreads(options.num_threads),
              [&](int64_t begin, int64_t end, int) {
                for (int64_t s = begin; s < end; ++s) {
                  CrossValidateScale(rows, omega, phases,
                                     options.length_scales[s], options.ridges,
                                     options.num_folds, num_markers,
                                     &results[s]);
                }
              });

  // The hyperparameters of the final fit: the smallest pooled held-out
  // error over the grid (every fold).
  int best_s = 0, best_r = 0;
  double best = std::numeric_limits<double>::infinity();
  for (int s = 0; s < num_scales; ++s) {
    for (int r = 0; r < num_ridges; ++r) {
      const double sse = results[s].outer[r].sum();
      summary->grid.push_back({options.length_scales[s], options.ridges[r],
                               std::sqrt(sse / std::max(1, n))});
      if (sse < best) {
        best = sse;
        best_s = s;
        best_r = r;
      }
    }
  }
  // Nested: each outer fold's rows predicted with the grid point its inner
  // CV (the other folds only) chose.
  Eigen::VectorXd nested(n);
  for (int o = 0; o < options.num_folds; ++o) {
    int fs = 0, fr = 0;
    double fbest = std::numeric_limits<double>::infinity();
    for (int s = 0; s < num_scales; ++s) {
      for (int r = 0; r < num_ridges; ++r) {
        if (results[s].inner[r][o] < fbest) {
          fbest = results[s].inner[r][o];
          fs = s;
          fr = r;
        }
      }
    }
    for (int i = 0; i < n; ++i) {
      if (rows.fold[i] == o) nested[i] = results[fs].outer[fr][i];
    }
  }
  const Eigen::VectorXd parametric = rows.targets.rowwise().squaredNorm();
  Eigen::VectorXd per_pose = Eigen::VectorXd::Zero(rows.num_poses);
  for (int i = 0; i < n; ++i)
    per_pose[rows.pose[i]] += parametric[i] - nested[i];
  const double total = per_pose.sum();
  const int p = rows.num_poses;
  const double mean = total / p;
  const double var =
      p > 1 ? (per_pose.array() - mean).square().sum() / (p - 1) : 0.0;
  summary->gain_m2 = total / n;
  summary->gain_se_m2 = std::sqrt(p * var) / n;
  summary->held_out_rms_parametric_m = std::sqrt(parametric.sum() / n);
  summary->held_out_rms_hybrid_m = std::sqrt(nested.sum() / n);

  summary->length_scale = options.length_scales[best_s];
  summary->ridge = options.ridges[best_r];
  FitAll(rows, omega, phases, summary->length_scale, summary->ridge,
         num_markers, &c);
  c.seed = options.seed;
  c.num_training = n;
  c.held_out_rms_parametric_m = summary->held_out_rms_parametric_m;
  c.held_out_rms_hybrid_m = summary->held_out_rms_hybrid_m;
  double hybrid = 0.0;
  for (int i = 0; i < n; ++i) {
    hybrid += (rows.targets.row(i).transpose() -
               c.Correction(used[i].joints, used[i].marker))
                  .squaredNorm();
  }
  summary->training_rms_parametric_m = summary->held_out_rms_parametric_m;
  summary->training_rms_hybrid_m = std::sqrt(hybrid / n);
  summary->kept =
      options.mode == LearnedResidualMode::kOn ||
      summary->gain_m2 > options.num_standard_errors * summary->gain_se_m2;
  summary->termination_type = TerminationType::kConvergence;
  summary->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  std::ostringstream msg;
  msg << "learned residual: " << (summary->kept ? "kept" : "not kept");
  summary->message = msg.str();
}

std::string LearnedResidualSummary::BriefReport() const {
  std::ostringstream out;
  char line[512];
  if (mode == LearnedResidualMode::kOff) return "";
  std::snprintf(
      line, sizeof(line),
      "learned residual (%s): %d random Fourier features on the joint "
      "angles, length scale %g, ridge %g per measurement (chosen by %d-fold "
      "CV by pose on %d measurements, %d poses%s)\n",
      LearnedResidualModeToString(mode), correction.num_features(),
      length_scale, ridge, num_folds, num_measurements, num_poses,
      num_skipped ? ", distances not used" : "");
  out << line;
  char rule[64];
  std::snprintf(rule, sizeof(rule), "%g SE", num_standard_errors);
  const std::string verdict =
      mode == LearnedResidualMode::kOn ? std::string("kept (on)")
      : kept ? "kept (gain > " + std::string(rule) + ")"
             : "not kept (gain <= " + std::string(rule) + ")";
  std::snprintf(line, sizeof(line),
                "  held out (nested CV): parametric %.4f mm, with the "
                "correction %.4f mm; gain %.4g mm^2, SE %.4g mm^2: %s\n",
                held_out_rms_parametric_m * 1e3, held_out_rms_hybrid_m * 1e3,
                gain_m2 * 1e6, gain_se_m2 * 1e6, verdict.c_str());
  out << line;
  std::snprintf(line, sizeof(line),
                "  training RMS %.4f mm -> %.4f mm with the correction; fit "
                "%.2f s\n",
                training_rms_parametric_m * 1e3, training_rms_hybrid_m * 1e3,
                seconds);
  out << line;
  return out.str();
}

}  // namespace activecal
