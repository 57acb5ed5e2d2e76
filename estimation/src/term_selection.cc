// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/term_selection.h"

#include <glog/logging.h>

#include <cmath>
#include <map>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/estimation/model_selection.h"
#include "activecal/residuals/joint_error_jacobian.h"

namespace activecal {
namespace {

// Pose ids: equal joint values, equal id (in order of first appearance).
int PoseIdsOf(const std::vector<Measurement>& measurements,
              std::vector<int>* ids) {
  std::map<std::vector<double>, int> seen;
  ids->clear();
  for (const Measurement& m : measurements) {
    std::vector<double> key(m.joints.data(), m.joints.data() + m.joints.size());
    auto it = seen.emplace(key, static_cast<int>(seen.size())).first;
    ids->push_back(it->second);
  }
  return static_cast<int>(seen.size());
}

struct CvResult {
  bool ok = false;
  std::string message;
  Eigen::VectorXd squared;  // held-out squared norm per training measurement
  double training_rms_m = 0.0;
};

}  // namespace

bool TermSelectionOptions::IsValid(std::string* error) const {
  std::string why;
  if (num_folds < 2) {
    why = "num_folds must be >= 2";
  } else if (!(num_standard_errors >= 0) ||
             !std::isfinite(num_standard_errors)) {
    why = "num_standard_errors must be finite and >= 0";
  } else if (!identification.IsValid(&why)) {
    why = "identification: " + why;
  }
  if (why.empty()) return true;
  if (error) *error = why;
  return false;
}

void SelectTerms(const RobotModel& model, const Eigen::VectorXd& start,
                 const std::vector<Measurement>& training,
                 const std::vector<TermFamily>& families,
                 const TermSelectionOptions& options,
                 TermSelectionSummary* summary) {
  CHECK(summary != nullptr);
  *summary = TermSelectionSummary();
  summary->num_standard_errors = options.num_standard_errors;
  auto fail = [summary](TerminationType type, const std::string& why) {
    summary->termination_type = type;
    summary->message = why;
  };
  std::string error;
  if (!options.IsValid(&error)) {
    return fail(TerminationType::kUserFailure, "term selection: " + error);
  }
  // Every family together, pruned to what the training poses separate.
  JointErrorModel all;
  std::vector<int> family_of;
  for (size_t f = 0; f < families.size(); ++f) {
    all.Append(families[f].terms);
    family_of.insert(family_of.end(), families[f].terms.size(),
                     static_cast<int>(f));
  }
  all.values.setZero(all.size());
  if (!CheckJointErrorInputs(model, all, training, &error)) {
    return fail(TerminationType::kUserFailure, "term selection: " + error);
  }
  std::vector<int> keep;
  if (!all.empty()) {
    const std::vector<Eigen::VectorXd> features =
        MeasurementTermFeatures(model, start, all, training);
    Eigen::MatrixXd J;
    if (!JointErrorJacobian(model, start, all, training, features,
                            options.identification.rotation_weight_m_per_rad,
                            &J, nullptr, &error)) {
      return fail(TerminationType::kUserFailure, "term selection: " + error);
    }
    keep =
        IdentifiableTerms(model, all, J, options.identification.rank_tolerance,
                          &summary->dropped_terms);
  }
  // The terms of a set of families (kept terms only).
  auto terms_of = [&](const std::vector<int>& fams) {
    std::vector<int> subset;
    for (int t : keep) {
      for (int f : fams) {
        if (family_of[t] == f) subset.push_back(t);
      }
    }
    JointErrorModel out = all.Subset(subset);
    out.values.setZero(out.size());
    return out;
  };

  std::vector<int> fold;
  if (!AssignPoseFolds(training, options.num_folds, options.seed, &fold,
                       &summary->num_poses, &error)) {
    return fail(TerminationType::kUserFailure,
                "term selection: cross-validation: " + error);
  }
  std::vector<int> pose;
  const int num_poses = PoseIdsOf(training, &pose);
  const int n = static_cast<int>(training.size());
  summary->num_held_out = n;
  IdentificationOptions fit = options.identification;
  fit.compute_covariance = false;
  fit.function_tolerance = std::max(fit.function_tolerance, 1e-12);
  fit.parameter_tolerance = std::max(fit.parameter_tolerance, 1e-10);

  auto cross_validate = [&](const JointErrorModel& terms) {
    CvResult result;
    result.squared = Eigen::VectorXd::Zero(n);
    std::vector<std::string> messages(options.num_folds + 1);
    std::vector<char> ok(options.num_folds + 1, 0);
    std::vector<Eigen::VectorXd> held(options.num_folds);
    double training_rms = 0.0;  // written by the last split only
    IdentificationOptions o = fit;
    o.joint_errors = terms;
    ParallelFor(
        options.num_folds + 1, options.num_threads,
        [&](int64_t begin, int64_t end, int) {
          for (int64_t s = begin; s < end; ++s) {
            std::vector<Measurement> train, test;
            for (int i = 0; i < n; ++i) {
              if (s == options.num_folds || fold[i] != s) {
                train.push_back(training[i]);
              } else {
                test.push_back(training[i]);
              }
            }
            IdentificationSummary id;
            Identify(model, train, start, o, &id);
            if (id.termination_type != TerminationType::kConvergence) {
              messages[s] = id.message;
              continue;
            }
            if (s == options.num_folds) {
              training_rms = id.rms_m;
              ok[s] = 1;
              continue;
            }
            std::string why;
            const std::vector<Eigen::VectorXd> features =
                terms.empty()
                    ? std::vector<Eigen::VectorXd>(test.size())
                    : MeasurementTermFeatures(model, start, terms, test);
            if (!JointErrorResidualNorms(
                    model, id.parameters, id.joint_errors, test, features,
                    o.rotation_weight_m_per_rad, &held[s], &why)) {
              messages[s] = why;
              continue;
            }
            ok[s] = 1;
          }
        });
    result.ok = true;
    for (int s = 0; s <= options.num_folds; ++s) {
      if (!ok[s]) {
        result.ok = false;
        result.message = (s == options.num_folds
                              ? std::string("the fit of every training pose")
                              : "fold " + std::to_string(s + 1)) +
                         ": " + messages[s];
        return result;
      }
    }
    result.training_rms_m = training_rms;
    std::vector<int> next(options.num_folds, 0);
    for (int i = 0; i < n; ++i) {
      const double e = held[fold[i]][next[fold[i]]++];
      result.squared[i] = e * e;
    }
    return result;
  };

  auto add_candidate = [&](const std::vector<int>& fams, int extends,
                           CvResult* out) {
    TermCandidate c;
    c.families = fams;
    c.name = "geometric";
    for (int f : fams) c.name += " + " + families[f].name;
    const JointErrorModel terms = terms_of(fams);
    c.num_terms = terms.size();
    *out = cross_validate(terms);
    c.ok = out->ok;
    c.extends = extends;
    if (out->ok) {
      const double mse = out->squared.sum() / n;
      c.held_out_rms_m = std::sqrt(mse);
      c.training_rms_m = out->training_rms_m;
      Eigen::VectorXd per_pose = Eigen::VectorXd::Zero(num_poses);
      for (int i = 0; i < n; ++i) per_pose[pose[i]] += out->squared[i];
      const double var = (per_pose.array() - per_pose.mean()).square().sum() /
                         std::max(1, num_poses - 1);
      const double se_mse = std::sqrt(num_poses * var) / n;
      c.held_out_se_m =
          c.held_out_rms_m > 0 ? se_mse / (2 * c.held_out_rms_m) : 0.0;
    }
    summary->candidates.push_back(c);
  };
  // The paired gain of candidate b over candidate a.
  auto paired_gain = [&](const CvResult& a, const CvResult& b, double* gain,
                         double* se) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(num_poses);
    for (int i = 0; i < n; ++i) d[pose[i]] += a.squared[i] - b.squared[i];
    *gain = d.sum() / n;
    const double var =
        (d.array() - d.mean()).square().sum() / std::max(1, num_poses - 1);
    *se = std::sqrt(num_poses * var) / n;
  };

  std::vector<int> current;
  CvResult current_result;
  add_candidate(current, -1, &current_result);
  if (!current_result.ok) {
    return fail(
        TerminationType::kFailure,
        "term selection: the geometric model: " + current_result.message);
  }
  int current_index = 0;
  for (;;) {
    int best = -1, best_candidate = -1;
    double best_gain = 0.0;
    CvResult best_result;
    for (size_t f = 0; f < families.size(); ++f) {
      bool in = false;
      for (int g : current) in = in || g == static_cast<int>(f);
      if (in) continue;
      std::vector<int> fams = current;
      fams.push_back(static_cast<int>(f));
      if (terms_of(fams).size() == terms_of(current).size()) continue;
      CvResult r;
      add_candidate(fams, current_index, &r);
      TermCandidate& c = summary->candidates.back();
      if (!r.ok) continue;
      paired_gain(current_result, r, &c.gain_m2, &c.gain_se_m2);
      if (c.gain_m2 > options.num_standard_errors * c.gain_se_m2 &&
          c.gain_m2 > best_gain) {
        best = static_cast<int>(f);
        best_gain = c.gain_m2;
        best_candidate = static_cast<int>(summary->candidates.size()) - 1;
        best_result = r;
      }
    }
    if (best < 0) break;
    current.push_back(best);
    current_result = best_result;
    current_index = best_candidate;
    summary->kept.push_back(families[best].name);
  }
  summary->chosen = current_index;
  summary->candidates[current_index].chosen = true;
  summary->terms = terms_of(current);
  summary->termination_type = TerminationType::kConvergence;
  std::ostringstream msg;
  msg << "kept " << (summary->kept.empty() ? "no joint error terms" : "");
  for (size_t k = 0; k < summary->kept.size(); ++k) {
    msg << (k ? ", " : "") << summary->kept[k];
  }
  msg << " (" << summary->terms.size() << " terms) by " << options.num_folds
      << "-fold cross-validation on " << num_poses << " poses";
  summary->message = msg.str();
}

std::string TermSelectionSummary::BriefReport() const {
  std::ostringstream out;
  out << "joint error terms by held-out error (a family kept when its gain "
         "exceeds "
      << num_standard_errors
      << " SE, paired by pose): " << TerminationTypeToString(termination_type)
      << "\n  " << message << "\n";
  for (const TermCandidate& c : candidates) {
    out << "  " << (c.chosen ? "* " : "  ") << c.name << " (" << c.num_terms
        << " terms): ";
    if (!c.ok) {
      out << "failed\n";
      continue;
    }
    out << "held-out RMS " << c.held_out_rms_m * 1e3 << " +- "
        << c.held_out_se_m * 1e3 << " mm, training " << c.training_rms_m * 1e3
        << " mm";
    if (c.extends >= 0) {
      out << "; gain " << c.gain_m2 * 1e6 << " mm^2 (SE " << c.gain_se_m2 * 1e6
          << ")";
    }
    out << "\n";
  }
  for (const std::string& d : dropped_terms) {
    out << "  not identifiable, left out: " << d << "\n";
  }
  return out.str();
}

}  // namespace activecal
