#include "activecal/core/point_jacobian.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "activecal/core/kinematics.h"

namespace activecal {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// The world axes of the three angles of R = Rz(rz) Ry(ry) Rx(rx): the
// derivative of R v by rx, ry, rz is axis x (R v).
void RpyAxes(double ry, double rz, Vector3d* ax, Vector3d* ay, Vector3d* az) {
  const double cy = std::cos(ry), sy = std::sin(ry);
  const double cz = std::cos(rz), sz = std::sin(rz);
  *ax << cz * cy, sz * cy, -sy;
  *ay << -sz, cz, 0.0;
  *az << 0.0, 0.0, 1.0;
}

// d(L x)/d p_k of one link or base block, in the block's parent frame, for
// the point y = L x (parent frame). Writes block_size columns.
void LinkColumns(const Link& link, const double* p, double q, const Vector3d& y,
                 const PointJacobianWorkspace::UrdfLinkCache* urdf,
                 Vector3d* col) {
  switch (link.convention) {
    case LinkConvention::kFrame: {
      // y = Rpy(rx, ry, rz) x + t.
      const Vector3d w(y[0] - p[0], y[1] - p[1], y[2] - p[2]);
      Vector3d ax, ay, az;
      RpyAxes(p[4], p[5], &ax, &ay, &az);
      col[0] = Vector3d::UnitX();
      col[1] = Vector3d::UnitY();
      col[2] = Vector3d::UnitZ();
      col[3] = ax.cross(w);
      col[4] = ay.cross(w);
      col[5] = az.cross(w);
      return;
    }
    case LinkConvention::kUrdf: {
      // y = o + Ro (tc + Rc M(x)), M the joint motion; w = Rc M(x).
      const Matrix3d& Ro = urdf->origin_rotation;
      const Vector3d tc(p[kUrdfX], p[kUrdfY], p[kUrdfZ]);
      const Vector3d w = Ro.transpose() * (y - link.origin_xyz) - tc;
      col[kUrdfX] = Ro.col(0);
      col[kUrdfY] = Ro.col(1);
      col[kUrdfZ] = Ro.col(2);
      col[kUrdfRx] = Ro * urdf->ax.cross(w);
      col[kUrdfRy] = Ro * urdf->ay.cross(w);
      col[kUrdfRz] = Ro * Vector3d::UnitZ().cross(w);
      Vector3d motion = Vector3d::Zero();  // d y / d s, s = offset + gain q
      if (link.joint_type != JointType::kFixed) {
        const Vector3d& axis = urdf->axis;
        motion = Ro * (link.joint_type == JointType::kRevolute
                           ? Vector3d(axis.cross(w))
                           : axis);
      }
      col[kUrdfOffset] = motion;
      col[kUrdfGain] = q * motion;
      return;
    }
    case LinkConvention::kStandardDH:
    case LinkConvention::kHayati: {
      // Rz(theta) Tz(d) Tx(a) Rx(alpha) [Ry(beta)].
      const bool revolute = link.joint_type == JointType::kRevolute;
      const bool prismatic = link.joint_type == JointType::kPrismatic;
      const double theta = p[kGamma] + (revolute ? p[kGain] * q : 0.0);
      const double d = p[kD] + (prismatic ? p[kGain] * q : 0.0);
      const double ct = std::cos(theta), st = std::sin(theta);
      const double ca = std::cos(p[kAlpha]), sa = std::sin(p[kAlpha]);
      const Vector3d o(p[kA] * ct, p[kA] * st, d);  // origin of Rx(alpha)
      const Vector3d ux(ct, st, 0.0);               // axis of Rx(alpha)
      const Vector3d about_z(-y[1], y[0], 0.0);     // z x y
      col[kGamma] = about_z;
      col[kAlpha] = ux.cross(y - o);
      col[kA] = ux;
      col[kD] = Vector3d::UnitZ();
      col[kBeta] = Vector3d::Zero();
      if (link.convention == LinkConvention::kHayati) {
        col[kBeta] = Vector3d(-st * ca, ct * ca, sa).cross(y - o);
      }
      col[kGain] = revolute ? Vector3d(q * about_z)
                            : (prismatic ? Vector3d(q * Vector3d::UnitZ())
                                         : Vector3d::Zero());
      return;
    }
    case LinkConvention::kModifiedDH: {
      // Rx(alpha) Tx(a) Rz(theta) Tz(d).
      const bool revolute = link.joint_type == JointType::kRevolute;
      const bool prismatic = link.joint_type == JointType::kPrismatic;
      const double ca = std::cos(p[kAlpha]), sa = std::sin(p[kAlpha]);
      const Vector3d uz(0.0, -sa, ca);    // axis of Rz(theta), Tz(d)
      const Vector3d o(p[kA], 0.0, 0.0);  // origin of Rz(theta)
      const Vector3d about_z = uz.cross(y - o);
      col[kGamma] = about_z;
      col[kAlpha] = Vector3d(0.0, -y[2], y[1]);  // x x y
      col[kA] = Vector3d::UnitX();
      col[kD] = uz;
      col[kBeta] = Vector3d::Zero();
      col[kGain] = revolute ? Vector3d(q * about_z)
                            : (prismatic ? Vector3d(q * uz) : Vector3d::Zero());
      return;
    }
  }
}

// A URDF link's transform from its cache: the expressions (and so the
// bits) of LinkTransform.
void UrdfTransform(const Link& link, const double* p, double q,
                   const PointJacobianWorkspace::UrdfLinkCache& c, Matrix3d* R,
                   Vector3d* t) {
  Vector3d tc(p[kUrdfX], p[kUrdfY], p[kUrdfZ]);
  const double s = p[kUrdfOffset] + p[kUrdfGain] * q;
  if (link.joint_type == JointType::kRevolute) {
    *R = c.link_rotation * AxisRotation(link.axis, s);
  } else {
    if (link.joint_type == JointType::kPrismatic) {
      tc += c.correction_rotation * (link.axis * s);
    }
    *R = c.link_rotation;
  }
  *t = link.origin_xyz + c.origin_rotation * tc;
}

// The cache of a URDF link for the block p: recomputed only when p changed.
const PointJacobianWorkspace::UrdfLinkCache& PrepareUrdfLink(
    const Link& link, const double* p,
    PointJacobianWorkspace::UrdfLinkCache* c) {
  constexpr int n = kMaxBlockSize;
  constexpr int size = PointJacobianWorkspace::UrdfLinkCache::kKeySize;
  double key[size];
  std::copy(p, p + n, key);
  std::copy(link.origin_rotation.data(), link.origin_rotation.data() + 9,
            key + n);
  std::copy(link.axis.data(), link.axis.data() + 3, key + n + 9);
  if (c->valid && std::memcmp(key, c->key, sizeof(key)) == 0) return *c;
  std::copy(key, key + size, c->key);
  c->origin_rotation = link.origin_rotation;
  c->correction_rotation = RpyRotation(p[kUrdfRx], p[kUrdfRy], p[kUrdfRz]);
  c->link_rotation = c->origin_rotation * c->correction_rotation;
  c->axis = c->correction_rotation * link.axis;
  Vector3d az;
  RpyAxes(p[kUrdfRy], p[kUrdfRz], &c->ax, &c->ay, &az);
  c->valid = true;
  return *c;
}

}  // namespace

PointJacobianWorkspace::PointJacobianWorkspace(const RobotModel& model)
    : urdf_(model.num_blocks()),
      parent_rotation_(model.num_joints() + 2),
      parent_translation_(model.num_joints() + 2),
      full_(3, model.num_parameters()),
      free_indices_(model.FreeParameterIndices()),
      block_offsets_(model.num_blocks()) {
  for (int b = 0; b < model.num_blocks(); ++b) {
    block_offsets_[b] = model.block_offset(b);
  }
}

void MeasuredPointJacobian(const RobotModel& model, const double* const* blocks,
                           const double* q, int marker,
                           PointJacobianWorkspace* workspace,
                           double* jacobian) {
  const int n = model.num_joints();
  std::vector<Matrix3d>& Rp = workspace->parent_rotation_;
  std::vector<Vector3d>& tp = workspace->parent_translation_;
  // Rp[b], tp[b]: the parent frame of block b (b = 0 base .. n links); the
  // entry n + 1 is the marker's parent (the tip frame).
  Rp[0].setIdentity();
  tp[0].setZero();
  Matrix3d R;
  Vector3d t;
  std::vector<PointJacobianWorkspace::UrdfLinkCache>& urdf = workspace->urdf_;
  for (int b = 0; b <= n; ++b) {
    const Link& link = model.link(b);
    const double qb = b == 0 ? 0.0 : q[b - 1];
    if (link.convention == LinkConvention::kUrdf) {
      UrdfTransform(link, blocks[b], qb,
                    PrepareUrdfLink(link, blocks[b], &urdf[b]), &R, &t);
    } else {
      LinkTransform(link, blocks[b], qb, &R, &t);
    }
    tp[b + 1] = tp[b] + Rp[b] * t;
    Rp[b + 1] = Rp[b] * R;
  }
  if (!model.tip.IsIdentity()) {
    tp[n + 1] += Rp[n + 1] * model.tip.translation;
    Rp[n + 1] = Rp[n + 1] * model.tip.rotation;
  }
  const double* m = blocks[model.marker_block(marker)];
  const Vector3d point = Rp[n + 1] * Vector3d(m[0], m[1], m[2]) + tp[n + 1];

  Eigen::Matrix<double, 3, Eigen::Dynamic>& full = workspace->full_;
  full.setZero();
  Vector3d col[kMaxBlockSize];
  for (int b = 0; b <= n; ++b) {
    const Vector3d y = Rp[b].transpose() * (point - tp[b]);
    LinkColumns(model.link(b), blocks[b], b == 0 ? 0.0 : q[b - 1], y, &urdf[b],
                col);
    const int offset = workspace->block_offsets_[b];
    for (int k = 0; k < model.block_size(b); ++k) {
      full.col(offset + k).noalias() = Rp[b] * col[k];
    }
  }
  // The marker's point moves with the tip frame; its angles do not move it.
  const int offset = workspace->block_offsets_[model.marker_block(marker)];
  full.middleCols<3>(offset) = Rp[n + 1];

  const std::vector<int>& free = workspace->free_indices_;
  const int num_free = static_cast<int>(free.size());
  for (int r = 0; r < 3; ++r) {
    for (int j = 0; j < num_free; ++j) {
      jacobian[r * num_free + j] = full(r, free[j]);
    }
  }
}

}  // namespace activecal
