// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Euler and Tait-Bryan angles: the 12 axis orders, intrinsic or extrinsic,
// in radians or degrees, to and from rotation matrices. For the orientation
// columns of files written by trackers and other software; activecal's own
// files keep rotation vectors or the URDF's roll-pitch-yaw (kinematics.h).
//
// Conventions. An axis order names three axes, each of X, Y, Z, with no two
// neighbours equal: the six Tait-Bryan orders (XYZ, XZY, YXZ, YZX, ZXY, ZYX,
// three distinct axes) and the six proper Euler orders (XYX, XZX, YXY, YZY,
// ZXZ, ZYZ, first axis repeated). The angles (a, b, c) are taken in the
// order's order, and R(angle) is the right-handed rotation by `angle` about
// a coordinate axis (Rx, Ry, Rz):
//
//   intrinsic "XYZ" (a, b, c): R = Rx(a) Ry(b) Rz(c)   rotations about the
//     moving axes: first about X, then about the new Y, then the newest Z;
//   extrinsic "XYZ" (a, b, c): R = Rz(c) Ry(b) Rx(a)   rotations about the
//     fixed axes: first about X, then the fixed Y, then the fixed Z.
//
// So extrinsic "XYZ" (a, b, c) is intrinsic "ZYX" (c, b, a), and URDF's
// roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll)) is extrinsic "XYZ" (roll,
// pitch, yaw). R maps a vector's coordinates in the rotated frame to the
// reference frame (its columns are the rotated frame's axes).
//
// From a matrix, the angles come back in the ranges: first and last in
// (-pi, pi]; the middle one in [-pi/2, pi/2] for a Tait-Bryan order, [0, pi]
// for a proper Euler order. At gimbal lock (middle angle +-pi/2 for
// Tait-Bryan, 0 or pi for proper Euler) only the sum or the difference of
// the first and last is defined: the angle of the last rotation of the
// sequence as written (c of "XYZ" (a, b, c)) is then set to 0 and the other
// one carries the whole rotation. The lock is taken when the matrix entries
// that fix that angle are below 8 * DBL_EPSILON (about 1.8e-15), that is at
// rounding level; within that distance of the lock the matrix still comes
// back to rounding precision from the angles returned.

#ifndef ACTIVECAL_CORE_EULER_ANGLES_H_
#define ACTIVECAL_CORE_EULER_ANGLES_H_

#include <Eigen/Core>
#include <string>

namespace activecal {

enum class EulerAxes {
  // Tait-Bryan (three distinct axes).
  kXYZ,
  kXZY,
  kYXZ,
  kYZX,
  kZXY,
  kZYX,
  // Proper Euler (first axis repeated).
  kXYX,
  kXZX,
  kYXY,
  kYZY,
  kZXZ,
  kZYZ,
};

// Whether the rotations are about the moving (intrinsic) or the fixed
// (extrinsic) axes.
enum class EulerFrame { kIntrinsic, kExtrinsic };

struct EulerConvention {
  EulerAxes axes = EulerAxes::kXYZ;
  EulerFrame frame = EulerFrame::kIntrinsic;
  bool degrees = false;  // the angles in degrees instead of radians
};

// "XYZ", ..., "ZYZ".
const char* EulerAxesToString(EulerAxes axes);
// "XYZ" etc., any case ("xyz"). False for anything else.
bool StringToEulerAxes(std::string text, EulerAxes* axes);

// "intrinsic", "extrinsic".
const char* EulerFrameToString(EulerFrame frame);
// "intrinsic" or "extrinsic", any case.
bool StringToEulerFrame(std::string text, EulerFrame* frame);

// "intrinsic XYZ, deg", "extrinsic ZYZ, rad".
std::string EulerConventionToString(const EulerConvention& convention);
// The form EulerConventionToString writes: "<frame> <axes>, <rad|deg>"
// (any case; ", rad" may be left out). False for anything else.
bool StringToEulerConvention(const std::string& text,
                             EulerConvention* convention);

// True for the six orders with a repeated axis (XYX, ...).
bool IsProperEuler(EulerAxes axes);

// The rotation matrix of `angles` (a, b, c) in `convention`'s unit.
Eigen::Matrix3d EulerAnglesToRotationMatrix(const Eigen::Vector3d& angles,
                                            const EulerConvention& convention);

// The angles (a, b, c) of the rotation matrix R (orthonormal, det +1; not
// checked) in `convention`'s unit, in the ranges and with the gimbal-lock
// choice above.
Eigen::Vector3d RotationMatrixToEulerAngles(const Eigen::Matrix3d& R,
                                            const EulerConvention& convention);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_EULER_ANGLES_H_
