// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/compensate.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>

#include "activecal/calibration/cell_planning.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/targets_csv.h"
#include "printf_text.h"
#include "workflow_fail.h"

namespace activecal {
namespace {

nlohmann::json Vector(const Eigen::VectorXd& v) {
  nlohmann::json j = nlohmann::json::array();
  for (int i = 0; i < v.size(); ++i) j.push_back(v[i]);
  return j;
}

Eigen::Vector3d RotationVector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

using internal::Printf;

bool Fail(const std::string& message, CompensateSummary* summary) {
  summary->outputs.clear();
  return internal::Fail(message, summary, TerminationType::kUserFailure);
}

// The report's text: the compensation's, the learned correction's rounds,
// the size of the correction, the file written.
std::string ReportText(const RobotDescription& robot,
                       const CompensateOptions& options,
                       const CompensateSummary& s) {
  const bool with_rotation = options.compensation.ik.match == IkMatch::kPose;
  std::string text = s.compensation.BriefReport();
  if (!robot.learned_correction.empty()) {
    text += Printf(
        "with --robot's learned correction (%d random Fourier features): %d "
        "fixed-point rounds, the last moved a correction by %.3g m; errors "
        "are of the corrected model\n",
        robot.learned_correction.num_features(), s.rounds.rounds,
        s.rounds.last_change_m);
  }
  if (s.has_correction) {
    text += Printf(
        "correction (the nominal model at the compensated joints against "
        "the targets): position max %.3f mm, RMS %.3f mm",
        s.correction.max_position_m * 1e3, s.correction.rms_position_m * 1e3);
    if (with_rotation) {
      text += Printf("; rotation max %.4f deg, RMS %.4f deg",
                     s.correction.max_rotation_rad * 180.0 / M_PI,
                     s.correction.rms_rotation_rad * 180.0 / M_PI);
    }
    text += "\n";
  }
  text += Printf("wrote %zu compensated targets to %s\n",
                 s.compensation.results.size(), options.out.c_str());
  return text;
}

// The one-line result: the JSON's num_converged, num_targets, correction
// (mm, deg) and max_ik_residual_m (mm).
std::string ResultLine(const CompensateOptions& options,
                       const CompensateSummary& s) {
  const CompensationSummary& c = s.compensation;
  std::string line =
      Printf("%s: %d of %zu targets converged", options.program.c_str(),
             c.num_converged, c.results.size());
  if (s.has_correction) {
    line += Printf(", correction max %.3f mm, RMS %.3f mm",
                   s.correction.max_position_m * 1e3,
                   s.correction.rms_position_m * 1e3);
    if (options.compensation.ik.match == IkMatch::kPose) {
      line += Printf(", max %.4f deg, RMS %.4f deg",
                     s.correction.max_rotation_rad * 180.0 / M_PI,
                     s.correction.rms_rotation_rad * 180.0 / M_PI);
    }
  }
  line += Printf(", IK residual max %.3g mm", c.max_position_error_m * 1e3);
  return line;
}

std::string JsonText(const RobotDescription& robot,
                     const CompensateOptions& options,
                     const CompensateSummary& s) {
  const CompensationSummary& summary = s.compensation;
  const IkMatch match = options.compensation.ik.match;
  nlohmann::json j;
  j["robot"] = robot.model.name;
  j["nominal"] = options.nominal_path;
  j["program"] =
      options.poses_csv.empty() ? options.targets_csv : options.poses_csv;
  j["match"] = IkMatchName(match);
  j["termination_type"] = TerminationTypeToString(summary.termination_type);
  j["all_converged"] = summary.AllConverged();
  j["num_targets"] = summary.results.size();
  j["num_converged"] = summary.num_converged;
  j["num_singular"] = summary.num_singular;
  j["num_limit"] = summary.num_limit;
  j["num_unreachable"] = summary.num_unreachable;
  j["num_invalid"] = summary.num_invalid;
  j["num_iteration_cap"] = summary.num_iteration_cap;
  j["num_collision"] = summary.num_collision;
  if (!options.cell_path.empty()) {
    j["cell"] = options.cell_path;
    j["collision_geometry"] =
        options.cell ? options.cell->collision_source : std::string();
  }
  // The inverse kinematics' residual of the calibrated model at its own
  // solution (about 0 when converged), and the size of the correction.
  j["max_ik_residual_m"] = summary.max_position_error_m;
  j["max_ik_residual_rad"] = summary.max_rotation_error_rad;
  if (s.has_correction) {
    nlohmann::json c = {{"num_targets", s.correction.num_targets},
                        {"max_position_m", s.correction.max_position_m},
                        {"rms_position_m", s.correction.rms_position_m}};
    if (match == IkMatch::kPose) {
      c["max_rotation_rad"] = s.correction.max_rotation_rad;
      c["rms_rotation_rad"] = s.correction.rms_rotation_rad;
    }
    j["correction"] = c;
  } else {
    j["correction"] = nullptr;
  }
  j["max_joint_change"] = summary.max_joint_change;
  j["rms_joint_change"] = summary.rms_joint_change;
  j["message"] = summary.message;
  j["learned_correction"] = !robot.learned_correction.empty();
  if (!robot.learned_correction.empty()) {
    j["learned_correction_rounds"] = s.rounds.rounds;
  }
  nlohmann::json rows = nlohmann::json::array();
  for (size_t i = 0; i < summary.results.size(); ++i) {
    const InverseKinematicsResult& r = summary.results[i];
    const IkTarget& t = summary.targets[i];
    nlohmann::json row = {{"pose_index", s.labels[i]},
                          {"status", IkStatusName(r.status)},
                          {"message", r.message},
                          {"position_error_m", r.position_error_m},
                          {"rotation_error_rad", r.rotation_error_rad},
                          {"iterations", r.iterations},
                          {"conditioning", r.conditioning},
                          {"joints", Vector(r.joints)},
                          {"target_m", Vector(t.point)}};
    if (match == IkMatch::kPose) {
      row["target_rotation_vector_rad"] = Vector(RotationVector(t.rotation));
    }
    if (s.starts.rows() == static_cast<int64_t>(summary.results.size())) {
      const Eigen::VectorXd change = r.joints - s.starts.row(i).transpose();
      row["start_joints"] = Vector(s.starts.row(i).transpose());
      row["joint_change"] = Vector(change);
      row["max_joint_change"] = change.cwiseAbs().maxCoeff();
    }
    rows.push_back(row);
  }
  j["targets"] = rows;
  return j.dump(2) + "\n";
}

bool Run(const RobotDescription& robot, const CompensateOptions& given,
         CompensateSummary* s) {
  std::string error;
  if (!given.IsValid(&error)) return Fail(error, s);
  CompensateOptions options = given;
  CompensationOptions& compensation = options.compensation;
  const RobotModel& model = robot.model;
  if (options.cell && options.cell->checker) {
    if (options.cell->collision_source.empty()) {
      // A "converged" row must mean checked: without geometry the cell
      // could only check the joint margins.
      return Fail(
          "--cell: " +
              (options.nominal_path.empty()
                   ? "--robot=" + options.robot_path +
                         " has no collision geometry"
                   : "neither --robot=" + options.robot_path +
                         " nor --nominal=" + options.nominal_path +
                         " has collision geometry") +
              " (<collision> in a URDF, collision: in a robot file): the "
              "cell's collision checks cannot be made; give the nominal "
              "URDF with --nominal",
          s);
    }
    compensation.check = CellCompensationCheck(*options.cell->checker);
  }
  if (!options.marker.empty()) {
    compensation.ik.marker = model.MarkerIndex(options.marker);
  }
  if (compensation.ik.marker < 0) {
    return Fail("--marker: '" + options.marker +
                    "' is not a marker of robot '" + model.name + "'",
                s);
  }
  // The nominal model (with --poses_csv, what the program means; with
  // --targets_csv, optional: the size of the correction).
  RobotDescription nominal;
  const RobotModel* nominal_model = options.nominal_model;
  Eigen::VectorXd meaning;
  if (!options.poses_csv.empty() && options.nominal_path.empty()) {
    return Fail(
        "--poses_csv needs --nominal: the model the program was "
        "taught with",
        s);
  }
  if (!options.nominal_path.empty()) {
    RobotLoadOptions load;
    load.chain = options.chain;
    // The frames' markers are where the tracker's targets sit on the tool,
    // not geometry: the program means the point of that same marker. (The
    // frames' base is replaced by the calibrated one anyway.) Without
    // this, a URDF nominal kept its default marker at the tip link while
    // --robot's sat at the frames' marker: nominal == calibrated moved the
    // joints by up to 0.6 rad.
    load.frames_path = options.frames_path;
    if (!LoadRobot(options.nominal_path, load, &nominal, &error)) {
      return Fail("--nominal: " + error, s);
    }
    if (!CheckSameChain(model, nominal.model, &error)) {
      return Fail("--robot and --nominal: " + error, s);
    }
    nominal_model = &nominal.model;
  }
  if (nominal_model) {
    meaning = ProgramMeaningParameters(model, model.nominal, *nominal_model,
                                       nominal_model->nominal);
  }
  // In memory: the shapes the file readers would have checked.
  const int n_joints = model.num_joints();
  if (options.in_memory && options.nominal_model != nullptr) {
    if (!CheckSameChain(model, *options.nominal_model, &error)) {
      return Fail("the robot and nominal_model: " + error, s);
    }
    if (options.joint_program.rows() == 0 ||
        options.joint_program.cols() != n_joints) {
      return Fail("joint_program: expected (n >= 1, " +
                      std::to_string(n_joints) + ") joint values, got (" +
                      std::to_string(options.joint_program.rows()) + ", " +
                      std::to_string(options.joint_program.cols()) + ")",
                  s);
    }
  } else if (options.in_memory) {
    const TargetList& t = options.targets;
    const int64_t n = t.points.rows();
    const auto shape = [](const Eigen::MatrixXd& m) {
      return "(" + std::to_string(m.rows()) + ", " + std::to_string(m.cols()) +
             ")";
    };
    if (n == 0 || t.points.cols() != 3) {
      return Fail(
          "targets.points: expected (n >= 1, 3) points, got " + shape(t.points),
          s);
    }
    if (t.rotation_vectors.rows() != 0 &&
        (t.rotation_vectors.rows() != n || t.rotation_vectors.cols() != 3)) {
      return Fail("targets.rotation_vectors: expected (" + std::to_string(n) +
                      ", 3) or none, got " + shape(t.rotation_vectors),
                  s);
    }
    if (t.start_joints.rows() != 0 &&
        (t.start_joints.rows() != n || t.start_joints.cols() != n_joints)) {
      return Fail("targets.start_joints: expected (" + std::to_string(n) +
                      ", " + std::to_string(n_joints) + ") or none, got " +
                      shape(t.start_joints),
                  s);
    }
    if (static_cast<int64_t>(t.pose_indices.size()) > n) {
      return Fail("targets.pose_indices: more labels than points", s);
    }
    if (compensation.ik.match == IkMatch::kPose &&
        t.rotation_vectors.rows() == 0) {
      return Fail(
          "match=pose needs the target orientations "
          "(targets.rotation_vectors)",
          s);
    }
  }
  CompensationSummary& summary = s->compensation;
  // The program is in memory as joints only with options.nominal_model: a
  // nominal_path with in-memory targets is the size of the correction.
  if (options.in_memory && options.nominal_model != nullptr) {
    s->starts = options.joint_program;
    for (int64_t i = 0; i < options.joint_program.rows(); ++i) {
      s->labels.push_back(i);
    }
    CompensateProgram(model, model.nominal, *options.nominal_model,
                      options.nominal_model->nominal, options.joint_program,
                      compensation, &summary);
  } else if (options.in_memory) {
    s->labels = options.targets.pose_indices;
    for (int64_t i = s->labels.size(); i < options.targets.points.rows(); ++i) {
      s->labels.push_back(i);
    }
    s->starts = options.targets.start_joints;
    CompensateTargets(model, model.nominal, IkTargetsFromList(options.targets),
                      options.targets.start_joints, Eigen::VectorXd(),
                      compensation, &summary);
  } else if (!options.poses_csv.empty()) {
    PoseList program;
    if (!ReadPosesCsv(options.poses_csv, model, /*reject_duplicates=*/false,
                      &program, &error)) {
      return Fail("--poses_csv: " + error, s);
    }
    s->labels = program.pose_indices;
    s->starts = program.joints;
    CompensateProgram(model, model.nominal, *nominal_model,
                      nominal_model->nominal, program.joints, compensation,
                      &summary);
  } else {
    TargetList list;
    TargetsCsvOptions csv;
    csv.columns_strict = options.columns_strict;
    std::vector<std::string> notes;
    if (!ReadTargetsCsv(options.targets_csv, model, csv, &list, &notes,
                        &error)) {
      return Fail("--targets_csv: " + error, s);
    }
    for (const std::string& n : notes) {
      s->notes += options.program + ": note: " + n + "\n";
    }
    if (compensation.ik.match == IkMatch::kPose &&
        list.rotation_vectors.rows() == 0) {
      return Fail("--match=pose needs the target orientations: --targets_csv " +
                      options.targets_csv +
                      " has no rx_rad, ry_rad, rz_rad columns",
                  s);
    }
    const std::vector<IkTarget> targets = IkTargetsFromList(list);
    s->labels = list.pose_indices;
    CompensateTargets(model, model.nominal, targets, list.start_joints,
                      Eigen::VectorXd(), compensation, &summary);
    s->starts = list.start_joints;
  }
  if (summary.termination_type == TerminationType::kUserFailure) {
    return Fail(summary.message, s);
  }
  // The learned correction of --robot's file (identify --learned_residual):
  // the targets reached by the hybrid model.
  s->rounds = ApplyLearnedCorrection(
      model, model.nominal, robot.learned_correction, compensation, &summary);
  // The size of the correction: the nominal model's pose at the
  // compensated joints against the targets (the error compensation
  // removes); without --nominal (Cartesian targets) there is no nominal
  // to measure it with.
  s->has_correction = nominal_model != nullptr;
  if (s->has_correction) {
    s->correction =
        MeasureCorrection(*nominal_model, meaning, compensation.ik.marker,
                          compensation.ik.match == IkMatch::kPose, summary);
  }
  if (!options.out.empty()) {
    s->outputs.push_back(
        {options.out, CompensatedPosesCsvText(model, s->labels, summary)});
  }
  if (!options.json_out.empty()) {
    s->outputs.push_back({options.json_out, JsonText(robot, options, *s)});
  }
  s->report = ReportText(robot, options, *s);
  s->result_line = ResultLine(options, *s);
  s->termination_type = summary.AllConverged() ? TerminationType::kConvergence
                                               : TerminationType::kFailure;
  if (!summary.AllConverged()) {
    // The same counts as the summary's message, each first also by its
    // pose_index (a target refused by the cell converged, but is not to
    // be run: it is counted under collision, not converged).
    const std::string text = summary.NotConvergedText(s->labels);
    const size_t colon = text.find(':');
    s->not_converged = text.substr(0, colon) +
                       ", written with their status to " + options.out +
                       text.substr(colon);
  }
  return true;
}

}  // namespace

bool CompensateOptions::HasOneProgram(std::string* error) const {
  if (!poses_csv.empty() + !targets_csv.empty() + in_memory != 1) {
    *error =
        "give exactly one of --poses_csv (joint targets) and "
        "--targets_csv (Cartesian targets)";
    return false;
  }
  return true;
}

bool CompensateOptions::IsValid(std::string* error) const {
  return HasOneProgram(error) && compensation.ik.IsValid(error);
}

bool ParseJointWeights(const std::string& text, std::vector<double>* weights,
                       std::string* error) {
  weights->clear();
  if (text.empty()) return true;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double w = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0') {
      *error = "--joint_weights: '" + item +
               "' is not a number (comma-separated weights, one per joint)";
      return false;
    }
    weights->push_back(w);
  }
  return true;
}

std::string UrdfWithoutFramesNote(const std::string& robot_path,
                                  const std::string& frames_path,
                                  const std::string& tip_link) {
  if (!IsUrdfPath(robot_path) || !frames_path.empty()) return "";
  const std::string tip = tip_link.empty() ? "" : " '" + tip_link + "'";
  return "activecal_compensate: note: --robot=" + robot_path +
         " has no --frames: the device frame is taken as the chain's base "
         "link and the marker as the origin of the tip link" +
         tip +
         ", with no offset; give the calibration's frames "
         "(activecal_identify --frames_out) with --frames when it had a base "
         "frame or markers\n";
}

void Compensate(const RobotDescription& robot, const CompensateOptions& options,
                CompensateSummary* summary) {
  *summary = CompensateSummary();
  Run(robot, options, summary);
}

}  // namespace activecal
