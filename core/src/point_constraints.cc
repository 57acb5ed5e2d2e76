// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/point_constraints.h"

#include <Eigen/Dense>
#include <algorithm>
#include <map>

#include "activecal/core/kinematics.h"

namespace activecal {

std::vector<std::string> PointLabels(
    const std::vector<Measurement>& measurements) {
  std::vector<std::string> labels;
  auto add = [&](const std::string& label) {
    if (std::find(labels.begin(), labels.end(), label) == labels.end()) {
      labels.push_back(label);
    }
  };
  for (const Measurement& m : measurements) {
    if (m.type == MeasurementType::kPoint) add(m.point);
  }
  for (const Measurement& m : measurements) {
    if (m.type == MeasurementType::kPointDistance) {
      add(m.point);
      add(m.point2);
    }
  }
  return labels;
}

bool HasPointRows(const std::vector<Measurement>& measurements) {
  return std::any_of(measurements.begin(), measurements.end(),
                     [](const Measurement& m) { return m.involves_points(); });
}

bool CheckPointLabels(const std::vector<Measurement>& measurements,
                      std::string* error) {
  std::map<std::string, int> count, first;
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    if (m.type != MeasurementType::kPoint) continue;
    if (count[m.point]++ == 0) first[m.point] = static_cast<int>(i);
  }
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    if (m.type == MeasurementType::kPoint && count[m.point] < 2) {
      if (error) {
        *error = "measurement " + std::to_string(i) + ": point '" + m.point +
                 "' has one row only: a fixed point needs at least two "
                 "configurations (its 3 coordinates absorb a single row)";
      }
      return false;
    }
    if (m.type != MeasurementType::kPointDistance) continue;
    for (const std::string* label : {&m.point, &m.point2}) {
      if (count.count(*label) == 0 || count.at(*label) == 0) {
        if (error) {
          *error = "measurement " + std::to_string(i) +
                   ": a known distance to point '" + *label +
                   "', which no point row reaches";
        }
        return false;
      }
    }
  }
  return true;
}

int LabelIndex(const std::vector<std::string>& labels,
               const std::string& label) {
  return static_cast<int>(std::find(labels.begin(), labels.end(), label) -
                          labels.begin());
}

std::vector<Eigen::Vector3d> MeanPointPositions(
    const RobotModel& model, const Eigen::VectorXd& parameters,
    const std::vector<Measurement>& measurements,
    const std::vector<std::string>& labels) {
  std::vector<Eigen::Vector3d> sum(labels.size(), Eigen::Vector3d::Zero());
  std::vector<int> n(labels.size(), 0);
  for (const Measurement& m : measurements) {
    if (m.type != MeasurementType::kPoint) continue;
    const int k = LabelIndex(labels, m.point);
    if (k >= static_cast<int>(labels.size())) continue;
    sum[k] += MeasuredPoint(model, parameters, m.joints, m.marker);
    ++n[k];
  }
  for (size_t k = 0; k < labels.size(); ++k) {
    if (n[k] > 0) sum[k] /= n[k];
  }
  return sum;
}

bool ReachPoint(const RobotModel& model, const Eigen::VectorXd& parameters,
                int marker, const Eigen::Vector3d& target, Eigen::VectorXd* q,
                double tolerance_m, int max_iterations) {
  const int n = model.num_joints();
  Eigen::VectorXd best = *q;
  Eigen::Vector3d e = target - MeasuredPoint(model, parameters, *q, marker);
  double best_error = e.norm();
  constexpr double kStep = 1e-6;  // central differences, rad or m
  for (int it = 0; it < max_iterations && best_error > tolerance_m; ++it) {
    Eigen::MatrixXd J(3, n);
    for (int j = 0; j < n; ++j) {
      Eigen::VectorXd plus = *q, minus = *q;
      plus[j] += kStep;
      minus[j] -= kStep;
      J.col(j) = (MeasuredPoint(model, parameters, plus, marker) -
                  MeasuredPoint(model, parameters, minus, marker)) /
                 (2 * kStep);
    }
    // Minimum-norm step J^T (J J^T)^-1 e.
    const Eigen::Matrix3d JJt = J * J.transpose();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(JJt);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) break;
    *q += J.transpose() * ldlt.solve(e);
    e = target - MeasuredPoint(model, parameters, *q, marker);
    if (!e.allFinite()) break;
    if (e.norm() < best_error) {
      best_error = e.norm();
      best = *q;
    } else if (it > 3) {
      break;  // no longer improving: rounding
    }
  }
  *q = best;
  return best_error <= tolerance_m;
}

}  // namespace activecal
