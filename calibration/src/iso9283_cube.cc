// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/iso9283_cube.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "activecal/io/csv_files.h"

namespace activecal {
namespace {

bool IsRotation(const Eigen::Matrix3d& r) {
  return (r.transpose() * r - Eigen::Matrix3d::Identity())
                 .cwiseAbs()
                 .maxCoeff() <= 1e-9 &&
         r.determinant() > 0;
}

bool Fail(const std::string& message, Iso9283CubeSummary* summary) {
  summary->ok = false;
  summary->message = message;
  return false;
}

// The numbers of a comma-separated list; false naming the bad entry.
bool Numbers(const std::string& text, const std::string& what,
             std::vector<double>* values, std::string* error) {
  values->clear();
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end == item.c_str() || *end != '\0' ||
        !std::isfinite(v)) {
      *error = what + ": value " + std::to_string(values->size() + 1) +
               " is '" + item + "', not a number";
      return false;
    }
    values->push_back(v);
  }
  return true;
}

bool Quaternion(const double* v, const std::string& what, Eigen::Matrix3d* r,
                std::string* error) {
  const Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
  if (!(std::abs(q.norm() - 1.0) <= 1e-3)) {
    char norm[32];
    std::snprintf(norm, sizeof(norm), "%.6g", q.norm());
    *error = what + ": the quaternion qw,qx,qy,qz has norm " + norm +
             ", not 1 (to 1e-3)";
    return false;
  }
  *r = q.normalized().toRotationMatrix();
  return true;
}

// Columns after each row of a CSV text (header first): `header` after the
// header, cells[k] after data row k.
std::string WithColumns(const std::string& text, const std::string& header,
                        const std::vector<std::string>& cells) {
  std::stringstream in(text);
  std::string line, out;
  int row = -1;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out += line + "\n";
      continue;
    }
    out += line + "," + (row < 0 ? header : cells[row]) + "\n";
    ++row;
  }
  return out;
}

std::string Shortest(double v) {
  char buffer[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof(buffer), "%.*g", digits, v);
    if (std::strtod(buffer, nullptr) == v) break;
  }
  return buffer;
}

}  // namespace

bool ParseIso9283Cube(const std::string& cube, const std::string& orientation,
                      Iso9283CubeOptions* options, std::string* error) {
  std::vector<double> v;
  if (!Numbers(cube, "--iso9283_cube", &v, error)) return false;
  if (v.size() != 4 && v.size() != 8) {
    *error =
        "--iso9283_cube: expected cx,cy,cz,edge_m or cx,cy,cz,edge_m,qw,"
        "qx,qy,qz (m, base frame), got " +
        std::to_string(v.size()) + " values";
    return false;
  }
  options->centre_m = Eigen::Vector3d(v[0], v[1], v[2]);
  options->edge_m = v[3];
  if (!(v[3] > 0)) {
    *error = "--iso9283_cube: the edge (value 4) must be > 0 m";
    return false;
  }
  if (v.size() == 8 && !Quaternion(&v[4], "--iso9283_cube (the cube's axes)",
                                   &options->cube_rotation, error)) {
    return false;
  }
  if (!orientation.empty()) {
    if (!Numbers(orientation, "--iso9283_orientation", &v, error)) return false;
    if (v.size() != 4) {
      *error = "--iso9283_orientation: expected qw,qx,qy,qz, got " +
               std::to_string(v.size()) + " values";
      return false;
    }
    if (!Quaternion(v.data(), "--iso9283_orientation", &options->tool_rotation,
                    error)) {
      return false;
    }
    options->has_tool_rotation = true;
  }
  return true;
}

std::string Iso9283CubePosesCsvText(const RobotModel& model,
                                    const Iso9283CubeSummary& summary) {
  PoseList poses;
  poses.joints = summary.joints;
  poses.pose_indices = summary.targets.pose_indices;
  Eigen::Quaterniond q(summary.tool_rotation);
  if (q.w() < 0) q.coeffs() *= -1;
  std::vector<std::string> cells;
  for (size_t k = 0; k < summary.labels.size(); ++k) {
    const Eigen::Vector3d& p = summary.points_m[k];
    cells.push_back(summary.labels[k] + "," + Shortest(p.x()) + "," +
                    Shortest(p.y()) + "," + Shortest(p.z()) + "," +
                    Shortest(q.w()) + "," + Shortest(q.x()) + "," +
                    Shortest(q.y()) + "," + Shortest(q.z()));
  }
  return WithColumns(PosesCsvText(model, poses),
                     "pose,commanded_x_m,commanded_y_m,commanded_z_m,"
                     "commanded_qw,commanded_qx,commanded_qy,commanded_qz",
                     cells);
}

std::string Iso9283CubeTargetsCsvText(const RobotModel& model,
                                      const Iso9283CubeSummary& summary) {
  return WithColumns(TargetsCsvText(model, summary.targets), "pose",
                     summary.labels);
}

void Iso9283CubePoints(const Iso9283CubeOptions& o,
                       std::vector<Eigen::Vector3d>* points,
                       std::vector<Eigen::Vector3d>* corners) {
  const double h = o.edge_m / 2;
  const Eigen::Vector3d u = o.cube_rotation.col(0), v = o.cube_rotation.col(1),
                        w = o.cube_rotation.col(2);
  const Eigen::Vector3d c1 = o.centre_m + h * (-u - v - w);
  const Eigen::Vector3d c2 = o.centre_m + h * (u - v - w);
  const Eigen::Vector3d c7 = o.centre_m + h * (u + v + w);
  const Eigen::Vector3d c8 = o.centre_m + h * (-u + v + w);
  const double f = o.corner_fraction;
  *corners = {c1, c2, c7, c8};
  *points = {o.centre_m, c1 + f * (c7 - c1), c2 + f * (c8 - c2),
             c7 + f * (c1 - c7), c8 + f * (c2 - c8)};
}

bool DesignIso9283Cube(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const Iso9283CubeOptions& options,
                       Iso9283CubeSummary* summary) {
  *summary = Iso9283CubeSummary();
  if (!(options.edge_m > 0) || !std::isfinite(options.edge_m)) {
    return Fail("the cube's edge must be > 0 m", summary);
  }
  if (!options.centre_m.allFinite()) {
    return Fail("the cube's centre is not finite", summary);
  }
  if (!IsRotation(options.cube_rotation) ||
      (options.has_tool_rotation && !IsRotation(options.tool_rotation))) {
    return Fail("an orientation is not a rotation", summary);
  }
  if (!(options.corner_fraction >= 0.08 && options.corner_fraction <= 0.12)) {
    return Fail(
        "the corner fraction must be in [0.08, 0.12] (ISO 9283: 10 +- 2 % of "
        "the diagonal)",
        summary);
  }
  if (options.marker < 0 || options.marker >= model.num_markers()) {
    return Fail("no marker " + std::to_string(options.marker + 1), summary);
  }
  Iso9283CubePoints(options, &summary->points_m, &summary->corners_m);
  summary->labels = {"P1", "P2", "P3", "P4", "P5"};
  // The base frame in the device's.
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  Eigen::Matrix3d rb;
  Eigen::Vector3d tb;
  LinkTransform(model.base, blocks[0], 0.0, &rb, &tb);
  Eigen::VectorXd middle(model.num_joints());
  for (int j = 0; j < model.num_joints(); ++j) {
    const Link& l = model.links[j];
    middle[j] = std::isfinite(l.joint_min) && std::isfinite(l.joint_max)
                    ? 0.5 * (l.joint_min + l.joint_max)
                    : 0.0;
  }
  if (options.has_tool_rotation) {
    summary->tool_rotation = options.tool_rotation;
  } else {
    Eigen::Matrix3d r;
    Eigen::Vector3d t;
    TargetFrame(model, parameters, middle, &r, &t, options.marker);
    summary->tool_rotation = rb.transpose() * r;
  }
  std::vector<IkTarget> targets;
  TargetList& list = summary->targets;
  list.points.resize(5, 3);
  list.rotation_vectors.resize(5, 3);
  for (int k = 0; k < 5; ++k) {
    IkTarget t;
    t.point = rb * summary->points_m[k] + tb;
    t.rotation = rb * summary->tool_rotation;
    targets.push_back(t);
    const Eigen::AngleAxisd aa(t.rotation);
    list.pose_indices.push_back(k + 1);
    list.points.row(k) = t.point.transpose();
    list.rotation_vectors.row(k) = (aa.angle() * aa.axis()).transpose();
  }
  CompensationOptions co;
  co.ik.match = IkMatch::kPose;
  co.ik.marker = options.marker;
  co.check = options.check;
  CompensateTargets(model, parameters, targets, Eigen::MatrixXd(), middle, co,
                    &summary->solve);
  if (summary->solve.termination_type == TerminationType::kUserFailure) {
    return Fail(summary->solve.message, summary);
  }
  summary->joints.resize(5, model.num_joints());
  for (int k = 0; k < 5; ++k) {
    const InverseKinematicsResult& r = summary->solve.results[k];
    summary->joints.row(k) = r.joints.transpose();
    if (r.status != IkStatus::kConverged) {
      char point[96];
      std::snprintf(point, sizeof(point), "(%.1f, %.1f, %.1f) mm",
                    summary->points_m[k].x() * 1e3,
                    summary->points_m[k].y() * 1e3,
                    summary->points_m[k].z() * 1e3);
      return Fail(summary->labels[k] + " at " + point +
                      " (base frame): " + IkStatusName(r.status) +
                      (r.message.empty() ? "" : ": " + r.message),
                  summary);
    }
  }
  list.start_joints = summary->joints;
  summary->ok = true;
  return true;
}

std::string Iso9283CubeSummary::TableText() const {
  std::string out =
      "ISO 9283 cube test poses (base frame; P2-P5 on the diagonals of the "
      "plane C1-C2-C7-C8):\n  pose       x mm       y mm       z mm  status "
      "    error mm\n";
  for (size_t k = 0; k < labels.size() && k < solve.results.size(); ++k) {
    char line[160];
    std::snprintf(
        line, sizeof(line), "  %-4s %10.3f %10.3f %10.3f  %-10s %.2e\n",
        labels[k].c_str(), points_m[k].x() * 1e3, points_m[k].y() * 1e3,
        points_m[k].z() * 1e3, IkStatusName(solve.results[k].status),
        solve.results[k].position_error_m * 1e3);
    out += line;
  }
  return out;
}

}  // namespace activecal
