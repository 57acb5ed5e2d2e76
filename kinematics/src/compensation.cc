// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/kinematics/compensation.h"

#include <glog/logging.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "activecal/core/parallel.h"
#include "activecal/io/csv_files.h"

namespace activecal {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

// The summary's count of each status, in IkStatus order.
constexpr int CompensationSummary::*kStatusCounts[] = {
    &CompensationSummary::num_converged,
    &CompensationSummary::num_singular,
    &CompensationSummary::num_limit,
    &CompensationSummary::num_unreachable,
    &CompensationSummary::num_invalid,
    &CompensationSummary::num_iteration_cap,
    &CompensationSummary::num_collision};
static_assert(std::size(kStatusCounts) ==
                  static_cast<size_t>(IkStatus::kCollision) + 1,
              "one count per IkStatus");

// The cell's check of the converged results (options.check), then the
// counts, maxima and the termination of a finished run.
void Summarize(const Eigen::MatrixXd& starts,
               const CompensationOptions& options,
               CompensationSummary* summary) {
  summary->starts = starts;
  if (options.check) {
    for (InverseKinematicsResult& r : summary->results) {
      std::string reason;
      if (r.status == IkStatus::kConverged &&
          !options.check(r.joints, &reason)) {
        r.status = IkStatus::kCollision;
        r.message = reason;
      }
    }
  }
  for (int CompensationSummary::*count : kStatusCounts) summary->*count = 0;
  double sum_change2 = 0.0;
  int first_failure = -1;
  const int n = static_cast<int>(summary->results.size());
  for (int i = 0; i < n; ++i) {
    const InverseKinematicsResult& r = summary->results[i];
    ++(summary->*kStatusCounts[static_cast<int>(r.status)]);
    if (r.status != IkStatus::kConverged && first_failure < 0)
      first_failure = i;
    summary->max_position_error_m =
        std::max(summary->max_position_error_m, r.position_error_m);
    summary->max_rotation_error_rad =
        std::max(summary->max_rotation_error_rad, r.rotation_error_rad);
    if (r.joints.size() == starts.cols()) {
      const Eigen::VectorXd change = r.joints - starts.row(i).transpose();
      summary->max_joint_change =
          std::max(summary->max_joint_change, change.cwiseAbs().maxCoeff());
      sum_change2 += change.squaredNorm();
    }
  }
  summary->rms_joint_change = n > 0 ? std::sqrt(sum_change2 / n) : 0.0;
  if (first_failure < 0) {
    summary->termination_type = TerminationType::kConvergence;
    summary->message.clear();
    return;
  }
  summary->termination_type = TerminationType::kFailure;
  summary->message = summary->NotConvergedText();
}

void UserFailure(const std::string& message, CompensationSummary* summary) {
  *summary = CompensationSummary();
  summary->termination_type = TerminationType::kUserFailure;
  summary->message = message;
}

// The options against the model: valid, and one joint weight per joint.
bool CheckOptions(const RobotModel& model, const CompensationOptions& options,
                  std::string* error) {
  if (!options.ik.IsValid(error)) return false;
  const size_t n = options.ik.joint_weights.size();
  if (n != 0 && n != static_cast<size_t>(model.num_joints())) {
    *error = "joint_weights: expected " + std::to_string(model.num_joints()) +
             " weights (one per joint of '" + model.name + "'), got " +
             std::to_string(n);
    return false;
  }
  return true;
}

}  // namespace

bool CheckSameChain(const RobotModel& calibrated, const RobotModel& nominal,
                    std::string* error) {
  auto fail = [error](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (calibrated.num_joints() != nominal.num_joints()) {
    return fail("the calibrated model '" + calibrated.name + "' has " +
                std::to_string(calibrated.num_joints()) +
                " joints, the nominal model '" + nominal.name + "' " +
                std::to_string(nominal.num_joints()) + ": not the same robot");
  }
  for (int j = 0; j < calibrated.num_joints(); ++j) {
    const JointType a = calibrated.links[j].joint_type;
    const JointType b = nominal.links[j].joint_type;
    if (a != b) {
      return fail("joint " + std::to_string(j + 1) +
                  ": the calibrated model's is " + JointTypeName(a) +
                  ", the nominal model's " + JointTypeName(b) +
                  ": not the same robot");
    }
  }
  if (calibrated.base.convention != nominal.base.convention) {
    return fail(
        std::string("the base frames differ: the calibrated model's is ") +
        LinkConventionName(calibrated.base.convention) +
        ", the nominal model's " + LinkConventionName(nominal.base.convention) +
        " (the program is placed with the calibrated base frame, so "
        "both need the same kind of base)");
  }
  if (calibrated.num_markers() != nominal.num_markers()) {
    return fail("the calibrated model has " +
                std::to_string(calibrated.num_markers()) +
                " markers, the nominal model " +
                std::to_string(nominal.num_markers()) + ": not the same tool");
  }
  return true;
}

Eigen::VectorXd ProgramMeaningParameters(
    const RobotModel& calibrated, const Eigen::VectorXd& calibrated_values,
    const RobotModel& nominal, const Eigen::VectorXd& nominal_values) {
  CHECK_EQ(calibrated.block_size(0), nominal.block_size(0));
  Eigen::VectorXd meaning = nominal_values;
  meaning.head(nominal.block_size(0)) =
      calibrated_values.head(calibrated.block_size(0));
  return meaning;
}

void SummarizeCompensation(const CompensationOptions& options,
                           CompensationSummary* summary) {
  const Eigen::MatrixXd starts = summary->starts;
  summary->max_position_error_m = summary->max_rotation_error_rad = 0.0;
  summary->max_joint_change = summary->rms_joint_change = 0.0;
  Summarize(starts, options, summary);
}

bool CompensationSummary::AllConverged() const {
  return termination_type == TerminationType::kConvergence;
}

std::string CompensationSummary::NotConvergedText(
    const std::vector<int64_t>& labels) const {
  const int n = static_cast<int>(results.size());
  if (num_converged == n) return "";
  std::string text = std::to_string(n - num_converged) + " of " +
                     std::to_string(n) + " targets are not converged:";
  const IkStatus order[] = {IkStatus::kSingular,     IkStatus::kLimit,
                            IkStatus::kUnreachable,  IkStatus::kInvalid,
                            IkStatus::kIterationCap, IkStatus::kCollision};
  bool any = false;
  for (IkStatus status : order) {
    int count = 0, first = -1;
    for (int i = 0; i < n; ++i) {
      if (results[i].status != status) continue;
      if (count++ == 0) first = i;
    }
    if (count == 0) continue;
    text += std::string(any ? ", " : " ") + std::to_string(count) + " " +
            IkStatusName(status) + " (the first, target " +
            std::to_string(first);
    if (static_cast<int>(labels.size()) == n) {
      text += ", pose_index " + std::to_string(labels[first]);
    }
    text += ": " + results[first].message + ")";
    any = true;
  }
  return text;
}

std::string CompensationSummary::BriefReport() const {
  std::ostringstream out;
  out << "compensation: " << TerminationTypeToString(termination_type) << ", "
      << results.size() << " targets: " << num_converged << " converged";
  if (num_singular) out << ", " << num_singular << " singular";
  if (num_limit) out << ", " << num_limit << " limit";
  if (num_unreachable) out << ", " << num_unreachable << " unreachable";
  if (num_invalid) out << ", " << num_invalid << " invalid";
  if (num_iteration_cap) out << ", " << num_iteration_cap << " iteration_cap";
  if (num_collision) out << ", " << num_collision << " collision";
  out << "\n  largest IK residual " << max_position_error_m << " m";
  if (max_rotation_error_rad > 0)
    out << ", " << max_rotation_error_rad << " rad";
  out << "; joint change: largest of one joint " << max_joint_change
      << ", RMS per target (all joints) " << rms_joint_change
      << " (rad or m)\n  " << seconds << " s";
  if (seconds > 0) out << " (" << results.size() / seconds << " targets/s)";
  out << "\n";
  if (!message.empty()) out << "  " << message << "\n";
  return out.str();
}

CorrectionSize MeasureCorrection(const RobotModel& nominal,
                                 const Eigen::VectorXd& values, int marker,
                                 bool with_rotation,
                                 const CompensationSummary& summary) {
  CHECK_EQ(summary.targets.size(), summary.results.size());
  CorrectionSize size;
  double sum_p2 = 0.0, sum_r2 = 0.0;
  for (size_t i = 0; i < summary.results.size(); ++i) {
    const Eigen::VectorXd& q = summary.results[i].joints;
    const IkTarget& target = summary.targets[i];
    // A target the calibrated model does not reach: the nominal model's
    // miss there holds the inverse kinematics' miss, not the correction.
    const IkStatus status = summary.results[i].status;
    if (status != IkStatus::kConverged && status != IkStatus::kSingular) {
      continue;
    }
    if (q.size() != nominal.num_joints() || !q.allFinite() ||
        !target.point.allFinite() || !target.rotation.allFinite()) {
      continue;
    }
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    TargetFrame(nominal, values, q, &R, &t, marker);
    const double p = (t - target.point).norm();
    const double r =
        with_rotation
            ? Eigen::AngleAxisd(target.rotation.transpose() * R).angle()
            : 0.0;
    ++size.num_targets;
    size.max_position_m = std::max(size.max_position_m, p);
    size.max_rotation_rad = std::max(size.max_rotation_rad, r);
    sum_p2 += p * p;
    sum_r2 += r * r;
  }
  if (size.num_targets > 0) {
    size.rms_position_m = std::sqrt(sum_p2 / size.num_targets);
    size.rms_rotation_rad = std::sqrt(sum_r2 / size.num_targets);
  }
  return size;
}

void CompensateProgram(const RobotModel& calibrated,
                       const Eigen::VectorXd& calibrated_values,
                       const RobotModel& nominal,
                       const Eigen::VectorXd& nominal_values,
                       const Eigen::MatrixXd& program,
                       const CompensationOptions& options,
                       CompensationSummary* summary) {
  CHECK(summary != nullptr);
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  if (!CheckSameChain(calibrated, nominal, &error) ||
      !calibrated.CheckParameters(calibrated_values, &error) ||
      !nominal.CheckParameters(nominal_values, &error) ||
      !CheckOptions(calibrated, options, &error)) {
    UserFailure(error, summary);
    return;
  }
  if (program.cols() != calibrated.num_joints()) {
    UserFailure("the program has " + std::to_string(program.cols()) +
                    " joints per row, the robot '" + calibrated.name + "' " +
                    std::to_string(calibrated.num_joints()),
                summary);
    return;
  }
  if (options.ik.marker < 0 || options.ik.marker >= nominal.num_markers()) {
    UserFailure("marker " + std::to_string(options.ik.marker + 1) +
                    " is not a marker of the model",
                summary);
    return;
  }
  *summary = CompensationSummary();
  const Eigen::VectorXd meaning = ProgramMeaningParameters(
      calibrated, calibrated_values, nominal, nominal_values);
  const int n = static_cast<int>(program.rows());
  summary->targets.resize(n);
  const std::vector<const double*> blocks =
      BlockPointers<double>(nominal, meaning.data());
  ParallelFor(
      n, options.num_threads, [&](int64_t begin, int64_t end, int /*thread*/) {
        for (int64_t i = begin; i < end; ++i) {
          const Eigen::VectorXd q = program.row(i).transpose();
          IkTarget& target = summary->targets[i];
          if (!q.allFinite()) {
            // Solved as invalid below.
            target.point.setConstant(NAN);
            continue;
          }
          TargetFrame(nominal, blocks.data(), q.data(), &target.rotation,
                      &target.point, options.ik.marker);
        }
      });
  SolveInverseKinematicsBatch(calibrated, calibrated_values, summary->targets,
                              program, options.ik, options.num_threads,
                              &summary->results);
  summary->seconds = SecondsSince(start);
  Summarize(program, options, summary);
}

void CompensateTargets(const RobotModel& model, const Eigen::VectorXd& values,
                       const std::vector<IkTarget>& targets,
                       const Eigen::MatrixXd& starts,
                       const Eigen::VectorXd& first_start,
                       const CompensationOptions& options,
                       CompensationSummary* summary) {
  CHECK(summary != nullptr);
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  if (!model.CheckParameters(values, &error) ||
      !CheckOptions(model, options, &error)) {
    UserFailure(error, summary);
    return;
  }
  const int n = static_cast<int>(targets.size());
  if (starts.rows() != 0 &&
      (starts.rows() != n || starts.cols() != model.num_joints())) {
    UserFailure("expected " + std::to_string(n) + " start configurations of " +
                    std::to_string(model.num_joints()) + " joints, got " +
                    std::to_string(starts.rows()) + " x " +
                    std::to_string(starts.cols()),
                summary);
    return;
  }
  *summary = CompensationSummary();
  summary->targets = targets;
  if (starts.rows() == n) {
    SolveInverseKinematicsBatch(model, values, targets, starts, options.ik,
                                options.num_threads, &summary->results);
    summary->seconds = SecondsSince(start);
    Summarize(starts, options, summary);
    return;
  }
  Eigen::VectorXd q = first_start;
  if (q.size() == 0) {
    q.resize(model.num_joints());
    for (int j = 0; j < model.num_joints(); ++j) {
      const Link& l = model.links[j];
      const double lo = std::isfinite(l.joint_min) ? l.joint_min : -M_PI;
      const double hi = std::isfinite(l.joint_max) ? l.joint_max : M_PI;
      q[j] = 0.5 * (lo + hi);
    }
  }
  if (!model.CheckJointValues(q, &error)) {
    UserFailure("first start configuration: " + error, summary);
    return;
  }
  Eigen::MatrixXd used(n, model.num_joints());
  summary->results.resize(n);
  for (int i = 0; i < n; ++i) {
    used.row(i) = q.transpose();
    SolveInverseKinematics(model, values, targets[i], q, options.ik,
                           &summary->results[i]);
    if (summary->results[i].status != IkStatus::kInvalid) {
      q = summary->results[i].joints;
    }
  }
  summary->seconds = SecondsSince(start);
  Summarize(used, options, summary);
}

std::vector<IkTarget> IkTargetsFromList(const TargetList& list) {
  const int n = static_cast<int>(list.points.rows());
  std::vector<IkTarget> targets(n);
  for (int i = 0; i < n; ++i) {
    targets[i].point = list.points.row(i).transpose();
    if (list.rotation_vectors.rows() == n) {
      const Eigen::Vector3d v = list.rotation_vectors.row(i).transpose();
      const double angle = v.norm();
      if (!v.allFinite()) {
        // Not the identity (a NaN angle fails "angle > 0"): a target the
        // solver refuses as not finite.
        targets[i].rotation.setConstant(NAN);
      } else if (angle > 0.0) {
        targets[i].rotation =
            Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
      }
    }
  }
  return targets;
}

std::string CompensatedPosesCsvText(const RobotModel& model,
                                    const std::vector<int64_t>& pose_indices,
                                    const CompensationSummary& summary) {
  const int n = static_cast<int>(summary.results.size());
  PoseList poses;
  poses.joints.resize(n, model.num_joints());
  for (int i = 0; i < n; ++i) {
    CHECK_EQ(summary.results[i].joints.size(), model.num_joints());
    poses.joints.row(i) = summary.results[i].joints.transpose();
  }
  poses.pose_indices = pose_indices;
  const std::string text = PosesCsvText(model, poses);
  // Append the two columns to each line of the poses CSV.
  std::ostringstream out;
  out.precision(17);
  std::istringstream in(text);
  std::string line;
  int row = -1;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out << line << "\n";
      continue;
    }
    if (row < 0) {
      out << line << ",status,position_error_m\n";
    } else {
      const InverseKinematicsResult& r = summary.results[row];
      out << line << "," << IkStatusName(r.status) << "," << r.position_error_m
          << "\n";
    }
    ++row;
  }
  CHECK_EQ(row, n);
  return out.str();
}

}  // namespace activecal
