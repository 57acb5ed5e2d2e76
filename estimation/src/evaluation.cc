// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/evaluation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/plane_constraints.h"
#include "activecal/core/point_constraints.h"

namespace activecal {

ErrorStatistics ComputeErrorStatistics(std::vector<double> magnitudes) {
  ErrorStatistics s;
  s.count = static_cast<int>(magnitudes.size());
  if (magnitudes.empty()) return s;
  double sum = 0.0, squares = 0.0;
  for (double m : magnitudes) {
    sum += m;
    squares += m * m;
  }
  s.mean = sum / s.count;
  s.rms = std::sqrt(squares / s.count);
  std::sort(magnitudes.begin(), magnitudes.end());
  s.max = magnitudes.back();
  // Nearest rank: the smallest value with at least 95% at or below it.
  const size_t rank =
      static_cast<size_t>(std::ceil(0.95 * magnitudes.size())) - 1;
  s.p95 = magnitudes[std::min(rank, magnitudes.size() - 1)];
  return s;
}

namespace {

// The fixed points' rows of EvaluateModel (evaluation.h): errors about the
// refitted points, appended to the position and distance magnitudes.
void EvaluatePointRows(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const std::vector<Measurement>& measurements,
                       EvaluationSummary* summary,
                       std::vector<double>* positions, Eigen::Vector3d* squares,
                       Eigen::Vector3d* sum, std::vector<double>* distances) {
  if (!HasPointRows(measurements)) return;
  const std::vector<std::string> labels = PointLabels(measurements);
  const std::vector<Eigen::Vector3d> centre =
      MeanPointPositions(model, parameters, measurements, labels);
  std::vector<std::vector<double>> spread(labels.size());
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    if (m.type == MeasurementType::kPoint) {
      const Eigen::Vector3d e =
          MeasuredPoint(model, parameters, m.joints, m.marker) -
          centre[LabelIndex(labels, m.point)];
      summary->position_errors[i] = e;
      positions->push_back(e.norm());
      spread[LabelIndex(labels, m.point)].push_back(e.norm());
      *squares += e.cwiseAbs2();
      *sum += e;
    } else if (m.type == MeasurementType::kPointDistance) {
      const double e = (centre[LabelIndex(labels, m.point)] -
                        centre[LabelIndex(labels, m.point2)])
                           .norm() -
                       m.distance;
      summary->distance_errors_m[i] = e;
      distances->push_back(std::abs(e));
    }
  }
  summary->point_labels = labels;
  summary->point_coordinates = centre;
  for (const std::vector<double>& s : spread) {
    summary->point_spread.push_back(ComputeErrorStatistics(s));
  }
}

// The plane rows of EvaluateModel: each plane refitted, the rows' signed
// distances from it and the flatness per plane.
bool EvaluatePlaneRows(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const std::vector<Measurement>& measurements,
                       EvaluationSummary* summary, std::string* error) {
  const std::vector<std::string> labels = PlaneLabels(measurements);
  if (labels.empty()) return true;
  if (!CheckPlaneLabels(measurements, error) ||
      !FitPlanes(model, parameters, measurements, labels,
                 &summary->plane_parameters, error)) {
    return false;
  }
  std::vector<std::vector<double>> flatness(labels.size());
  std::vector<double> all;
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    if (m.type != MeasurementType::kPlane) continue;
    const size_t k = LabelIndex(labels, m.plane);
    const double e = PlaneResidual(
        summary->plane_parameters[k],
        MeasuredPoint(model, parameters, m.joints, m.marker), m.probe_radius_m);
    summary->plane_errors_m[i] = e;
    flatness[k].push_back(std::abs(e));
    all.push_back(std::abs(e));
  }
  summary->plane_labels = labels;
  for (const std::vector<double>& f : flatness) {
    summary->plane_flatness.push_back(ComputeErrorStatistics(f));
  }
  summary->plane = ComputeErrorStatistics(all);
  return true;
}

}  // namespace

bool EvaluateModel(const RobotModel& model, const Eigen::VectorXd& parameters,
                   const std::vector<Measurement>& measurements,
                   EvaluationSummary* summary) {
  return EvaluateCorrectedModel(model, parameters, LearnedCorrection(),
                                measurements, summary);
}

bool EvaluateCorrectedModel(const RobotModel& model,
                            const Eigen::VectorXd& parameters,
                            const LearnedCorrection& correction,
                            const std::vector<Measurement>& measurements,
                            EvaluationSummary* summary) {
  *summary = EvaluationSummary();
  std::string error;
  if (!model.Validate(&error) || !model.CheckParameters(parameters, &error)) {
    summary->message = error;
    return false;
  }
  if (!correction.empty() && !correction.Validate(&model, &error)) {
    summary->message = "learned correction: " + error;
    return false;
  }
  const int n = static_cast<int>(measurements.size());
  summary->num_measurements = n;
  summary->position_errors.assign(n, Eigen::Vector3d::Zero());
  summary->rotation_errors_rad.assign(n, 0.0);
  summary->distance_errors_m.assign(n, 0.0);
  summary->plane_errors_m.assign(n, 0.0);
  std::vector<double> positions, rotations, distances;
  Eigen::Vector3d squares = Eigen::Vector3d::Zero(), sum = squares;
  for (int i = 0; i < n; ++i) {
    const Measurement& m = measurements[i];
    if (!CheckMeasurement(model, m, &error)) {
      summary->message = "measurement " + std::to_string(i) + ": " + error;
      return false;
    }
    if (m.involves_points()) continue;  // below
    const Measurement p =
        PredictCorrectedMeasurement(model, parameters, correction, m);
    if (m.type == MeasurementType::kDistance) {
      summary->distance_errors_m[i] = p.distance - m.distance;
      distances.push_back(std::abs(p.distance - m.distance));
      continue;
    }
    const Eigen::Vector3d e = p.position - m.position;
    summary->position_errors[i] = e;
    positions.push_back(e.norm());
    squares += e.cwiseAbs2();
    sum += e;
    if (m.type == MeasurementType::kPose) {
      auto rotation = [](const Eigen::Vector3d& v) -> Eigen::Matrix3d {
        const double a = v.norm();
        return a > 0 ? Eigen::AngleAxisd(a, v / a).toRotationMatrix()
                     : Eigen::Matrix3d::Identity();
      };
      const double angle = Eigen::AngleAxisd(rotation(m.rotation).transpose() *
                                             rotation(p.rotation))
                               .angle();
      summary->rotation_errors_rad[i] = angle;
      rotations.push_back(angle);
    }
  }
  EvaluatePointRows(model, parameters, measurements, summary, &positions,
                    &squares, &sum, &distances);
  if (!EvaluatePlaneRows(model, parameters, measurements, summary, &error)) {
    summary->message = error;
    return false;
  }
  summary->position = ComputeErrorStatistics(positions);
  if (!positions.empty()) {
    summary->rmse_xyz_m = (squares / positions.size()).cwiseSqrt();
    summary->mean_xyz_m = sum / positions.size();
  }
  summary->rotation = ComputeErrorStatistics(rotations);
  summary->distance = ComputeErrorStatistics(distances);
  summary->success = true;
  std::ostringstream msg;
  msg << "evaluated " << n << " measurements";
  summary->message = msg.str();
  return true;
}

const char* PostureGroupName(PostureGroup group) {
  constexpr const char* kNames[] = {"repeated", "new", "out_of_range"};
  return EnumToString(kNames, group);
}

std::vector<PostureGroup> ClassifyPostures(
    const RobotModel& model, const std::vector<Measurement>& training,
    const std::vector<Measurement>& measurements,
    const PostureGroupOptions& options) {
  const int n = model.num_joints();
  std::vector<Eigen::VectorXd> poses;
  for (const Measurement& m : training) {
    poses.push_back(m.joints);
    if (m.type == MeasurementType::kDistance) poses.push_back(m.joints2);
  }
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(
                      n, std::numeric_limits<double>::infinity()),
                  hi = -lo;
  for (const Eigen::VectorXd& q : poses) {
    if (q.size() != n) continue;
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  Eigen::VectorXd tolerance(n);
  for (int j = 0; j < n; ++j) {
    tolerance[j] = model.links[j].joint_type == JointType::kPrismatic
                       ? options.prismatic_tolerance_m
                       : options.revolute_tolerance_rad;
  }
  auto group_of = [&](const Eigen::VectorXd& q) {
    if (q.size() != n) return PostureGroup::kOutOfRange;
    for (const Eigen::VectorXd& t : poses) {
      if (t.size() == n &&
          ((q - t).cwiseAbs().array() <= tolerance.array()).all()) {
        return PostureGroup::kRepeated;
      }
    }
    if ((q.array() >= lo.array()).all() && (q.array() <= hi.array()).all()) {
      return PostureGroup::kNew;
    }
    return PostureGroup::kOutOfRange;
  };
  std::vector<PostureGroup> groups;
  for (const Measurement& m : measurements) {
    PostureGroup g = group_of(m.joints);
    if (m.type == MeasurementType::kDistance) {
      g = std::max(g, group_of(m.joints2));
    }
    groups.push_back(g);
  }
  return groups;
}

std::string EvaluationSummary::PointSpreadText() const {
  std::string text;
  char line[512];
  for (size_t k = 0; k < point_labels.size(); ++k) {
    const ErrorStatistics& s = point_spread[k];
    const Eigen::Vector3d& c = point_coordinates[k];
    std::snprintf(line, sizeof(line),
                  "  point %s (%d rows, refitted at %.6f, %.6f, %.6f m): "
                  "distance to the point's mean %.3f mm mean, RMS %.3f mm, "
                  "max %.3f mm\n",
                  point_labels[k].c_str(), s.count, c.x(), c.y(), c.z(),
                  s.mean * 1e3, s.rms * 1e3, s.max * 1e3);
    text += line;
  }
  for (size_t k = 0; k < plane_labels.size(); ++k) {
    const ErrorStatistics& s = plane_flatness[k];
    const Eigen::Vector4d& p = plane_parameters[k];
    std::snprintf(line, sizeof(line),
                  "  plane %s (%d rows, refitted: normal %.6f, %.6f, %.6f, "
                  "offset %.6f m): flatness RMS %.3f mm, max %.3f mm\n",
                  plane_labels[k].c_str(), s.count, p[0], p[1], p[2], p[3],
                  s.rms * 1e3, s.max * 1e3);
    text += line;
  }
  return text;
}

std::string EvaluationSummary::BriefReport() const {
  std::ostringstream out;
  out.precision(4);
  out << "activecal evaluation: " << num_measurements << " measurements\n";
  if (position.count > 0) {
    out << "  position (" << position.count << "): RMSE " << position.rms * 1e3
        << " mm (x " << rmse_xyz_m.x() * 1e3 << ", y " << rmse_xyz_m.y() * 1e3
        << ", z " << rmse_xyz_m.z() * 1e3 << "), mean " << position.mean * 1e3
        << " mm, 95% " << position.p95 * 1e3 << " mm, max "
        << position.max * 1e3 << " mm\n";
  }
  if (rotation.count > 0) {
    const double deg = 180.0 / M_PI;
    out << "  orientation (" << rotation.count << "): RMS "
        << rotation.rms * deg << " deg, 95% " << rotation.p95 * deg
        << " deg, max " << rotation.max * deg << " deg\n";
  }
  if (distance.count > 0) {
    out << "  distance (" << distance.count << "): RMS " << distance.rms * 1e3
        << " mm, max " << distance.max * 1e3 << " mm\n";
  }
  return out.str();
}

}  // namespace activecal
