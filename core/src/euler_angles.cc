// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/euler_angles.h"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>

namespace activecal {
namespace {

struct AxesInfo {
  EulerAxes axes;
  const char* name;
  int first, second, third;  // 0 = X, 1 = Y, 2 = Z
};

constexpr AxesInfo kAxes[] = {
    {EulerAxes::kXYZ, "XYZ", 0, 1, 2}, {EulerAxes::kXZY, "XZY", 0, 2, 1},
    {EulerAxes::kYXZ, "YXZ", 1, 0, 2}, {EulerAxes::kYZX, "YZX", 1, 2, 0},
    {EulerAxes::kZXY, "ZXY", 2, 0, 1}, {EulerAxes::kZYX, "ZYX", 2, 1, 0},
    {EulerAxes::kXYX, "XYX", 0, 1, 0}, {EulerAxes::kXZX, "XZX", 0, 2, 0},
    {EulerAxes::kYXY, "YXY", 1, 0, 1}, {EulerAxes::kYZY, "YZY", 1, 2, 1},
    {EulerAxes::kZXZ, "ZXZ", 2, 0, 2}, {EulerAxes::kZYZ, "ZYZ", 2, 1, 2},
};

const AxesInfo& Info(EulerAxes axes) {
  for (const AxesInfo& info : kAxes) {
    if (info.axes == axes) return info;
  }
  return kAxes[0];  // unreachable for a valid enum value
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return s;
}

// The right-handed rotation by `angle` about coordinate axis `axis`.
Eigen::Matrix3d Elementary(int axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
  R(axis, axis) = 1.0;
  R(u, u) = c;
  R(u, v) = -s;
  R(v, u) = s;
  R(v, v) = c;
  return R;
}

// Below this, the matrix entries that fix the last angle are rounding
// noise: the gimbal lock (euler_angles.h).
constexpr double kLock = 8 * DBL_EPSILON;

// -pi to pi: the ranges are (-pi, pi].
double HalfOpen(double angle) {
  return angle <= -M_PI ? angle + 2 * M_PI : angle;
}

// The angles (a, b, c) of M = Rx(a) Ry(b) Rz(c) (tait_bryan) or
// M = Rx(a) Ry(b) Rx(c) (proper Euler), with sin b (proper) of sign `sign`;
// at the lock the angle `zero_first` ? a : c is 0.
Eigen::Vector3d CanonicalAngles(const Eigen::Matrix3d& M, bool tait_bryan,
                                double sign, bool zero_first) {
  double a, b, c;
  if (tait_bryan) {
    // Row 0 of M: (cb cc, -cb sc, sb); column 2: (sb, -sa cb, ca cb).
    const double cos_b = std::hypot(M(0, 0), M(0, 1));
    b = std::atan2(M(0, 2), cos_b);
    if (cos_b > kLock) {
      c = std::atan2(-M(0, 1), M(0, 0));
    } else if (zero_first) {
      // M = Ry(b) Rz(c): row 1 is (sin c, cos c, 0).
      return Eigen::Vector3d(0.0, b, std::atan2(M(1, 0), M(1, 1)));
    } else {
      c = 0.0;
    }
    // M Rz(-c) = Rx(a) Ry(b), whose column 1 is (0, cos a, sin a).
    const double sc = std::sin(c), cc = std::cos(c);
    a = std::atan2(sc * M(2, 0) + cc * M(2, 1), sc * M(1, 0) + cc * M(1, 1));
  } else {
    // Row 0 of M: (cb, sb sc, sb cc).
    const double sin_b = std::hypot(M(0, 1), M(0, 2));
    b = std::atan2(sign * sin_b, M(0, 0));
    if (sin_b > kLock) {
      c = std::atan2(sign * M(0, 1), sign * M(0, 2));
    } else if (zero_first) {
      // M = Ry(b) Rx(c): row 1 is (0, cos c, -sin c).
      return Eigen::Vector3d(0.0, b, std::atan2(-M(1, 2), M(1, 1)));
    } else {
      c = 0.0;
    }
    // M Rx(-c) = Rx(a) Ry(b), whose column 1 is (0, cos a, sin a).
    const double sc = std::sin(c), cc = std::cos(c);
    a = std::atan2(cc * M(2, 1) - sc * M(2, 2), cc * M(1, 1) - sc * M(1, 2));
  }
  return Eigen::Vector3d(a, b, c);
}

}  // namespace

const char* EulerAxesToString(EulerAxes axes) { return Info(axes).name; }

bool StringToEulerAxes(std::string text, EulerAxes* axes) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return std::toupper(c); });
  for (const AxesInfo& info : kAxes) {
    if (text == info.name) {
      *axes = info.axes;
      return true;
    }
  }
  return false;
}

const char* EulerFrameToString(EulerFrame frame) {
  return frame == EulerFrame::kIntrinsic ? "intrinsic" : "extrinsic";
}

bool StringToEulerFrame(std::string text, EulerFrame* frame) {
  text = Lower(text);
  if (text == "intrinsic") {
    *frame = EulerFrame::kIntrinsic;
  } else if (text == "extrinsic") {
    *frame = EulerFrame::kExtrinsic;
  } else {
    return false;
  }
  return true;
}

std::string EulerConventionToString(const EulerConvention& convention) {
  return std::string(EulerFrameToString(convention.frame)) + " " +
         EulerAxesToString(convention.axes) + ", " +
         (convention.degrees ? "deg" : "rad");
}

bool StringToEulerConvention(const std::string& text,
                             EulerConvention* convention) {
  const std::string lower = Lower(text);
  const size_t space = lower.find(' ');
  if (space == std::string::npos) return false;
  EulerConvention parsed;
  if (!StringToEulerFrame(lower.substr(0, space), &parsed.frame)) return false;
  std::string rest = lower.substr(space + 1);
  const size_t comma = rest.find(',');
  if (comma != std::string::npos) {
    const std::string unit = rest.substr(comma + 1);
    if (unit == " deg") {
      parsed.degrees = true;
    } else if (unit != " rad") {
      return false;
    }
    rest = rest.substr(0, comma);
  }
  if (!StringToEulerAxes(rest, &parsed.axes)) return false;
  *convention = parsed;
  return true;
}

bool IsProperEuler(EulerAxes axes) {
  const AxesInfo& info = Info(axes);
  return info.first == info.third;
}

Eigen::Matrix3d EulerAnglesToRotationMatrix(const Eigen::Vector3d& angles,
                                            const EulerConvention& convention) {
  const AxesInfo& info = Info(convention.axes);
  // x / 180 * pi: exact at 90 and 180 degrees (x / 180 a power of two).
  const Eigen::Vector3d rad =
      convention.degrees ? Eigen::Vector3d(angles / 180.0 * M_PI) : angles;
  const Eigen::Matrix3d Ra = Elementary(info.first, rad[0]);
  const Eigen::Matrix3d Rb = Elementary(info.second, rad[1]);
  const Eigen::Matrix3d Rc = Elementary(info.third, rad[2]);
  return convention.frame == EulerFrame::kIntrinsic
             ? Eigen::Matrix3d(Ra * Rb * Rc)
             : Eigen::Matrix3d(Rc * Rb * Ra);
}

Eigen::Vector3d RotationMatrixToEulerAngles(const Eigen::Matrix3d& R,
                                            const EulerConvention& convention) {
  const AxesInfo& info = Info(convention.axes);
  const bool extrinsic = convention.frame == EulerFrame::kExtrinsic;
  // The intrinsic sequence (i, j, k) with R = Ri(.) Rj(.) Rk(.): extrinsic
  // (a, b, c) about (first, second, third) is intrinsic (c, b, a) about
  // (third, second, first).
  const int i = extrinsic ? info.third : info.first;
  const int j = info.second;
  const bool tait_bryan = info.first != info.third;
  const int k = tait_bryan ? (extrinsic ? info.first : info.third) : 3 - i - j;
  // R in the basis (e_i, e_j, e_k): the canonical X-Y-(Z|X) sequence. If
  // (i, j, k) is an odd permutation, that basis is left-handed and every
  // rotation turns the other way: the angles change sign.
  const int idx[3] = {i, j, k};
  Eigen::Matrix3d M;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) M(r, c) = R(idx[r], idx[c]);
  }
  const double sign = (j - i + 3) % 3 == 1 ? 1.0 : -1.0;
  // The angle set to 0 at the lock is the convention's last (c): the
  // intrinsic sequence's first angle when extrinsic.
  Eigen::Vector3d angles = CanonicalAngles(M, tait_bryan, sign, extrinsic);
  angles *= sign;
  for (int n = 0; n < 3; ++n) angles[n] = HalfOpen(angles[n]);
  if (extrinsic) std::swap(angles[0], angles[2]);
  if (convention.degrees) angles = angles / M_PI * 180.0;
  return angles;
}

}  // namespace activecal
