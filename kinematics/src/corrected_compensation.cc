// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/kinematics/corrected_compensation.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "activecal/core/kinematics.h"
#include "activecal/kinematics/inverse_kinematics.h"

namespace activecal {

CorrectionRounds ApplyLearnedCorrection(const RobotModel& model,
                                        const Eigen::VectorXd& values,
                                        const LearnedCorrection& correction,
                                        const CompensationOptions& options,
                                        CompensationSummary* summary,
                                        int max_rounds) {
  CorrectionRounds rounds;
  if (correction.empty() || summary->results.empty() ||
      summary->termination_type == TerminationType::kUserFailure) {
    return rounds;
  }
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(summary->results.size());
  const int marker = options.ik.marker;
  const Eigen::Matrix3d rb = BaseRotation(model, values);
  // The correction at each target's current joints (zero where invalid).
  auto corrections = [&]() {
    std::vector<Eigen::Vector3d> c(n, Eigen::Vector3d::Zero());
    for (int i = 0; i < n; ++i) {
      const InverseKinematicsResult& r = summary->results[i];
      if (r.status == IkStatus::kInvalid || !r.joints.allFinite()) continue;
      c[i] = rb * correction.Correction(r.joints, marker);
    }
    return c;
  };
  std::vector<Eigen::Vector3d> c = corrections();
  const std::vector<IkTarget> meant = summary->targets;
  Eigen::MatrixXd q(n, model.num_joints());
  while (rounds.rounds < max_rounds) {
    std::vector<IkTarget> shifted = meant;
    for (int i = 0; i < n; ++i) {
      const InverseKinematicsResult& r = summary->results[i];
      shifted[i].point -= c[i];
      if (r.joints.size() == q.cols() && r.joints.allFinite()) {
        q.row(i) = r.joints.transpose();
      } else {
        q.row(i) = summary->starts.row(i);
      }
    }
    std::vector<InverseKinematicsResult> results;
    SolveInverseKinematicsBatch(model, values, shifted, q, options.ik,
                                options.num_threads, &results);
    for (int i = 0; i < n; ++i) {
      // An invalid target stays as the parametric run left it.
      if (summary->results[i].status == IkStatus::kInvalid) continue;
      summary->results[i] = results[i];
    }
    ++rounds.rounds;
    const std::vector<Eigen::Vector3d> next = corrections();
    rounds.last_change_m = 0.0;
    // Over the targets the solver reached (one it cannot reach, e.g.
    // outside the joint limits, need not settle).
    for (int i = 0; i < n; ++i) {
      if (summary->results[i].status != IkStatus::kConverged) continue;
      rounds.last_change_m =
          std::max(rounds.last_change_m, (next[i] - c[i]).norm());
    }
    c = next;
    if (rounds.last_change_m <= options.ik.position_tolerance_m) break;
  }
  // The hybrid model's error left at each result.
  for (int i = 0; i < n; ++i) {
    InverseKinematicsResult& r = summary->results[i];
    if (r.status == IkStatus::kInvalid || !r.joints.allFinite()) continue;
    const Eigen::Vector3d point =
        MeasuredPoint(model, values, r.joints, marker) + c[i];
    r.position_error_m = (point - meant[i].point).norm();
    if (r.status == IkStatus::kConverged &&
        r.position_error_m > options.ik.position_tolerance_m) {
      char text[200];
      std::snprintf(text, sizeof(text),
                    "the learned correction did not settle: %.3g m left "
                    "after %d rounds",
                    r.position_error_m, rounds.rounds);
      r.status = IkStatus::kIterationCap;
      r.message = text;
    }
  }
  summary->targets = meant;
  summary->seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  SummarizeCompensation(options, summary);
  return rounds;
}

}  // namespace activecal
