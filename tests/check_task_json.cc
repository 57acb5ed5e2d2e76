// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Reads an activecal_select --criterion=task_rms report back and checks its
// meaning: predicted_task_rms_m recomputed from joint_angles_rad (fresh
// Jacobians of the built-in PUMA at its nominal values, task = the lattice
// of `levels`, prior = the rows of measured_csv), the counts, the
// certificate's range and, with a target, the curve: sizes increasing, the
// size found the first on the curve meeting the target, the size before it
// on the curve and missing it.
//
//   check_task_json report.json

#include <Eigen/Cholesky>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "activecal/calibration/pool_builder.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/io/csv_files.h"
#include "activecal/residuals/jacobians.h"

namespace {

int failures = 0;

void Check(bool ok, const std::string& what) {
  if (!ok) {
    std::cout << "FAIL: " << what << "\n";
    ++failures;
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace activecal;
  if (argc != 2) {
    std::cerr << "usage: check_task_json report.json\n";
    return 2;
  }
  std::ifstream in(argv[1]);
  const nlohmann::json j = nlohmann::json::parse(in);
  const RobotModel model = Puma560PaperModel();
  const double sigma = j.at("noise_m").get<double>();
  // The task: the lattice.
  JointLattice lattice;
  std::string error;
  if (!JointLattice::Create(model, j.at("levels").get<int>(), &lattice,
                            &error)) {
    std::cout << "FAIL: " << error << "\n";
    return 1;
  }
  RowMatrixXd task;
  if (!PoolJacobians(model, model.nominal, lattice.AllJointValues(),
                     PoolJacobianOptions(), &task, &error)) {
    std::cout << "FAIL: " << error << "\n";
    return 1;
  }
  const Eigen::MatrixXd W =
      task.transpose() * task / static_cast<double>(task.rows() / 3);
  // The design.
  const auto& angles = j.at("joint_angles_rad");
  Eigen::MatrixXd joints(angles.size(), model.num_joints());
  for (size_t r = 0; r < angles.size(); ++r) {
    for (int c = 0; c < model.num_joints(); ++c) {
      joints(r, c) = angles[r][c].get<double>();
    }
  }
  Check(j.at("num_poses").get<size_t>() == angles.size(),
        "num_poses is the number of joint_angles_rad rows");
  Check(j.at("pose_indices").size() == angles.size(),
        "one pose index per pose");
  if (j.contains("target_rms_m")) {
    // The design is the curve's entry of its size.
    bool found = false;
    for (const auto& entry : j.at("predicted_task_rms_by_size_m")) {
      found = found || entry[0].get<size_t>() == angles.size();
    }
    Check(found, "the design's size is on the curve");
  }
  RowMatrixXd design;
  if (!PoolJacobians(model, model.nominal, joints, PoolJacobianOptions(),
                     &design, &error)) {
    std::cout << "FAIL: " << error << "\n";
    return 1;
  }
  Eigen::MatrixXd M = design.transpose() * design;
  const std::string measured_csv = j.value("measured_csv", "");
  if (!measured_csv.empty()) {
    std::vector<Measurement> measured;
    RowMatrixXd prior;
    if (!ReadMeasurementsCsv(measured_csv, model, &measured, &error) ||
        !MeasuredInformationRows(model, model.nominal, measured, 1.0, sigma,
                                 &prior, &error)) {
      std::cout << "FAIL: " << error << "\n";
      return 1;
    }
    Check(j.at("num_measured").get<size_t>() == measured.size(),
          "num_measured");
    M += prior.transpose() * prior;
  }
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  Check(llt.info() == Eigen::Success, "the design's M is positive definite");
  const double rms = sigma * std::sqrt(llt.solve(W).trace());
  const double reported = j.at("predicted_task_rms_m").get<double>();
  Check(std::abs(rms - reported) <= 1e-6 * rms,
        "predicted_task_rms_m " + std::to_string(reported) +
            " recomputed from joint_angles_rad: " + std::to_string(rms));
  if (j.contains("efficiency_lower_bound") &&
      j.value("criterion", "") == "task_rms") {
    const double e = j.at("efficiency_lower_bound").get<double>();
    Check(e > 0 && e <= 1, "efficiency_lower_bound in (0, 1]");
    const double lower = j.at("task_rms_lower_bound_m").get<double>();
    Check(lower <= reported * (1 + 1e-12),
          "task_rms_lower_bound_m <= predicted_task_rms_m");
    Check(std::abs(e - (lower / reported) * (lower / reported)) <= 1e-9,
          "efficiency = (lower bound / predicted)^2");
  }
  if (j.contains("target_rms_m")) {
    const double target = j.at("target_rms_m").get<double>();
    const int n = j.at("num_poses").get<int>();
    const auto& curve = j.at("predicted_task_rms_by_size_m");
    Check(!curve.empty(), "a curve");
    int first_meeting = -1;
    bool has_before = false;
    for (size_t k = 0; k < curve.size(); ++k) {
      const int size = curve[k][0].get<int>();
      const double value = curve[k][1].get<double>();
      if (k > 0) Check(size > curve[k - 1][0].get<int>(), "sizes increase");
      if (value <= target && first_meeting < 0) first_meeting = size;
      if (size == n) {
        Check(std::abs(value - reported) <= 1e-12 * reported,
              "the curve's value at num_poses is predicted_task_rms_m");
      }
      if (size == n - 1) {
        has_before = true;
        Check(value > target, "num_poses - 1 misses the target");
      }
    }
    Check(first_meeting == n, "num_poses is the first size meeting the target");
    Check(has_before || n == curve[0][0].get<int>(),
          "num_poses - 1 is on the curve (unless it is the first size)");
    Check(reported <= target, "the design meets the target");
  }
  if (failures == 0) std::cout << "ok: " << argv[1] << "\n";
  return failures == 0 ? 0 : 1;
}
