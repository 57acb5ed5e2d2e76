// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Forward kinematics of a RobotModel, written once and templated on the
// scalar so that Ceres' Jets differentiate through it.
//
// The parameters come as one pointer per block (see robot_model.h for the
// block layout): blocks[0] the base, blocks[1..n] the links,
// blocks[n+1..n+K] the markers. Joint readings q are plain doubles (radians
// or metres).
//
//   T(q) = B * L1(q1) * ... * Ln(qn) * Tip
//   measured point of marker k = R(q) * marker_k + t(q)
//
// All frames are expressed in the measuring device's frame, the base frame's
// parent ("coordinate zero" in Sun & Hollerbach).

#ifndef ACTIVECAL_CORE_KINEMATICS_H_
#define ACTIVECAL_CORE_KINEMATICS_H_

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

template <typename T>
using Matrix3 = Eigen::Matrix<T, 3, 3>;
template <typename T>
using Vector3 = Eigen::Matrix<T, 3, 1>;

// The rotation Rz(rz) Ry(ry) Rx(rx) (fixed-axis roll, pitch, yaw).
template <typename T>
Matrix3<T> RpyRotation(const T& rx, const T& ry, const T& rz) {
  using std::cos;
  using std::sin;
  const T cx = cos(rx), sx = sin(rx);
  const T cy = cos(ry), sy = sin(ry);
  const T cz = cos(rz), sz = sin(rz);
  Matrix3<T> R;
  R << cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx,  //
      sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx,   //
      -sy, cy * sx, cy * cx;
  return R;
}

// The rotation by `angle` about the unit vector `axis` (Rodrigues).
template <typename T>
Matrix3<T> AxisRotation(const Eigen::Vector3d& axis, const T& angle) {
  using std::cos;
  using std::sin;
  const T c = cos(angle), s = sin(angle);
  const T v = T(1.0) - c;
  const double x = axis[0], y = axis[1], z = axis[2];
  Matrix3<T> R;
  R << c + v * (x * x), v * (x * y) - s * z, v * (x * z) + s * y,  //
      v * (x * y) + s * z, c + v * (y * y), v * (y * z) - s * x,   //
      v * (x * z) - s * y, v * (y * z) + s * x, c + v * (z * z);
  return R;
}

// The rigid transform (R, t) of one link given its block p and joint reading
// q: a point x in the link's frame is R * x + t in the previous frame.
template <typename T>
void LinkTransform(const Link& link, const T* p, double q, Matrix3<T>* R,
                   Vector3<T>* t) {
  using std::cos;
  using std::sin;
  if (link.convention == LinkConvention::kFrame) {
    *R = RpyRotation(p[3], p[4], p[5]);
    *t << p[0], p[1], p[2];
    return;
  }
  if (link.convention == LinkConvention::kUrdf) {
    // Origin(xyz, rotation) * Correction(x..rz) * Motion(axis, offset +
    // gain q).
    const Eigen::Matrix3d& Ro = link.origin_rotation;
    const Matrix3<T> Rc = RpyRotation(p[kUrdfRx], p[kUrdfRy], p[kUrdfRz]);
    Vector3<T> tc(p[kUrdfX], p[kUrdfY], p[kUrdfZ]);
    const T s = p[kUrdfOffset] + p[kUrdfGain] * q;
    Matrix3<T> Rl = Ro.cast<T>() * Rc;
    if (link.joint_type == JointType::kRevolute) {
      *R = Rl * AxisRotation(link.axis, s);
    } else {
      if (link.joint_type == JointType::kPrismatic) {
        tc += Rc * (link.axis.cast<T>() * s);
      }
      *R = Rl;
    }
    *t = link.origin_xyz.cast<T>() + Ro.cast<T>() * tc;
    return;
  }
  T theta = p[kGamma];
  T d = p[kD];
  if (link.joint_type == JointType::kRevolute) {
    theta += p[kGain] * q;
  } else if (link.joint_type == JointType::kPrismatic) {
    d += p[kGain] * q;
  }
  const T ct = cos(theta), st = sin(theta);
  const T ca = cos(p[kAlpha]), sa = sin(p[kAlpha]);
  switch (link.convention) {
    case LinkConvention::kModifiedDH:
      // Rx(alpha) Tx(a) Rz(theta) Tz(d)
      (*R) << ct, -st, T(0.0), ca * st, ca * ct, -sa, sa * st, sa * ct, ca;
      (*t) << p[kA], -sa * d, ca * d;
      return;
    case LinkConvention::kStandardDH:
    case LinkConvention::kHayati:
      // Rz(theta) Tz(d) Tx(a) Rx(alpha) [Ry(beta)]
      (*R) << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, T(0.0), sa, ca;
      (*t) << p[kA] * ct, p[kA] * st, d;
      if (link.convention == LinkConvention::kHayati) {
        const T cb = cos(p[kBeta]), sb = sin(p[kBeta]);
        const Vector3<T> c0 = R->col(0), c2 = R->col(2);
        R->col(0) = c0 * cb - c2 * sb;
        R->col(2) = c0 * sb + c2 * cb;
      }
      return;
    default:
      break;
  }
  // Not reached for a valid convention; keeps the outputs defined.
  R->setIdentity();
  t->setZero();
}

// The tip frame (R, t) for joint readings q (model.num_joints() values):
// the last link's frame followed by model.tip.
template <typename T>
void ForwardKinematics(const RobotModel& model, const T* const* blocks,
                       const double* q, Matrix3<T>* R, Vector3<T>* t) {
  LinkTransform(model.base, blocks[0], 0.0, R, t);
  Matrix3<T> Ri;
  Vector3<T> ti;
  for (int i = 0; i < model.num_joints(); ++i) {
    LinkTransform(model.links[i], blocks[i + 1], q[i], &Ri, &ti);
    *t += (*R) * ti;
    *R = (*R) * Ri;
  }
  if (!model.tip.IsIdentity()) {
    *t += (*R) * model.tip.translation.cast<T>();
    *R = (*R) * model.tip.rotation.cast<T>();
  }
}

// The measured point of marker `marker` (0-based) in the device's frame.
template <typename T>
Vector3<T> MeasuredPoint(const RobotModel& model, const T* const* blocks,
                         const double* q, int marker = 0) {
  Matrix3<T> R;
  Vector3<T> t;
  ForwardKinematics(model, blocks, q, &R, &t);
  const T* m = blocks[model.marker_block(marker)];
  return R * Vector3<T>(m[0], m[1], m[2]) + t;
}

// The rotation Rz(rz) Ry(ry) Rx(rx) of a marker block's angles.
template <typename T>
Matrix3<T> ToolRotation(const T* marker) {
  return RpyRotation(marker[3], marker[4], marker[5]);
}

// The measured target frame of marker `marker` in the device's frame:
// orientation R (the tip frame turned by the marker's angles) and origin t
// (the measured point).
template <typename T>
void TargetFrame(const RobotModel& model, const T* const* blocks,
                 const double* q, Matrix3<T>* R, Vector3<T>* t,
                 int marker = 0) {
  Matrix3<T> Rn;
  Vector3<T> tn;
  ForwardKinematics(model, blocks, q, &Rn, &tn);
  const T* m = blocks[model.marker_block(marker)];
  *t = Rn * Vector3<T>(m[0], m[1], m[2]) + tn;
  *R = Rn * ToolRotation(m);
}

// Convenience for a full parameter vector in block order (double only).
Eigen::Vector3d MeasuredPoint(const RobotModel& model,
                              const Eigen::VectorXd& parameters,
                              const Eigen::VectorXd& q, int marker = 0);
void ForwardKinematics(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const Eigen::VectorXd& q, Eigen::Matrix3d* R,
                       Eigen::Vector3d* t);

void TargetFrame(const RobotModel& model, const Eigen::VectorXd& parameters,
                 const Eigen::VectorXd& q, Eigen::Matrix3d* R,
                 Eigen::Vector3d* t, int marker = 0);

// The fixed-axis angles (roll, pitch, yaw) of a rotation, R = Rz(yaw)
// Ry(pitch) Rx(roll), with pitch in [-pi/2, pi/2] (the URDF convention); at
// pitch = +-pi/2, roll is 0.
Eigen::Vector3d RotationToRpy(const Eigen::Matrix3d& R);

// RotationToRpy of R for a file whose angles are in units of `unit` radians
// (1: radians; M_PI / 180: degrees), each angle rounded to the fewest
// decimal places (0 to 20) at which the three read back (times `unit`,
// through RpyRotation) to exactly R, on this branch or on the other one
// (pitch beyond +-pi/2); RotationToRpy(R) / unit when none does (then they
// read back to R to rounding, a few ulp). A rotation read from "rpy: [0.1,
// 0.2, 0.3]" or "[0, 2, 0]" is so written the same again (at exactly pitch
// +-90 deg only yaw - roll is defined: roll is written 0). Write the angles
// with the shortest round-trip text (std::to_chars).
Eigen::Vector3d RotationToShortRpy(const Eigen::Matrix3d& R, double unit = 1.0);

// Pointers to each block of a full parameter vector.
template <typename T>
std::vector<const T*> BlockPointers(const RobotModel& model, const T* full) {
  std::vector<const T*> blocks(model.num_blocks());
  int offset = 0;
  for (int b = 0; b < model.num_blocks(); ++b) {
    blocks[b] = full + offset;
    offset += model.block_size(b);
  }
  return blocks;
}

}  // namespace activecal

#endif  // ACTIVECAL_CORE_KINEMATICS_H_
