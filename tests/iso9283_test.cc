// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// ISO 9283 7.2 pose accuracy and repeatability (estimation/iso9283.h)
// against an independent computation: the attained orientations are built
// from known deviations by quaternions (not matrices), the position
// figures summed axis by axis in long double, and a worked example
// (docs/iso9283.md) by hand.

#include "activecal/estimation/iso9283.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "activecal/core/random.h"

namespace activecal {
namespace {

// exp(d) as a quaternion, from the angle and axis.
Eigen::Quaterniond Exp(const Eigen::Vector3d& d) {
  const double angle = d.norm();
  if (angle == 0) return Eigen::Quaterniond::Identity();
  const Eigen::Vector3d axis = d / angle;
  return Eigen::Quaterniond(std::cos(angle / 2), std::sin(angle / 2) * axis.x(),
                            std::sin(angle / 2) * axis.y(),
                            std::sin(angle / 2) * axis.z());
}

void CheckAgainstIndependent(const Eigen::Quaterniond& commanded_q,
                             uint64_t seed) {
  Random random(seed);
  Iso9283Sample commanded;
  commanded.position = Eigen::Vector3d(0.8, -0.2, 0.5);
  commanded.rotation = commanded_q.toRotationMatrix();
  const int n = 30;
  std::vector<Iso9283Sample> attained(n);
  std::vector<Eigen::Vector3d> d(n);
  const Eigen::Vector3d offset(4e-4, -2e-4, 1e-4);
  const Eigen::Vector3d bias(2e-4, -1e-4, 3e-4);
  for (int j = 0; j < n; ++j) {
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = 5e-5 * random.Gaussian();
    attained[j].position = commanded.position + offset + p;
    for (int a = 0; a < 3; ++a) d[j][a] = bias[a] + 1e-4 * random.Gaussian();
    attained[j].rotation = (Exp(d[j]) * commanded_q).toRotationMatrix();
  }
  Iso9283PoseResult r;
  std::string error;
  ASSERT_TRUE(Iso9283Pose(commanded, attained, &r, &error)) << error;
  // Position, axis by axis in long double.
  long double mean[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    for (int j = 0; j < n; ++j) mean[a] += attained[j].position[a];
    mean[a] /= n;
  }
  long double ap2 = 0;
  for (int a = 0; a < 3; ++a) {
    const long double e = mean[a] - commanded.position[a];
    ap2 += e * e;
  }
  EXPECT_NEAR(r.ap_p_m, static_cast<double>(std::sqrt(ap2)), 1e-15);
  std::vector<long double> l(n);
  long double l_bar = 0;
  for (int j = 0; j < n; ++j) {
    long double s = 0;
    for (int a = 0; a < 3; ++a) {
      s += (attained[j].position[a] - mean[a]) *
           (attained[j].position[a] - mean[a]);
    }
    l[j] = std::sqrt(s);
    l_bar += l[j];
  }
  l_bar /= n;
  long double var = 0;
  for (int j = 0; j < n; ++j) var += (l[j] - l_bar) * (l[j] - l_bar);
  const long double rp_l = l_bar + 3 * std::sqrt(var / (n - 1));
  EXPECT_NEAR(r.rp_l_m, static_cast<double>(rp_l), 1e-15);
  // Orientation: the known deviations.
  for (int a = 0; a < 3; ++a) {
    long double m = 0;
    for (int j = 0; j < n; ++j) m += d[j][a];
    m /= n;
    long double v = 0;
    for (int j = 0; j < n; ++j) v += (d[j][a] - m) * (d[j][a] - m);
    EXPECT_NEAR(r.ap_rad[a], static_cast<double>(m), 1e-12) << a;
    EXPECT_NEAR(r.rp_rad[a], static_cast<double>(3 * std::sqrt(v / (n - 1))),
                1e-12)
        << a;
  }
}

TEST(Iso9283Test, MatchesAnIndependentComputation) {
  CheckAgainstIndependent(Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized(),
                          1);
}

// Pitch +-90 deg (where roll-pitch-yaw angles are singular) and a whole
// turn about z: the figures are the same as anywhere else.
TEST(Iso9283Test, SingularPitchAndWholeTurns) {
  for (double pitch : {M_PI / 2, -M_PI / 2}) {
    CheckAgainstIndependent(
        Eigen::Quaterniond(Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY())),
        2);
  }
  CheckAgainstIndependent(
      Eigen::Quaterniond(Eigen::AngleAxisd(2 * M_PI, Eigen::Vector3d::UnitZ())),
      3);
}

// docs/iso9283.md's worked example: 3 cycles, by hand.
TEST(Iso9283Test, WorkedExample) {
  Iso9283Sample c;
  c.position = Eigen::Vector3d(1.0, 0.0, 0.5);
  std::vector<Iso9283Sample> a(3);
  a[0].position = Eigen::Vector3d(1.0003, 0.0001, 0.5);
  a[1].position = Eigen::Vector3d(1.0005, -0.0001, 0.5);
  a[2].position = Eigen::Vector3d(1.0004, 0.0, 0.5003);
  const double rz[3] = {1e-4, 3e-4, 2e-4};  // rad about z
  for (int j = 0; j < 3; ++j) {
    a[j].rotation =
        Eigen::AngleAxisd(rz[j], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  Iso9283PoseResult r;
  std::string error;
  ASSERT_TRUE(Iso9283Pose(c, a, &r, &error)) << error;
  // Barycentre (1.0004, 0, 0.5001): AP_p = sqrt(0.4^2 + 0.1^2) mm.
  EXPECT_NEAR(r.ap_p_m, std::sqrt(0.17) * 1e-3, 1e-12);
  // l = |(-0.1, 0.1, -0.1)|, |(0.1, -0.1, -0.1)|, |(0, 0, 0.2)| mm.
  const double l1 = std::sqrt(0.03) * 1e-3, l3 = 0.2e-3;
  const double l_bar = (2 * l1 + l3) / 3;
  const double s_l = std::sqrt(
      (2 * (l1 - l_bar) * (l1 - l_bar) + (l3 - l_bar) * (l3 - l_bar)) / 2);
  EXPECT_NEAR(r.rp_l_m, l_bar + 3 * s_l, 1e-12);
  EXPECT_NEAR(r.ap_rad.z(), 2e-4, 1e-12);
  EXPECT_NEAR(r.rp_rad.z(), 3e-4, 1e-12);  // S_c = 1e-4 rad
  EXPECT_NEAR(r.ap_rad.x(), 0, 1e-15);
}

TEST(Iso9283Test, BadInput) {
  Iso9283PoseResult r;
  std::string error;
  Iso9283Sample c;
  EXPECT_FALSE(Iso9283Pose(c, {c}, &r, &error));
  EXPECT_EQ(error, "ISO 9283 needs at least 2 cycles to a pose, got 1");
  Iso9283Sample bad;
  bad.rotation(0, 0) = 2;
  EXPECT_FALSE(Iso9283Pose(c, {c, bad}, &r, &error));
  EXPECT_EQ(error, "cycle 2: the attained orientation is not a rotation");
}

}  // namespace
}  // namespace activecal
