// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Euler / Tait-Bryan conventions (core/euler_angles.h): every order, both
// frames, both units, against products of elementary rotations written out
// by hand; round trips; the gimbal-lock points.

#include "activecal/core/euler_angles.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace activecal {
namespace {

// The elementary rotations, written out.
Eigen::Matrix3d Rx(double a) {
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return R;
}
Eigen::Matrix3d Ry(double a) {
  Eigen::Matrix3d R;
  R << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return R;
}
Eigen::Matrix3d Rz(double a) {
  Eigen::Matrix3d R;
  R << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return R;
}

const std::vector<EulerAxes> kAllAxes = {
    EulerAxes::kXYZ, EulerAxes::kXZY, EulerAxes::kYXZ, EulerAxes::kYZX,
    EulerAxes::kZXY, EulerAxes::kZYX, EulerAxes::kXYX, EulerAxes::kXZX,
    EulerAxes::kYXY, EulerAxes::kYZY, EulerAxes::kZXZ, EulerAxes::kZYZ};
// The axes of kAllAxes[i], first to last: letters 4i to 4i + 2.
const char kAxesLetters[] = "XYZ XZY YXZ YZX ZXY ZYX XYX XZX YXY YZY ZXZ ZYZ";

// The rotation by a about the axis 'X', 'Y' or 'Z' (zero for another).
Eigen::Matrix3d Elementary(char axis, double a) {
  if (axis == 'X') return Rx(a);
  if (axis == 'Y') return Ry(a);
  return axis == 'Z' ? Rz(a) : Eigen::Matrix3d::Zero();
}

// The three axes of an order, by hand ("???" for none of kAllAxes).
std::string AxesLetters(EulerAxes axes) {
  for (size_t i = 0; i < kAllAxes.size(); ++i) {
    if (kAllAxes[i] == axes) return std::string(kAxesLetters + 4 * i, 3);
  }
  return "???";
}

// The intrinsic product for each order (extrinsic: the reverse).
Eigen::Matrix3d HandIntrinsic(EulerAxes axes, double a, double b, double c) {
  const std::string r = AxesLetters(axes);
  return Elementary(r[0], a) * Elementary(r[1], b) * Elementary(r[2], c);
}
Eigen::Matrix3d HandExtrinsic(EulerAxes axes, double a, double b, double c) {
  const std::string r = AxesLetters(axes);
  return Elementary(r[2], c) * Elementary(r[1], b) * Elementary(r[0], a);
}

// Every (order, frame, unit).
std::vector<EulerConvention> AllConventions() {
  std::vector<EulerConvention> all;
  for (EulerAxes axes : kAllAxes) {
    for (EulerFrame frame : {EulerFrame::kIntrinsic, EulerFrame::kExtrinsic}) {
      for (bool degrees : {false, true}) all.push_back({axes, frame, degrees});
    }
  }
  return all;
}

std::string Name(const EulerConvention& c) {
  return EulerConventionToString(c);
}

double MaxDiff(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return (A - B).cwiseAbs().maxCoeff();
}

TEST(EulerAnglesTest, EveryConventionIsItsProductOfElementaryRotations) {
  const Eigen::Vector3d rad(0.3, -0.7, 1.9);
  for (const EulerConvention& c : AllConventions()) {
    const Eigen::Matrix3d hand =
        c.frame == EulerFrame::kIntrinsic
            ? HandIntrinsic(c.axes, rad[0], rad[1], rad[2])
            : HandExtrinsic(c.axes, rad[0], rad[1], rad[2]);
    const Eigen::Vector3d given =
        c.degrees ? Eigen::Vector3d(rad / M_PI * 180) : rad;
    EXPECT_LT(MaxDiff(EulerAnglesToRotationMatrix(given, c), hand), 1e-15)
        << Name(c);
  }
}

TEST(EulerAnglesTest, IntrinsicIsExtrinsicReversed) {
  const Eigen::Vector3d v(0.4, 1.1, -2.5);
  for (EulerAxes axes : kAllAxes) {
    const std::string name = EulerAxesToString(axes);
    EulerAxes reversed;
    ASSERT_TRUE(
        StringToEulerAxes(std::string(name.rbegin(), name.rend()), &reversed));
    const Eigen::Matrix3d intrinsic =
        EulerAnglesToRotationMatrix(v, {axes, EulerFrame::kIntrinsic, false});
    const Eigen::Matrix3d extrinsic =
        EulerAnglesToRotationMatrix(Eigen::Vector3d(v[2], v[1], v[0]),
                                    {reversed, EulerFrame::kExtrinsic, false});
    EXPECT_LT(MaxDiff(intrinsic, extrinsic), 1e-15) << name;
  }
}

TEST(EulerAnglesTest, UrdfRpyIsExtrinsicXyz) {
  // URDF: R = Rz(yaw) Ry(pitch) Rx(roll).
  const double roll = 0.2, pitch = -1.2, yaw = 2.9;
  EXPECT_LT(MaxDiff(EulerAnglesToRotationMatrix(
                        Eigen::Vector3d(roll, pitch, yaw),
                        {EulerAxes::kXYZ, EulerFrame::kExtrinsic, false}),
                    Rz(yaw) * Ry(pitch) * Rx(roll)),
            1e-15);
}

// Random rotations (quaternions of a fixed seed) -> angles -> rotation.
TEST(EulerAnglesTest, MatrixAnglesMatrixRoundTrips) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  for (int n = 0; n < 200; ++n) {
    const Eigen::Matrix3d R =
        Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng))
            .normalized()
            .toRotationMatrix();
    for (const EulerConvention& c : AllConventions()) {
      const Eigen::Vector3d angles = RotationMatrixToEulerAngles(R, c);
      ASSERT_LT(MaxDiff(EulerAnglesToRotationMatrix(angles, c), R), 1e-12)
          << Name(c) << " sample " << n;
      // The ranges: first and last in (-pi, pi], the middle [-pi/2, pi/2]
      // (Tait-Bryan) or [0, pi] (proper Euler).
      const double half_turn = c.degrees ? 180.0 : M_PI;
      for (int k : {0, 2}) {
        EXPECT_GT(angles[k], -half_turn) << Name(c);
        EXPECT_LE(angles[k], half_turn) << Name(c);
      }
      if (IsProperEuler(c.axes)) {
        EXPECT_GE(angles[1], 0.0) << Name(c);
        EXPECT_LE(angles[1], half_turn) << Name(c);
      } else {
        EXPECT_GE(angles[1], -half_turn / 2) << Name(c);
        EXPECT_LE(angles[1], half_turn / 2) << Name(c);
      }
    }
  }
}

// Angles inside the ranges come back as given.
TEST(EulerAnglesTest, AnglesMatrixAnglesRoundTrips) {
  for (const EulerConvention& c : AllConventions()) {
    const double scale = c.degrees ? 180.0 / M_PI : 1.0;
    const Eigen::Vector3d angles =
        scale * (IsProperEuler(c.axes) ? Eigen::Vector3d(-2.9, 0.4, 3.0)
                                       : Eigen::Vector3d(-2.9, -1.4, 3.0));
    const Eigen::Vector3d back =
        RotationMatrixToEulerAngles(EulerAnglesToRotationMatrix(angles, c), c);
    EXPECT_LT((back - angles).cwiseAbs().maxCoeff(), 1e-12 * scale) << Name(c);
  }
}

// Half turns of the first and last angles come back as +180 deg, not -180:
// the ranges are (-180, 180].
TEST(EulerAnglesTest, HalfTurnsArePositive) {
  for (const EulerConvention& c : AllConventions()) {
    const Eigen::Vector3d given_deg(180.0, 30.0, 180.0);
    const Eigen::Vector3d given =
        c.degrees ? given_deg : Eigen::Vector3d(given_deg / 180.0 * M_PI);
    const Eigen::Vector3d back =
        RotationMatrixToEulerAngles(EulerAnglesToRotationMatrix(given, c), c);
    const Eigen::Vector3d back_deg =
        c.degrees ? back : Eigen::Vector3d(back / M_PI * 180.0);
    EXPECT_LT((back_deg - given_deg).cwiseAbs().maxCoeff(), 1e-12)
        << Name(c) << ": " << back_deg.transpose();
  }
}

// The 24 rotations of the cube (signed permutation matrices, det +1): exact
// zeros, half turns and locks everywhere. Each comes back exactly enough,
// with its angles in the ranges (a half turn is +180, never -180).
TEST(EulerAnglesTest, CubeRotations) {
  std::vector<Eigen::Matrix3d> cube;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                           {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : perms) {
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
      for (int r = 0; r < 3; ++r) R(r, p[r]) = (signs >> r) & 1 ? -1.0 : 1.0;
      if (R.determinant() > 0) cube.push_back(R);
    }
  }
  ASSERT_EQ(cube.size(), 24u);
  for (const EulerConvention& c : AllConventions()) {
    const double half_turn = c.degrees ? 180.0 : M_PI;
    for (const Eigen::Matrix3d& R : cube) {
      const Eigen::Vector3d angles = RotationMatrixToEulerAngles(R, c);
      EXPECT_LT(MaxDiff(EulerAnglesToRotationMatrix(angles, c), R), 1e-15)
          << Name(c) << "\n"
          << R;
      for (int k = 0; k < 3; ++k) {
        EXPECT_GT(angles[k], -half_turn) << Name(c) << "\n" << R;
        EXPECT_LE(angles[k], half_turn) << Name(c) << "\n" << R;
      }
    }
  }
}

// The gimbal lock: the middle angle at +-90 deg (Tait-Bryan: singular;
// proper Euler: regular) and at 0 and 180 deg (singular for proper Euler).
// The matrix comes back to rounding, the middle angle exactly, and at the
// singular points the last angle of the convention is 0 with the first
// carrying the whole rotation about the locked axis.
TEST(EulerAnglesTest, GimbalLockPointsAreExact) {
  for (const EulerConvention& c : AllConventions()) {
    const bool proper = IsProperEuler(c.axes);
    for (double middle_deg : {90.0, -90.0, 0.0, 180.0}) {
      if (!proper && (middle_deg == 0.0 || middle_deg == 180.0)) continue;
      const double a = 25.0, cc = -40.0;  // degrees
      const Eigen::Vector3d given_deg(a, middle_deg, cc);
      const Eigen::Vector3d given =
          c.degrees ? given_deg : Eigen::Vector3d(given_deg / 180.0 * M_PI);
      const Eigen::Matrix3d R = EulerAnglesToRotationMatrix(given, c);
      const Eigen::Vector3d back = RotationMatrixToEulerAngles(R, c);
      const std::string what =
          Name(c) + " middle " + std::to_string(middle_deg);
      EXPECT_LT(MaxDiff(EulerAnglesToRotationMatrix(back, c), R), 1e-12)
          << what;
      const Eigen::Vector3d back_deg =
          c.degrees ? back : Eigen::Vector3d(back / M_PI * 180.0);
      const bool singular =
          proper ? (middle_deg == 0.0 || middle_deg == 180.0) : true;
      if (middle_deg == -90.0 && proper) {
        // Outside [0, 180]: the other representation, middle +90.
        EXPECT_EQ(back_deg[1], 90.0) << what;
        continue;
      }
      EXPECT_EQ(back_deg[1], middle_deg) << what;
      if (!singular) {
        EXPECT_NEAR(back_deg[0], a, 1e-10) << what;
        EXPECT_NEAR(back_deg[2], cc, 1e-10) << what;
        continue;
      }
      EXPECT_EQ(back[2], 0.0) << what;
      // The first angle carries the rotation about the locked axis: the
      // product with c = 0 is R (checked above); and it is a +- c.
      const double sum = a + cc, difference = a - cc;
      const double first = back_deg[0];
      EXPECT_TRUE(std::abs(first - sum) < 1e-10 ||
                  std::abs(first - difference) < 1e-10)
          << what << ": first angle " << first;
    }
  }
}

// A matrix at the lock that was not built from angles (a quaternion): the
// entries that would fix the last angle are rounding noise.
TEST(EulerAnglesTest, LockedMatrixFromAQuaternion) {
  // XYZ intrinsic with b = 90 deg: R = Rx(a) Ry(pi/2) Rz(c) depends on a + c.
  const Eigen::Quaterniond q =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) *
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ());
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const EulerConvention c{EulerAxes::kXYZ, EulerFrame::kIntrinsic, false};
  const Eigen::Vector3d back = RotationMatrixToEulerAngles(R, c);
  EXPECT_LT(MaxDiff(EulerAnglesToRotationMatrix(back, c), R), 1e-15);
  EXPECT_NEAR(back[1], M_PI / 2, 1e-15);
  EXPECT_EQ(back[2], 0.0);
  EXPECT_NEAR(back[0], 0.8, 1e-14);
}

// The lock threshold (8 DBL_EPSILON on the entries that fix the last
// angle): just above it the last angle is computed, just below it is 0;
// both bring the matrix back.
TEST(EulerAnglesTest, LockThresholdIsCrossed) {
  const EulerConvention c{EulerAxes::kZYX, EulerFrame::kIntrinsic, false};
  const double threshold = 8 * DBL_EPSILON;
  for (double distance : {threshold * 4, threshold / 4}) {
    // b = pi/2 - distance: cos b = distance (to rounding).
    const Eigen::Vector3d given(0.3, M_PI / 2 - distance, 0.5);
    const Eigen::Matrix3d R = EulerAnglesToRotationMatrix(given, c);
    const Eigen::Vector3d back = RotationMatrixToEulerAngles(R, c);
    EXPECT_LT(MaxDiff(EulerAnglesToRotationMatrix(back, c), R), 1e-15)
        << distance;
    if (distance > threshold) {
      EXPECT_NEAR(back[2], 0.5, 1e-6) << distance;
      EXPECT_NEAR(back[0], 0.3, 1e-6) << distance;
    } else {
      EXPECT_EQ(back[2], 0.0) << distance;
      EXPECT_NEAR(back[0], 0.3 - 0.5, 1e-12) << distance;
    }
  }
}

// Near (not at) the lock, the matrix still comes back to rounding.
TEST(EulerAnglesTest, NearLockRoundTrips) {
  for (const EulerConvention& c : AllConventions()) {
    const double lock = IsProperEuler(c.axes) ? 0.0 : M_PI / 2;
    for (double distance : {1e-6, 1e-9, 1e-12, 1e-14}) {
      Eigen::Vector3d given(
          1.0, lock + (IsProperEuler(c.axes) ? distance : -distance), -2.0);
      if (c.degrees) given = given / M_PI * 180.0;
      const Eigen::Matrix3d R = EulerAnglesToRotationMatrix(given, c);
      const Eigen::Vector3d back = RotationMatrixToEulerAngles(R, c);
      EXPECT_LT(MaxDiff(EulerAnglesToRotationMatrix(back, c), R), 1e-12)
          << Name(c) << " " << distance;
    }
  }
}

TEST(EulerAnglesTest, DegreesAreExactAtQuarterTurns) {
  const EulerConvention deg{EulerAxes::kZYZ, EulerFrame::kIntrinsic, true};
  const Eigen::Matrix3d R =
      EulerAnglesToRotationMatrix(Eigen::Vector3d(90, 90, 180), deg);
  const Eigen::Matrix3d hand = Rz(M_PI / 2) * Ry(M_PI / 2) * Rz(M_PI);
  EXPECT_LT(MaxDiff(R, hand), 1e-15);
  const Eigen::Vector3d back = RotationMatrixToEulerAngles(R, deg);
  EXPECT_EQ(back[1], 90.0);
  EXPECT_NEAR(back[0], 90.0, 1e-12);
  EXPECT_NEAR(back[2], 180.0, 1e-12);
}

TEST(EulerAnglesTest, NamesRoundTrip) {
  for (const EulerConvention& c : AllConventions()) {
    EulerConvention back;
    ASSERT_TRUE(StringToEulerConvention(EulerConventionToString(c), &back))
        << Name(c);
    EXPECT_EQ(back.axes, c.axes);
    EXPECT_EQ(back.frame, c.frame);
    EXPECT_EQ(back.degrees, c.degrees);
    EulerAxes axes;
    ASSERT_TRUE(StringToEulerAxes(EulerAxesToString(c.axes), &axes));
    EXPECT_EQ(axes, c.axes);
  }
  EXPECT_EQ(
      EulerConventionToString({EulerAxes::kXYZ, EulerFrame::kIntrinsic, true}),
      "intrinsic XYZ, deg");
  EulerConvention c;
  ASSERT_TRUE(StringToEulerConvention("Extrinsic zyz", &c));
  EXPECT_EQ(c.axes, EulerAxes::kZYZ);
  EXPECT_EQ(c.frame, EulerFrame::kExtrinsic);
  EXPECT_FALSE(c.degrees);
  EulerAxes axes;
  EXPECT_TRUE(StringToEulerAxes("xyz", &axes));
  EXPECT_EQ(axes, EulerAxes::kXYZ);
  for (const char* bad : {"XXY", "XYY", "XY", "XYZW", "ABC", ""}) {
    EXPECT_FALSE(StringToEulerAxes(bad, &axes)) << bad;
  }
  EulerFrame frame;
  EXPECT_TRUE(StringToEulerFrame("EXTRINSIC", &frame));
  EXPECT_EQ(frame, EulerFrame::kExtrinsic);
  EXPECT_FALSE(StringToEulerFrame("fixed", &frame));
  for (const char* bad : {"intrinsic", "XYZ", "intrinsic XYZ, grad",
                          "sideways XYZ", "intrinsic XXZ, rad"}) {
    EXPECT_FALSE(StringToEulerConvention(bad, &c)) << bad;
  }
  EXPECT_TRUE(IsProperEuler(EulerAxes::kZXZ));
  EXPECT_FALSE(IsProperEuler(EulerAxes::kZXY));
}

}  // namespace
}  // namespace activecal
