// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/model_selection.h"

#include <glog/logging.h>

#include <Eigen/QR>
#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/estimation/registration_fit.h"
#include "activecal/residuals/jacobians.h"

namespace activecal {

constexpr const char* kModelSelectionMethodNames[] = {"none", "validation",
                                                      "cv", "auto"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(ModelSelectionMethod,
                                kModelSelectionMethodNames)

constexpr const char* kParameterRankingNames[] = {"significance", "jacobian"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(ParameterRanking, kParameterRankingNames)

constexpr const char* kSelectionRuleNames[] = {"min", "1se", "1se_most",
                                               "ftest"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(SelectionRule, kSelectionRuleNames)

bool ModelSelectionOptions::IsValid(std::string* error) const {
  std::string why;
  if (method == ModelSelectionMethod::kAuto) {
    why = "model selection 'auto' is resolved by the caller (Calibrate)";
  } else if (method == ModelSelectionMethod::kCrossValidation &&
             num_folds < 2) {
    why = "cross-validation needs at least 2 folds, got " +
          std::to_string(num_folds);
  } else if (!identification.IsValid(&why)) {
    why = "identification options: " + why;
  }
  if (why.empty()) return true;
  if (error) *error = why;
  return false;
}

std::vector<int> RankFreeParameters(const RobotModel& model,
                                    const Eigen::MatrixXd& jacobian,
                                    int* num_registration) {
  const std::vector<int> free = model.FreeParameterIndices();
  const int p = static_cast<int>(free.size());
  CHECK_EQ(jacobian.cols(), p);
  std::vector<int> order, links;
  for (int k = 0; k < p; ++k) {
    const int block = model.BlockOf(free[k]);
    if (block == 0 || model.is_marker_block(block)) {
      order.push_back(k);
    } else {
      links.push_back(k);
    }
  }
  if (num_registration) *num_registration = static_cast<int>(order.size());
  if (links.empty()) return order;
  auto unit = [&](int k) -> Eigen::VectorXd {
    const double n = jacobian.col(k).norm();
    return n > 0 ? Eigen::VectorXd(jacobian.col(k) / n)
                 : Eigen::VectorXd(Eigen::VectorXd::Zero(jacobian.rows()));
  };
  // An orthonormal basis of the registration columns, to project out.
  Eigen::MatrixXd reg(jacobian.rows(), order.size());
  for (size_t k = 0; k < order.size(); ++k) reg.col(k) = unit(order[k]);
  Eigen::MatrixXd q;
  if (!order.empty()) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(reg);
    q = qr.householderQ() *
        Eigen::MatrixXd::Identity(jacobian.rows(), order.size());
  }
  Eigen::MatrixXd rest(jacobian.rows(), links.size());
  for (size_t k = 0; k < links.size(); ++k) {
    Eigen::VectorXd c = unit(links[k]);
    if (q.size()) {
      for (int pass = 0; pass < 2; ++pass) c -= q * (q.transpose() * c);
    }
    rest.col(k) = c;
  }
  // Eigen's pivoting takes the largest remaining column norm, the first
  // one on a tie.
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(rest);
  const auto& perm = qr.colsPermutation().indices();
  for (int k = 0; k < perm.size(); ++k) order.push_back(links[perm[k]]);
  return order;
}

std::vector<int> RankBySignificance(const RobotModel& model,
                                    const Eigen::VectorXd& moved,
                                    const Eigen::VectorXd& standard_deviations,
                                    int* num_registration) {
  const std::vector<int> free = model.FreeParameterIndices();
  const int p = static_cast<int>(free.size());
  CHECK_EQ(moved.size(), p);
  CHECK_EQ(standard_deviations.size(), p);
  std::vector<int> order, links;
  for (int k = 0; k < p; ++k) {
    const int block = model.BlockOf(free[k]);
    (block == 0 || model.is_marker_block(block) ? order : links).push_back(k);
  }
  if (num_registration) *num_registration = static_cast<int>(order.size());
  auto t = [&](int k) {
    const double sd = standard_deviations[k];
    return sd > 0 ? std::abs(moved[k]) / sd
                  : std::numeric_limits<double>::infinity();
  };
  std::stable_sort(links.begin(), links.end(),
                   [&](int a, int b) { return t(a) > t(b); });
  order.insert(order.end(), links.begin(), links.end());
  return order;
}

namespace {

// The pose of each measurement (0-based, in order of first appearance):
// equal joint values, a distance by both poses. Returns the pose count.
int PoseIds(const std::vector<Measurement>& measurements,
            std::vector<int>* pose) {
  std::map<std::vector<double>, int> pose_of;
  pose->resize(measurements.size());
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    std::vector<double> key(m.joints.data(), m.joints.data() + m.joints.size());
    if (m.type == MeasurementType::kDistance) {
      key.push_back(std::numeric_limits<double>::infinity());
      key.insert(key.end(), m.joints2.data(),
                 m.joints2.data() + m.joints2.size());
    }
    auto it = pose_of.emplace(key, static_cast<int>(pose_of.size())).first;
    (*pose)[i] = it->second;
  }
  return static_cast<int>(pose_of.size());
}

}  // namespace

bool AssignPoseFolds(const std::vector<Measurement>& measurements,
                     int num_folds, uint64_t seed, std::vector<int>* fold,
                     int* num_poses, std::string* error) {
  std::vector<int> pose;
  const int n = PoseIds(measurements, &pose);
  if (num_poses) *num_poses = n;
  if (num_folds < 2 || n < num_folds) {
    if (error) {
      *error = std::to_string(num_folds) + " folds need at least " +
               std::to_string(std::max(2, num_folds)) +
               " distinct poses, the measurements have " + std::to_string(n);
    }
    return false;
  }
  Random random(seed);
  const std::vector<int64_t> shuffled = random.SampleWithoutReplacement(n, n);
  std::vector<int> fold_of_pose(n);
  for (int k = 0; k < n; ++k) fold_of_pose[shuffled[k]] = k % num_folds;
  fold->resize(measurements.size());
  for (size_t i = 0; i < measurements.size(); ++i) {
    (*fold)[i] = fold_of_pose[pose[i]];
  }
  return true;
}

namespace {

// The level of the F test of SelectionRule::kFTest.
constexpr double kFTestLevel = 0.01;

// The model with only the first `kept` ranked parameters free.
RobotModel Keep(const RobotModel& model, const std::vector<int>& free,
                const std::vector<int>& ranking, int kept) {
  RobotModel m = model;
  for (int i : free) m.SetFree(i, false);
  for (int k = 0; k < kept; ++k) m.SetFree(free[ranking[k]], true);
  return m;
}

// Squared residual norms of `measurements` at `parameters`.
bool SquaredNorms(const RobotModel& model, const Eigen::VectorXd& parameters,
                  const std::vector<Measurement>& measurements,
                  double rotation_weight, Eigen::VectorXd* squares) {
  Eigen::VectorXd norms;
  std::string error;
  if (!MeasurementErrors(model, parameters, measurements, rotation_weight,
                         &norms, &error)) {
    return false;
  }
  *squares = norms.cwiseAbs2();
  return squares->allFinite();
}

// sqrt(n * sample variance of v) / divisor: the standard error of
// sum(v) / divisor for n = v.size() independent terms.
double StandardErrorOfSum(const std::vector<double>& v, double divisor) {
  const int n = static_cast<int>(v.size());
  if (n < 2) return 0.0;
  double mean = 0.0;
  for (double x : v) mean += x;
  mean /= n;
  double ss = 0.0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(n * ss / (n - 1)) / divisor;
}

}  // namespace

void SelectModel(const RobotModel& model, const Eigen::VectorXd& start,
                 const std::vector<Measurement>& training,
                 const std::vector<Measurement>& validation,
                 const ModelSelectionOptions& options,
                 ModelSelectionSummary* summary) {
  CHECK(summary != nullptr);
  *summary = ModelSelectionSummary();
  std::string error;
  auto fail = [&](TerminationType type, const std::string& why) {
    summary->termination_type = type;
    summary->message = why;
  };
  if (!options.IsValid(&error)) {
    return fail(TerminationType::kUserFailure, error);
  }
  const double w = options.identification.rotation_weight_m_per_rad;
  Eigen::MatrixXd J;
  if (!StackedJacobian(model, start, training, w, &J, &error)) {
    return fail(TerminationType::kUserFailure, error);
  }
  const std::vector<int> free = model.FreeParameterIndices();
  const std::vector<std::string> names = model.FreeParameterNames();
  const int p = static_cast<int>(free.size());
  const std::vector<int> jacobian_ranking =
      RankFreeParameters(model, J, &summary->num_registration);
  if (options.method == ModelSelectionMethod::kNone) {
    for (int k : jacobian_ranking) summary->ranking.push_back(names[k]);
    summary->best_num_kept = p;
    summary->free = FreeSet(model);
    summary->termination_type = TerminationType::kConvergence;
    summary->message = "no model selection: every free parameter kept";
    return;
  }
  // Splits: 0 is the whole training set; 1..F the folds of a
  // cross-validation (training part, held-out part). held_index: each
  // held-out measurement's place among all held-out ones (the training
  // measurements with cv, the validation ones otherwise).
  std::vector<std::vector<Measurement>> split_train(1, training), split_test(1);
  std::vector<std::vector<int>> held_index(1);
  std::vector<int> held_pose;
  int num_held_poses = 0;
  if (options.method == ModelSelectionMethod::kCrossValidation) {
    std::vector<int> fold;
    if (!AssignPoseFolds(training, options.num_folds, options.seed, &fold,
                         &summary->num_poses, &error)) {
      return fail(TerminationType::kUserFailure, "cross-validation: " + error);
    }
    split_train.resize(options.num_folds + 1);
    split_test.resize(options.num_folds + 1);
    held_index.resize(options.num_folds + 1);
    for (size_t i = 0; i < training.size(); ++i) {
      for (int f = 0; f < options.num_folds; ++f) {
        (fold[i] == f ? split_test : split_train)[f + 1].push_back(training[i]);
      }
      held_index[fold[i] + 1].push_back(static_cast<int>(i));
    }
    summary->num_held_out = static_cast<int>(training.size());
    num_held_poses = PoseIds(training, &held_pose);
  } else {
    if (validation.empty()) {
      return fail(TerminationType::kUserFailure,
                  "model selection by validation needs validation "
                  "measurements");
    }
    for (size_t i = 0; i < validation.size(); ++i) {
      if (!CheckMeasurement(model, validation[i], &error)) {
        return fail(
            TerminationType::kUserFailure,
            "validation measurement " + std::to_string(i) + ": " + error);
      }
      held_index[0].push_back(static_cast<int>(i));
    }
    summary->num_held_out = static_cast<int>(validation.size());
    num_held_poses = PoseIds(validation, &held_pose);
  }
  const int num_splits = static_cast<int>(split_train.size());
  const int threads = ResolveNumThreads(options.num_threads);
  // Fits of the curve: no covariance, tolerances the RMS needs.
  IdentificationOptions fast = options.identification;
  fast.compute_covariance = false;
  fast.function_tolerance = std::max(fast.function_tolerance, 1e-9);
  fast.parameter_tolerance = std::max(fast.parameter_tolerance, 1e-9);
  fast.gradient_tolerance = std::max(fast.gradient_tolerance, 1e-12);
  // Each split's ranking.
  std::vector<std::vector<int>> rankings(num_splits, jacobian_ranking);
  std::vector<std::string> rank_errors(num_splits);
  if (options.ranking == ParameterRanking::kSignificance) {
    ParallelFor(num_splits, threads, [&](int64_t begin, int64_t end, int) {
      for (int64_t sp = begin; sp < end; ++sp) {
        IdentificationSummary all;
        IdentificationOptions ranked = fast;
        ranked.compute_covariance = true;
        Identify(model, split_train[sp], start, ranked, &all);
        if (all.termination_type != TerminationType::kConvergence) {
          // A fold too weak for every parameter keeps the Jacobian order;
          // the whole training set must rank.
          if (sp == 0) rank_errors[sp] = all.message;
          continue;
        }
        const Eigen::VectorXd moved = all.estimates - ExtractFree(model, start);
        rankings[sp] =
            RankBySignificance(model, moved, all.standard_deviations, nullptr);
      }
    });
    for (int sp = 0; sp < num_splits; ++sp) {
      if (rank_errors[sp].empty()) continue;
      return fail(TerminationType::kFailure,
                  std::string("model selection: the fit of every free "
                              "parameter, to rank them, failed") +
                      (sp ? " on fold " + std::to_string(sp) : "") + ": " +
                      rank_errors[sp]);
    }
  }
  for (int k : rankings[0]) summary->ranking.push_back(names[k]);
  const int first = std::max(1, summary->num_registration);
  const int num_points = p - first + 1;
  // Per (point, split): converged, training RMS and cost, the held-out
  // squared norms. Each split walks up the curve, every fit started from
  // the one before (the added parameter at its start value): the splits
  // run in parallel, the points of one split in order, so the result does
  // not depend on the thread count.
  const int num_tasks = num_points * num_splits;
  std::vector<char> ok(num_tasks, 0), fitted(num_tasks, 0);
  std::vector<double> train_rms(num_tasks, 0.0), train_cost(num_tasks, 0.0);
  std::vector<Eigen::VectorXd> held_squares(num_tasks);
  // kValidation: why the first refit of the registration to the
  // validation measurements failed (split 0 only, one thread writes it).
  std::string refit_error;
  std::mutex progress_mutex;
  int64_t splits_done = 0;
  ParallelFor(num_splits, threads, [&](int64_t begin, int64_t end, int) {
    for (int64_t sp = begin; sp < end; ++sp) {
      Eigen::VectorXd from = start;
      for (int point = 0; point < num_points; ++point) {
        const int task = point * num_splits + static_cast<int>(sp);
        const RobotModel m = Keep(model, free, rankings[sp], first + point);
        IdentificationSummary fit;
        Identify(m, split_train[sp], from, fast, &fit);
        if (fit.termination_type != TerminationType::kConvergence) {
          from = start;
          continue;
        }
        from = fit.parameters;
        fitted[task] = 1;
        train_rms[task] = fit.rms_m;
        train_cost[task] = 2.0 * fit.solver_summary.final_cost;
        bool good = true;
        if (sp > 0) {
          good = SquaredNorms(m, fit.parameters, split_test[sp], w,
                              &held_squares[task]);
        } else if (options.method == ModelSelectionMethod::kValidation) {
          if (options.register_held_out) {
            RegistrationFitSummary reg;
            FitRegistration(m, fit.parameters, validation, fast, &reg);
            good = reg.termination_type == TerminationType::kConvergence;
            if (!good && refit_error.empty()) refit_error = reg.message;
            if (good) {
              held_squares[task] =
                  reg.identification.residual_norms.cwiseAbs2();
            }
          } else {
            good = SquaredNorms(m, fit.parameters, validation, w,
                                &held_squares[task]);
          }
        }
        ok[task] = good;
      }
      if (options.progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        options.progress(++splits_done, num_splits);
      }
    }
  });
  // Per point: the held-out squared norms summed per held-out pose.
  const double num_held = summary->num_held_out;
  std::vector<std::vector<double>> pose_sums(num_points);
  int best_point = -1;
  double best = std::numeric_limits<double>::infinity();
  for (int point = 0; point < num_points; ++point) {
    ModelSelectionPoint pt;
    pt.num_kept = first + point;
    if (pt.num_kept > summary->num_registration) {
      pt.added = names[rankings[0][pt.num_kept - 1]];
    }
    pt.ok = true;
    std::vector<double>& sums = pose_sums[point];
    sums.assign(num_held_poses, 0.0);
    for (int sp = 0; sp < num_splits; ++sp) {
      const int task = point * num_splits + sp;
      pt.ok = pt.ok && ok[task];
      if (!pt.ok) break;
      const Eigen::VectorXd& sq = held_squares[task];
      for (int j = 0; j < sq.size(); ++j) {
        sums[held_pose[held_index[sp][j]]] += sq[j];
      }
    }
    pt.training_rms_m = train_rms[point * num_splits];
    pt.training_cost = train_cost[point * num_splits];
    if (pt.ok) {
      double sum = 0.0;
      for (double x : sums) sum += x;
      pt.held_out_rms_m = std::sqrt(sum / num_held);
      pt.held_out_se_m =
          pt.held_out_rms_m > 0
              ? StandardErrorOfSum(sums, num_held) / (2 * pt.held_out_rms_m)
              : 0.0;
      if (pt.held_out_rms_m < best) {
        best = pt.held_out_rms_m;
        best_point = point;
      }
    } else {
      pt.held_out_rms_m = std::numeric_limits<double>::quiet_NaN();
    }
    summary->curve.push_back(pt);
  }
  if (best_point < 0 && !refit_error.empty()) {
    return fail(TerminationType::kFailure,
                "model selection: the base and markers could not be "
                "refitted to the " +
                    std::to_string(validation.size()) +
                    " validation measurements: " + refit_error);
  }
  if (best_point < 0) {
    return fail(TerminationType::kFailure,
                "model selection: no parameter count could be fitted and "
                "validated (too few measurements in the folds?)");
  }
  summary->minimum_num_kept = first + best_point;
  // Paired by pose against the minimum.
  for (int point = 0; point < num_points; ++point) {
    ModelSelectionPoint& pt = summary->curve[point];
    if (!pt.ok) continue;
    std::vector<double> d(num_held_poses);
    double sum = 0.0;
    for (int k = 0; k < num_held_poses; ++k) {
      d[k] = pose_sums[point][k] - pose_sums[best_point][k];
      sum += d[k];
    }
    pt.excess_m2 = sum / num_held;
    pt.excess_se_m2 = StandardErrorOfSum(d, num_held);
    pt.within_one_se = pt.excess_m2 <= pt.excess_se_m2;
  }
  // The F test of each point against the fit of every parameter, on the
  // training rows.
  const ModelSelectionPoint& last = summary->curve.back();
  const bool last_fitted = fitted[(num_points - 1) * num_splits] != 0;
  int rows = 0;
  for (const Measurement& m : training) rows += m.dimension();
  const int dof = rows - p;
  for (int point = 0; point < num_points; ++point) {
    ModelSelectionPoint& pt = summary->curve[point];
    if (!last_fitted || !fitted[point * num_splits] || dof <= 0) continue;
    const int extra = p - pt.num_kept;
    if (extra == 0) {
      pt.f_test_p_value = 1.0;
      continue;
    }
    const double residual = last.training_cost / dof;
    const double f =
        residual > 0 ? std::max(0.0, pt.training_cost - last.training_cost) /
                           extra / residual
                     : std::numeric_limits<double>::infinity();
    pt.f_test_p_value =
        std::isfinite(f)
            ? boost::math::cdf(boost::math::complement(
                  boost::math::fisher_f_distribution<double>(extra, dof), f))
            : 0.0;
  }
  summary->rule = options.rule;
  int chosen = -1;
  switch (options.rule) {
    case SelectionRule::kMinimum:
      chosen = best_point;
      break;
    case SelectionRule::kFewestWithinOneSe:
    case SelectionRule::kMostWithinOneSe:
      for (int point = 0; point < num_points; ++point) {
        if (!summary->curve[point].within_one_se) continue;
        if (chosen < 0 || options.rule == SelectionRule::kMostWithinOneSe) {
          chosen = point;
        }
      }
      break;
    case SelectionRule::kFTest:
      if (!last_fitted) {
        return fail(TerminationType::kFailure,
                    "model selection: the F test needs the fit of every "
                    "free parameter on the training measurements, which "
                    "failed");
      }
      for (int point = 0; point < num_points && chosen < 0; ++point) {
        if (fitted[point * num_splits] &&
            summary->curve[point].f_test_p_value >= kFTestLevel) {
          chosen = point;
        }
      }
      break;
  }
  CHECK_GE(chosen, 0);
  summary->best_num_kept = first + chosen;
  const double chosen_rms = summary->curve[chosen].held_out_rms_m;
  for (int k = summary->best_num_kept; k < p; ++k) {
    summary->dropped.push_back(names[rankings[0][k]]);
  }
  summary->free =
      FreeSet(Keep(model, free, rankings[0], summary->best_num_kept));
  summary->termination_type = TerminationType::kConvergence;
  std::ostringstream msg;
  msg << "model selection (" << ModelSelectionMethodToString(options.method)
      << ", ranked by " << ParameterRankingToString(options.ranking)
      << ", rule " << SelectionRuleToString(options.rule)
      << "): " << summary->best_num_kept << " of " << p
      << " free parameters kept, held-out RMS " << chosen_rms << " m";
  if (summary->best_num_kept != summary->minimum_num_kept) {
    msg << " (the minimum, " << best << " m, at " << summary->minimum_num_kept
        << ")";
  }
  // Counts above the kept one that could not be tested are not shown to
  // predict worse: on few poses the folds' training parts are too small
  // for the larger models, and the choice falls on a smaller one by
  // default. Said, so that it is not read as evidence.
  std::vector<int> untested;
  for (const ModelSelectionPoint& pt : summary->curve) {
    if (!pt.ok && pt.num_kept > summary->best_num_kept) {
      untested.push_back(pt.num_kept);
    }
  }
  if (!untested.empty()) {
    msg << "; not tested (a fit failed"
        << (options.method == ModelSelectionMethod::kCrossValidation
                ? ", too few poses in a fold's training part?"
                : "")
        << "), so not compared: " << untested.size() << " larger count"
        << (untested.size() > 1 ? "s" : "") << " (";
    for (size_t k = 0; k < untested.size(); ++k) {
      msg << (k ? ", " : "") << untested[k];
    }
    msg << (options.method == ModelSelectionMethod::kCrossValidation
                ? "); more poses or fewer folds would test them"
                : ")");
  }
  summary->message = msg.str();
}

std::string ModelSelectionSummary::BriefReport() const {
  std::ostringstream out;
  out << message << "\n";
  if (curve.empty()) return out.str();
  out << "  kept  added                         training RMS (m)  held-out "
         "RMS (m)  +- SE (m)\n";
  for (const ModelSelectionPoint& pt : curve) {
    char line[200];
    std::string mark;
    if (pt.num_kept == best_num_kept) mark += "  <- kept";
    if (pt.num_kept == minimum_num_kept && best_num_kept != minimum_num_kept) {
      mark += "  <- minimum";
    }
    std::snprintf(
        line, sizeof(line), "  %4d  %-28s  %16.6g  %16.6g  %9.3g%s\n",
        pt.num_kept, pt.added.empty() ? "(registration)" : pt.added.c_str(),
        pt.training_rms_m, pt.held_out_rms_m, pt.held_out_se_m, mark.c_str());
    out << line;
  }
  if (!dropped.empty()) {
    out << "  held at their start values:";
    for (const std::string& d : dropped) out << " " << d;
    out << "\n";
  }
  return out.str();
}

}  // namespace activecal
