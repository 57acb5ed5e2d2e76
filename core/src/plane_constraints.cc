// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/plane_constraints.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>

#include "activecal/core/kinematics.h"
#include "activecal/core/point_constraints.h"
#include "activecal/core/random.h"

namespace activecal {

std::vector<std::string> PlaneLabels(
    const std::vector<Measurement>& measurements) {
  std::vector<std::string> labels;
  for (const Measurement& m : measurements) {
    if (m.type == MeasurementType::kPlane &&
        std::find(labels.begin(), labels.end(), m.plane) == labels.end()) {
      labels.push_back(m.plane);
    }
  }
  return labels;
}

bool CheckPlaneLabels(const std::vector<Measurement>& measurements,
                      std::string* error) {
  std::map<std::string, int> count;
  for (const Measurement& m : measurements) {
    if (m.type == MeasurementType::kPlane) ++count[m.plane];
  }
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    if (m.type != MeasurementType::kPlane || count[m.plane] >= 3) continue;
    if (error) {
      *error = "measurement " + std::to_string(i) + ": plane '" + m.plane +
               "' has " + std::to_string(count[m.plane]) +
               (count[m.plane] == 1 ? " row" : " rows") +
               " only: a plane needs at least three touches (its 3 "
               "parameters absorb fewer)";
    }
    return false;
  }
  return true;
}

double PlaneResidual(const Eigen::Vector4d& plane, const Eigen::Vector3d& p,
                     double radius) {
  return plane.head<3>().dot(p) - plane[3] - radius;
}

Eigen::Matrix<double, 3, 2> PlaneTangentBasis(const Eigen::Vector3d& n) {
  // The axis least aligned with n, crossed with it: never parallel.
  int k = 0;
  n.cwiseAbs().minCoeff(&k);
  const Eigen::Vector3d a = Eigen::Vector3d::Unit(k);
  Eigen::Matrix<double, 3, 2> basis;
  basis.col(0) = n.cross(a).normalized();
  basis.col(1) = n.cross(basis.col(0));
  return basis;
}

bool FitPlane(const std::vector<Eigen::Vector3d>& centres,
              const std::vector<double>& radii,
              const std::vector<Eigen::Vector3d>& approach,
              Eigen::Vector4d* plane, std::string* error) {
  const int n = static_cast<int>(centres.size());
  if (n < 3) {
    if (error) *error = "a plane needs at least three touches";
    return false;
  }
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : centres) c += p;
  c /= n;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double extent = 0.0;
  for (const Eigen::Vector3d& p : centres) {
    scatter += (p - c) * (p - c).transpose();
    extent = std::max(extent, (p - c).norm());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  // Eigenvalues ascending: the middle one is the spread across the line
  // the touches would lie on.
  if (!(extent > 0) ||
      std::sqrt(std::max(0.0, eigen.eigenvalues()[1]) / n) < 1e-9 * extent ||
      std::sqrt(std::max(0.0, eigen.eigenvalues()[1]) / n) < 1e-12) {
    if (error) {
      *error =
          "the touches lie on a line (or at one place): they do not "
          "determine a plane";
    }
    return false;
  }
  Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  double side = 0.0;
  for (int i = 0; i < n && i < static_cast<int>(approach.size()); ++i) {
    side += normal.dot(approach[i]);
  }
  if (std::abs(side) <= 1e-9 * n) side = -normal.dot(c);
  if (std::abs(side) <= 1e-12) {
    int k = 0;
    normal.cwiseAbs().maxCoeff(&k);
    side = normal[k];
  }
  if (side < 0) normal = -normal;
  auto radius = [&](int i) {
    return i < static_cast<int>(radii.size()) ? radii[i] : 0.0;
  };
  double d = 0.0;
  for (int i = 0; i < n; ++i) d += normal.dot(centres[i]) - radius(i);
  d /= n;
  // Radii that differ between touches: Gauss-Newton on (tangent step, d)
  // from there (equal radii: already the minimum, the step is zero).
  for (int it = 0; it < 10; ++it) {
    const Eigen::Matrix<double, 3, 2> b = PlaneTangentBasis(normal);
    Eigen::MatrixXd J(n, 3);
    Eigen::VectorXd r(n);
    for (int i = 0; i < n; ++i) {
      J(i, 0) = b.col(0).dot(centres[i]);
      J(i, 1) = b.col(1).dot(centres[i]);
      J(i, 2) = -1.0;
      r[i] = normal.dot(centres[i]) - d - radius(i);
    }
    const Eigen::Vector3d step = -J.colPivHouseholderQr().solve(r);
    if (!step.allFinite()) break;
    normal = (normal + b * step.head<2>()).normalized();
    d += step[2];
    if (step.norm() < 1e-15) break;
  }
  *plane << normal, d;
  return true;
}

void OrientPlanesLike(const Eigen::VectorXd& reference,
                      const std::vector<Measurement>& measurements,
                      const std::vector<std::string>& labels,
                      Eigen::VectorXd* planes) {
  for (size_t k = 0; k < labels.size(); ++k) {
    double* plane = planes->data() + 4 * k;
    if (Eigen::Map<const Eigen::Vector3d>(plane).dot(
            reference.segment<3>(4 * k)) >= 0) {
      continue;
    }
    double radius = -1.0;
    bool one_radius = true;
    for (const Measurement& m : measurements) {
      if (m.type != MeasurementType::kPlane || m.plane != labels[k]) continue;
      if (radius >= 0 && m.probe_radius_m != radius) one_radius = false;
      radius = m.probe_radius_m;
    }
    if (!one_radius) continue;
    for (int a = 0; a < 3; ++a) plane[a] = -plane[a];
    plane[3] = -plane[3] - 2 * radius;
  }
}

bool FitPlanes(const RobotModel& model, const Eigen::VectorXd& parameters,
               const std::vector<Measurement>& measurements,
               const std::vector<std::string>& labels,
               std::vector<Eigen::Vector4d>* planes, std::string* error) {
  planes->assign(labels.size(), Eigen::Vector4d::Zero());
  for (size_t k = 0; k < labels.size(); ++k) {
    std::vector<Eigen::Vector3d> centres, approach;
    std::vector<double> radii;
    for (const Measurement& m : measurements) {
      if (m.type != MeasurementType::kPlane || m.plane != labels[k]) continue;
      Eigen::Matrix3d R, R_marker;
      Eigen::Vector3d flange, centre;
      ForwardKinematics(model, parameters, m.joints, &R, &flange);
      TargetFrame(model, parameters, m.joints, &R_marker, &centre, m.marker);
      centres.push_back(centre);
      // The stylus from the ball back to the flange; a model with the
      // ball within 1 cm of the flange (a nominal without the probe's
      // offset, or a start fitted from there): the marker frame's z axis
      // (the tool frame's, with the marker's angles), which a stylus
      // points along.
      const Eigen::Vector3d back = flange - centres.back();
      approach.push_back(
          back.norm() >= 0.01 ? back : Eigen::Vector3d(-R_marker.col(2)));
      radii.push_back(m.probe_radius_m);
    }
    std::string why;
    if (!FitPlane(centres, radii, approach, &(*planes)[k], &why)) {
      if (error) *error = "plane '" + labels[k] + "': " + why;
      return false;
    }
  }
  return true;
}

std::vector<Measurement> SimulatePlaneTouches(const RobotModel& model,
                                              const Eigen::VectorXd& parameters,
                                              const std::string& label,
                                              const Eigen::Vector4d& plane,
                                              double radius_m, int num_touches,
                                              uint64_t seed, int marker) {
  Random random(seed);
  std::vector<Measurement> rows;
  const int n = model.num_joints();
  for (int draw = 0;
       draw < 200 * num_touches && static_cast<int>(rows.size()) < num_touches;
       ++draw) {
    Eigen::VectorXd q(n);
    for (int j = 0; j < n; ++j) {
      const Link& link = model.links[j];
      q[j] =
          link.joint_min + (link.joint_max - link.joint_min) * random.Uniform();
    }
    const Eigen::Vector3d c = MeasuredPoint(model, parameters, q, marker);
    const Eigen::Vector3d target =
        c - PlaneResidual(plane, c, radius_m) * plane.head<3>();
    if (!ReachPoint(model, parameters, marker, target, &q, 1e-12, 100))
      continue;
    if (!model.CheckJointValues(q, nullptr)) continue;
    Eigen::Matrix3d R;
    Eigen::Vector3d flange;
    ForwardKinematics(model, parameters, q, &R, &flange);
    const Eigen::Vector3d centre = MeasuredPoint(model, parameters, q, marker);
    if (plane.head<3>().dot(flange - centre) <= 0) continue;
    Measurement m;
    m.type = MeasurementType::kPlane;
    m.plane = label;
    m.probe_radius_m = radius_m;
    m.marker = marker;
    m.joints = q;
    rows.push_back(m);
  }
  return rows;
}

}  // namespace activecal
