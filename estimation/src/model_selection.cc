#include "activecal/estimation/model_selection.h"

#include <glog/logging.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/estimation/registration_fit.h"

namespace activecal {

const char* ModelSelectionMethodName(ModelSelectionMethod method) {
  switch (method) {
    case ModelSelectionMethod::kNone:
      return "none";
    case ModelSelectionMethod::kValidation:
      return "validation";
    case ModelSelectionMethod::kCrossValidation:
      return "cv";
  }
  return "unknown";
}

bool ParseModelSelectionMethod(const std::string& name,
                               ModelSelectionMethod* method) {
  for (ModelSelectionMethod m :
       {ModelSelectionMethod::kNone, ModelSelectionMethod::kValidation,
        ModelSelectionMethod::kCrossValidation}) {
    if (name == ModelSelectionMethodName(m)) {
      *method = m;
      return true;
    }
  }
  return false;
}

const char* ParameterRankingName(ParameterRanking ranking) {
  return ranking == ParameterRanking::kSignificance ? "significance"
                                                    : "jacobian";
}

bool ParseParameterRanking(const std::string& name, ParameterRanking* ranking) {
  for (ParameterRanking r :
       {ParameterRanking::kSignificance, ParameterRanking::kJacobian}) {
    if (name == ParameterRankingName(r)) {
      *ranking = r;
      return true;
    }
  }
  return false;
}

bool ModelSelectionOptions::IsValid(std::string* error) const {
  std::string why;
  if (method == ModelSelectionMethod::kCrossValidation && num_folds < 2) {
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

bool AssignPoseFolds(const std::vector<Measurement>& measurements,
                     int num_folds, uint64_t seed, std::vector<int>* fold,
                     int* num_poses, std::string* error) {
  std::map<std::vector<double>, int> pose_of;
  std::vector<int> pose(measurements.size());
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    std::vector<double> key(m.joints.data(), m.joints.data() + m.joints.size());
    if (m.type == MeasurementType::kDistance) {
      key.push_back(std::numeric_limits<double>::infinity());
      key.insert(key.end(), m.joints2.data(),
                 m.joints2.data() + m.joints2.size());
    }
    auto it = pose_of.emplace(key, static_cast<int>(pose_of.size())).first;
    pose[i] = it->second;
  }
  const int n = static_cast<int>(pose_of.size());
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

// The model with only the first `kept` ranked parameters free.
RobotModel Keep(const RobotModel& model, const std::vector<int>& free,
                const std::vector<int>& ranking, int kept) {
  RobotModel m = model;
  for (int i : free) m.SetFree(i, false);
  for (int k = 0; k < kept; ++k) m.SetFree(free[ranking[k]], true);
  return m;
}

// Sum of squared residual norms of `measurements` at `parameters`.
bool SumSquares(const RobotModel& model, const Eigen::VectorXd& parameters,
                const std::vector<Measurement>& measurements,
                double rotation_weight, double* sum) {
  Eigen::VectorXd norms;
  std::string error;
  if (!MeasurementErrors(model, parameters, measurements, rotation_weight,
                         &norms, &error)) {
    return false;
  }
  *sum = norms.squaredNorm();
  return std::isfinite(*sum);
}

}  // namespace

void SelectModel(RobotModel* model, const Eigen::VectorXd& start,
                 const std::vector<Measurement>& training,
                 const std::vector<Measurement>& validation,
                 const ModelSelectionOptions& options,
                 ModelSelectionSummary* summary) {
  CHECK(model != nullptr);
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
  if (!StackedJacobian(*model, start, training, w, &J, &error)) {
    return fail(TerminationType::kUserFailure, error);
  }
  const std::vector<int> free = model->FreeParameterIndices();
  const std::vector<std::string> names = model->FreeParameterNames();
  const int p = static_cast<int>(free.size());
  const std::vector<int> jacobian_ranking =
      RankFreeParameters(*model, J, &summary->num_registration);
  if (options.method == ModelSelectionMethod::kNone) {
    for (int k : jacobian_ranking) summary->ranking.push_back(names[k]);
    summary->best_num_kept = p;
    summary->termination_type = TerminationType::kConvergence;
    summary->message = "no model selection: every free parameter kept";
    return;
  }
  // Splits: 0 is the whole training set; 1..F the folds of a
  // cross-validation (training part, held-out part).
  std::vector<std::vector<Measurement>> split_train(1, training), split_test(1);
  if (options.method == ModelSelectionMethod::kCrossValidation) {
    std::vector<int> fold;
    if (!AssignPoseFolds(training, options.num_folds, options.seed, &fold,
                         &summary->num_poses, &error)) {
      return fail(TerminationType::kUserFailure, "cross-validation: " + error);
    }
    split_train.resize(options.num_folds + 1);
    split_test.resize(options.num_folds + 1);
    for (size_t i = 0; i < training.size(); ++i) {
      for (int f = 0; f < options.num_folds; ++f) {
        (fold[i] == f ? split_test : split_train)[f + 1].push_back(training[i]);
      }
    }
    summary->num_held_out = static_cast<int>(training.size());
  } else {
    if (validation.empty()) {
      return fail(TerminationType::kUserFailure,
                  "model selection by validation needs validation "
                  "measurements");
    }
    for (size_t i = 0; i < validation.size(); ++i) {
      if (!CheckMeasurement(*model, validation[i], &error)) {
        return fail(
            TerminationType::kUserFailure,
            "validation measurement " + std::to_string(i) + ": " + error);
      }
    }
    summary->num_held_out = static_cast<int>(validation.size());
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
        Identify(*model, split_train[sp], start, ranked, &all);
        if (all.termination_type != TerminationType::kConvergence) {
          // A fold too weak for every parameter keeps the Jacobian order;
          // the whole training set must rank.
          if (sp == 0) rank_errors[sp] = all.message;
          continue;
        }
        const Eigen::VectorXd moved =
            all.estimates - ExtractFree(*model, start);
        rankings[sp] =
            RankBySignificance(*model, moved, all.standard_deviations, nullptr);
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
  // Per (point, split): converged, training RMS, held-out sum of squares.
  // Each split walks up the curve, every fit started from the one before
  // (the added parameter at its start value): the splits run in parallel,
  // the points of one split in order, so the result does not depend on the
  // thread count.
  const int num_tasks = num_points * num_splits;
  std::vector<char> ok(num_tasks, 0);
  std::vector<double> train_rms(num_tasks, 0.0), held_sum(num_tasks, 0.0);
  // kValidation: why the first refit of the registration to the
  // validation measurements failed (split 0 only, one thread writes it).
  std::string refit_error;
  ParallelFor(num_splits, threads, [&](int64_t begin, int64_t end, int) {
    for (int64_t sp = begin; sp < end; ++sp) {
      Eigen::VectorXd from = start;
      for (int point = 0; point < num_points; ++point) {
        const int task = point * num_splits + static_cast<int>(sp);
        const RobotModel m = Keep(*model, free, rankings[sp], first + point);
        IdentificationSummary fit;
        Identify(m, split_train[sp], from, fast, &fit);
        if (fit.termination_type != TerminationType::kConvergence) {
          from = start;
          continue;
        }
        from = fit.parameters;
        train_rms[task] = fit.rms_m;
        double sum = 0.0;
        bool good = true;
        if (sp > 0) {
          good = SumSquares(m, fit.parameters, split_test[sp], w, &sum);
        } else if (options.method == ModelSelectionMethod::kValidation) {
          if (options.register_held_out) {
            RegistrationFitSummary reg;
            FitRegistration(m, fit.parameters, validation, fast, &reg);
            good = reg.termination_type == TerminationType::kConvergence;
            if (!good && refit_error.empty()) refit_error = reg.message;
            sum = reg.rms_m * reg.rms_m * validation.size();
          } else {
            good = SumSquares(m, fit.parameters, validation, w, &sum);
          }
        }
        ok[task] = good;
        held_sum[task] = sum;
      }
    }
  });
  double best = std::numeric_limits<double>::infinity();
  for (int point = 0; point < num_points; ++point) {
    ModelSelectionPoint pt;
    pt.num_kept = first + point;
    if (pt.num_kept > summary->num_registration) {
      pt.added = names[rankings[0][pt.num_kept - 1]];
    }
    pt.ok = true;
    double sum = 0.0;
    for (int sp = 0; sp < num_splits; ++sp) {
      const int task = point * num_splits + sp;
      pt.ok = pt.ok && ok[task];
      sum += held_sum[task];
    }
    pt.training_rms_m = train_rms[point * num_splits];
    pt.held_out_rms_m = pt.ok ? std::sqrt(sum / summary->num_held_out)
                              : std::numeric_limits<double>::quiet_NaN();
    if (pt.ok && pt.held_out_rms_m < best) {
      best = pt.held_out_rms_m;
      summary->best_num_kept = pt.num_kept;
    }
    summary->curve.push_back(pt);
  }
  if (summary->best_num_kept == 0 && !refit_error.empty()) {
    return fail(TerminationType::kFailure,
                "model selection: the base and markers could not be "
                "refitted to the " +
                    std::to_string(validation.size()) +
                    " validation measurements: " + refit_error);
  }
  if (summary->best_num_kept == 0) {
    return fail(TerminationType::kFailure,
                "model selection: no parameter count could be fitted and "
                "validated (too few measurements in the folds?)");
  }
  for (int k = summary->best_num_kept; k < p; ++k) {
    summary->dropped.push_back(names[rankings[0][k]]);
  }
  *model = Keep(*model, free, rankings[0], summary->best_num_kept);
  summary->termination_type = TerminationType::kConvergence;
  std::ostringstream msg;
  msg << "model selection (" << ModelSelectionMethodName(options.method)
      << ", ranked by " << ParameterRankingName(options.ranking)
      << "): " << summary->best_num_kept << " of " << p
      << " free parameters kept, held-out RMS " << best << " m";
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
         "RMS (m)\n";
  for (const ModelSelectionPoint& pt : curve) {
    char line[160];
    std::snprintf(line, sizeof(line), "  %4d  %-28s  %16.6g  %16.6g%s\n",
                  pt.num_kept,
                  pt.added.empty() ? "(registration)" : pt.added.c_str(),
                  pt.training_rms_m, pt.held_out_rms_m,
                  pt.num_kept == best_num_kept ? "  <- kept" : "");
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
