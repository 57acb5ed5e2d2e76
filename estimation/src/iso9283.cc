// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/iso9283.h"

#include <cmath>

namespace activecal {
namespace {

bool IsRotation(const Eigen::Matrix3d& r) {
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() <= 1e-6 &&
         r.determinant() > 0;
}

// The rotation vector of `r` (rad), by Eigen's angle-axis of a matrix.
Eigen::Vector3d Log(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

}  // namespace

bool Iso9283Pose(const Iso9283Sample& commanded,
                 const std::vector<Iso9283Sample>& attained,
                 Iso9283PoseResult* result, std::string* error) {
  *result = Iso9283PoseResult();
  const int n = static_cast<int>(attained.size());
  if (n < 2) {
    *error =
        "ISO 9283 needs at least 2 cycles to a pose, got " + std::to_string(n);
    return false;
  }
  if (!IsRotation(commanded.rotation)) {
    *error = "the commanded orientation is not a rotation";
    return false;
  }
  for (int j = 0; j < n; ++j) {
    if (!IsRotation(attained[j].rotation)) {
      *error = "cycle " + std::to_string(j + 1) +
               ": the attained orientation is not a rotation";
      return false;
    }
  }
  Iso9283PoseResult& r = *result;
  r.num_cycles = n;
  std::vector<Eigen::Vector3d> d(n);
  for (int j = 0; j < n; ++j) {
    r.barycentre_m += attained[j].position / n;
    d[j] = Log(attained[j].rotation * commanded.rotation.transpose());
    r.ap_rad += d[j] / n;
  }
  r.ap_xyz_m = r.barycentre_m - commanded.position;
  r.ap_p_m = r.ap_xyz_m.norm();
  std::vector<double> l(n);
  for (int j = 0; j < n; ++j) {
    l[j] = (attained[j].position - r.barycentre_m).norm();
    r.l_bar_m += l[j] / n;
  }
  double sum_l = 0.0;
  Eigen::Vector3d sum_d = Eigen::Vector3d::Zero();
  for (int j = 0; j < n; ++j) {
    sum_l += (l[j] - r.l_bar_m) * (l[j] - r.l_bar_m);
    sum_d += (d[j] - r.ap_rad).cwiseAbs2();
  }
  r.s_l_m = std::sqrt(sum_l / (n - 1));
  r.rp_l_m = r.l_bar_m + 3 * r.s_l_m;
  r.s_rad = (sum_d / (n - 1)).cwiseSqrt();
  r.rp_rad = 3 * r.s_rad;
  return true;
}

}  // namespace activecal
