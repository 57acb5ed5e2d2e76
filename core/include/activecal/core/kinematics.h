// Forward kinematics of a RobotModel, written once and templated on the
// scalar so that Ceres' Jets differentiate through it.
//
// The parameters come as one pointer per block (see robot_model.h for the
// block layout): blocks[0] the base, blocks[1..n] the links, blocks[n+1] the
// tool point. Joint readings q are plain doubles (radians or metres).
//
//   T(q) = B * L1(q1) * ... * Ln(qn)
//   measured point = R(q) * tool + t(q)
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

// The rigid transform (R, t) of one link given its block p and joint reading
// q: a point x in the link's frame is R * x + t in the previous frame.
template <typename T>
void LinkTransform(const Link& link, const T* p, double q, Matrix3<T>* R,
                   Vector3<T>* t) {
  using std::cos;
  using std::sin;
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
  }
  // Not reached for a valid convention; keeps the outputs defined.
  R->setIdentity();
  t->setZero();
}

// The end transform (R, t) of the last link for joint readings q
// (model.num_joints() values).
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
}

// The measured point (the tool point in the device's frame).
template <typename T>
Vector3<T> MeasuredPoint(const RobotModel& model, const T* const* blocks,
                         const double* q) {
  Matrix3<T> R;
  Vector3<T> t;
  ForwardKinematics(model, blocks, q, &R, &t);
  const T* tool = blocks[model.num_joints() + 1];
  return R * Vector3<T>(tool[0], tool[1], tool[2]) + t;
}

// The rotation Rz(rz) Ry(ry) Rx(rx) of the tool block's angles.
template <typename T>
Matrix3<T> ToolRotation(const T* tool) {
  using std::cos;
  using std::sin;
  const T cx = cos(tool[3]), sx = sin(tool[3]);
  const T cy = cos(tool[4]), sy = sin(tool[4]);
  const T cz = cos(tool[5]), sz = sin(tool[5]);
  Matrix3<T> R;
  R << cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx,  //
      sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx,   //
      -sy, cy * sx, cy * cx;
  return R;
}

// The measured target frame in the device's frame: orientation R (the last
// link's frame turned by the tool angles) and origin t (the measured point).
template <typename T>
void TargetFrame(const RobotModel& model, const T* const* blocks,
                 const double* q, Matrix3<T>* R, Vector3<T>* t) {
  Matrix3<T> Rn;
  Vector3<T> tn;
  ForwardKinematics(model, blocks, q, &Rn, &tn);
  const T* tool = blocks[model.num_joints() + 1];
  *t = Rn * Vector3<T>(tool[0], tool[1], tool[2]) + tn;
  *R = Rn * ToolRotation(tool);
}

// Convenience for a full parameter vector in block order (double only).
Eigen::Vector3d MeasuredPoint(const RobotModel& model,
                              const Eigen::VectorXd& parameters,
                              const Eigen::VectorXd& q);
void ForwardKinematics(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const Eigen::VectorXd& q, Eigen::Matrix3d* R,
                       Eigen::Vector3d* t);

void TargetFrame(const RobotModel& model, const Eigen::VectorXd& parameters,
                 const Eigen::VectorXd& q, Eigen::Matrix3d* R,
                 Eigen::Vector3d* t);

// Pointers to each block of a full parameter vector.
template <typename T>
std::vector<const T*> BlockPointers(const RobotModel& model, const T* full) {
  std::vector<const T*> blocks(model.num_blocks());
  for (int b = 0; b < model.num_blocks(); ++b) {
    blocks[b] = full + model.block_offset(b);
  }
  return blocks;
}

}  // namespace activecal

#endif  // ACTIVECAL_CORE_KINEMATICS_H_
