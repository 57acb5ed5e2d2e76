// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/simulate_workflow.h"

#include <glog/logging.h>

#include <string>

#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/pool_reduction.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/io/csv_files.h"
#include "workflow_fail.h"

namespace activecal {
namespace {

using internal::Fail;

// The ISO 9283 cycle columns of the poses CSV (activecal_select
// --iso9283_cube writes them), one entry per data row; empty without them.
bool CommandedPoses(const std::string& path, const RobotModel& model,
                    std::vector<CommandedPose>* commanded, std::string* error) {
  std::string text;
  if (!ReadTextFile(path, &text, error) ||
      !ParseCommandedPosesIfAny(text, path, model, MeasurementsCsvOptions(),
                                commanded, error)) {
    *error = "--poses_csv: " + *error;
    return false;
  }
  return true;
}

}  // namespace

bool SimulateAtPoses(const RobotDescription& robot,
                     const SimulateOptions& options, SimulateSummary* summary) {
  *summary = SimulateSummary();
  RobotModel& model = summary->model;
  model = robot.model;
  const MeasurementType type = options.type;
  const bool perturbed = options.perturb_m > 0 || options.perturb_rad > 0;
  const bool truth_known =
      robot.true_parameters.size() == model.num_parameters();
  if (!truth_known && !perturbed) {
    return Fail("--robot '" + options.robot_path +
                    "' has no true values to simulate from: add 'true:' "
                    "entries to its blocks (docs/formats.md) or perturb it "
                    "(--perturb_m, --perturb_rad)",
                summary);
  }
  PoseList poses;
  std::string error;
  if (!ReadPosesCsv(options.poses_csv, model, /*reject_duplicates=*/false,
                    &poses, &error)) {
    return Fail("--poses_csv: " + error, summary);
  }
  std::vector<CommandedPose> commanded;
  if (!CommandedPoses(options.poses_csv, model, &commanded, &error)) {
    return Fail(error, summary);
  }
  if (!commanded.empty() && type == MeasurementType::kDistance) {
    return Fail("--poses_csv " + options.poses_csv +
                    " has ISO 9283 cycle columns (pose, commanded_*): cycles "
                    "are measured as --type=position or pose, not distance",
                summary);
  }
  // The cell: the poses it allows, and the targets each sees.
  Eigen::MatrixXd joints = poses.joints;
  // The poses CSV's data row of each row of joints.
  std::vector<int64_t> rows(poses.joints.rows());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<int64_t>(i);
  std::vector<uint32_t> seen;
  if (options.cell != nullptr) {
    PoolFilterSummary feasibility;
    if (!FilterPool(*options.cell, poses.joints, PoolFilterOptions(),
                    &feasibility)) {
      return Fail("--cell: " + feasibility.message, summary);
    }
    if (feasibility.num_feasible() == 0) {
      return Fail("--cell: no pose of --poses_csv is left: " +
                      FeasibleNote(*options.cell, feasibility),
                  summary);
    }
    summary->report += "  " + feasibility.BriefReport(*options.cell);
    joints = feasibility.FeasibleJoints(poses.joints);
    rows = feasibility.feasible;
    if (CellTargetsAreMarkers(*options.cell, model)) {
      seen = feasibility.targets_seen;
    }
  }
  // The truth: the file's, or its nominal values, moved.
  Eigen::VectorXd& truth = summary->truth;
  truth = truth_known ? robot.true_parameters : model.nominal;
  if (perturbed) {
    if (options.reduce_parameter_set) {
      // The parameters the poses separate, each measuring what it sees.
      std::string why;
      if (!ReduceModelForPool(options.parameter_set, joints,
                              seen.empty() ? nullptr : &seen, &model,
                              &summary->report, &why)) {
        return Fail(why, summary);
      }
    }
    const Eigen::VectorXd unperturbed = truth;
    if (!PerturbParameters(model, unperturbed, options.perturb_m,
                           options.perturb_rad, options.seed, &truth, &error)) {
      return Fail("--" + error, summary);
    }
  }
  std::vector<Measurement> plan;
  std::vector<int> row_of;  // the poses CSV's data row of each of plan
  const int n = static_cast<int>(joints.rows());
  if (type == MeasurementType::kDistance) {
    int identical = -1;
    if (!SimulationPlan(joints, type, &plan, &identical)) {
      if (identical < 0) {
        return Fail(
            "--type=distance needs at least 2 poses, got " + std::to_string(n),
            summary);
      }
      return Fail("--type=distance: poses " + std::to_string(identical + 1) +
                      " and " + std::to_string(identical + 2) + " of " +
                      options.poses_csv +
                      " (data rows) are identical: a distance between them "
                      "measures nothing; remove one",
                  summary);
    }
  } else {
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < (seen.empty() ? 1 : model.num_markers()); ++k) {
        if (!seen.empty() && (k >= 32 || !(seen[i] & (1u << k)))) continue;
        Measurement m;
        m.type = type;
        m.joints = joints.row(i).transpose();
        m.marker = k;
        plan.push_back(m);
        row_of.push_back(static_cast<int>(rows[i]));
      }
    }
  }
  std::vector<Measurement>& measurements = summary->measurements;
  if (!SimulateMeasurements(model, truth, plan, options.noise, options.seed,
                            &measurements, &error)) {
    if (type == MeasurementType::kDistance) {
      error +=
          " (measurement i is the distance between poses i + 1 and "
          "i + 2 of " +
          options.poses_csv + ", data rows)";
    }
    return Fail(error, summary);
  }
  // ISO 9283 cycles: the poses' label and commanded pose carried to each
  // measurement row, so that activecal_evaluate --iso9283 reads the file.
  std::string& text = summary->measurements_csv;
  text = MeasurementsCsvText(model, measurements);
  if (!commanded.empty()) {
    CHECK_EQ(commanded.size(), static_cast<size_t>(poses.joints.rows()));
    CHECK_EQ(row_of.size(), measurements.size());
    text = WithCommandedPoseColumns(text, commanded, row_of);
  }
  if (options.true_model) {
    RobotFileOptions file;
    file.angle_unit = robot.angle_unit;
    file.true_parameters = truth;
    file.comment =
        "The robot activecal_simulate measured: its 'true:' "
        "entries are the values the measurements of " +
        options.out + " were computed from";
    if (perturbed) {
      file.comment +=
          " (" + std::string(truth_known ? "the true" : "the nominal") +
          " values of " +
          (options.robot_path.empty() ? std::string("the built-in PUMA 560")
                                      : options.robot_path) +
          ", every free parameter perturbed: " + options.perturbation_flags +
          ")";
    }
    summary->true_model_text = RobotFileText(model, model.nominal, file);
    summary->written_report =
        "wrote the true model (" + std::to_string(model.num_free()) +
        " free parameters" + (perturbed ? ", perturbed" : "") + ") to " +
        options.true_model_out + "\n";
  }
  summary->result_line = options.program_name + ": wrote " +
                         std::to_string(measurements.size()) + " " +
                         options.type_name + " measurements of '" + model.name +
                         "' to " + options.out;
  summary->termination_type = TerminationType::kConvergence;
  return true;
}

}  // namespace activecal
