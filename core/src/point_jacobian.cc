// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

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

// The world axes of the first two angles of R = Rz(rz) Ry(ry) Rx(rx): the
// derivative of R v by rx, ry is axis x (R v) (rz: the z axis).
void RpyAxes(double ry, double rz, Vector3d* ax, Vector3d* ay) {
  const double cy = std::cos(ry), sy = std::sin(ry);
  const double cz = std::cos(rz), sz = std::sin(rz);
  *ax << cz * cy, sz * cy, -sy;
  *ay << -sz, cz, 0.0;
}

}  // namespace

// Everything about one block that does not depend on the joint reading.
struct BlockPlan {
  LinkConvention convention = LinkConvention::kFrame;
  JointType joint_type = JointType::kFixed;
  // kUrdf: the link's nominal origin and unit axis (copied: the kernel
  // does not keep the model).
  Vector3d origin_xyz = Vector3d::Zero();
  Vector3d link_axis = Vector3d::UnitZ();
  double p[kMaxBlockSize] = {};
  // DH family: cos and sin of alpha and (Hayati) beta; for a joint that
  // does not turn, cos and sin of the columns' theta = gamma + 0.0 (the
  // columns' expression, which differs from the transform's in the sign of
  // a zero); for one that does not slide, the columns' d = d + 0.0.
  double ca = 1, sa = 0, cb = 1, sb = 0;
  double column_ct = 1, column_st = 0, column_d = 0;
  // kFrame: the constant transform and the axes of its angles.
  Matrix3d frame_rotation;
  Vector3d frame_translation;
  Vector3d ax, ay;  // also a URDF correction's RpyAxes
  // kUrdf: Ro, Rc, Ro Rc and Rc * axis.
  Matrix3d origin_rotation;
  Matrix3d correction_rotation;
  Matrix3d link_rotation;
  Vector3d axis;
  // The block's free entries and the output column of each.
  int num_free = 0;
  int entry[kMaxBlockSize] = {};
  int column[kMaxBlockSize] = {};
};

struct PointJacobianKernel::Plan {
  int num_joints = 0;
  int num_columns = 0;
  std::vector<BlockPlan> links;  // 0 base, 1..n the links
  bool has_tip = false;
  Matrix3d tip_rotation;
  Vector3d tip_translation;
  Vector3d marker;
  // The measured marker's free position entries (0..2) and their columns;
  // its free angles and other markers' free entries are zero columns.
  int num_marker_free = 0;
  int marker_entry[3] = {};
  int marker_column[3] = {};
  std::vector<int> zero_columns;
  // The base's frame in the device's frame (pose-independent).
  Matrix3d base_rotation;
  Vector3d base_translation;
};

namespace {

// The transform of a DH-family, frame or URDF block from its plan: the
// expressions (and so the bits) of LinkTransform, the pose-independent
// sines and cosines taken from the plan.
// The joint angle of a DH-family block and its cos and sin (what the
// transform uses); the prismatic length.
struct DhJoint {
  double ct = 1, st = 0, d = 0;
};

DhJoint PlannedDhJoint(const BlockPlan& b, double q) {
  const double* p = b.p;
  double theta = p[kGamma];
  double d = p[kD];
  if (b.joint_type == JointType::kRevolute) {
    theta += p[kGain] * q;
  } else if (b.joint_type == JointType::kPrismatic) {
    d += p[kGain] * q;
  }
  DhJoint j;
  j.ct = std::cos(theta);
  j.st = std::sin(theta);
  j.d = d;
  return j;
}

void PlannedTransform(const BlockPlan& b, double q, const DhJoint& joint,
                      Matrix3d* R, Vector3d* t) {
  const double* p = b.p;
  switch (b.convention) {
    case LinkConvention::kFrame:
      *R = b.frame_rotation;
      *t = b.frame_translation;
      return;
    case LinkConvention::kUrdf: {
      Vector3d tc(p[kUrdfX], p[kUrdfY], p[kUrdfZ]);
      const double s = p[kUrdfOffset] + p[kUrdfGain] * q;
      if (b.joint_type == JointType::kRevolute) {
        *R = b.link_rotation * AxisRotation(b.link_axis, s);
      } else {
        if (b.joint_type == JointType::kPrismatic) {
          tc += b.correction_rotation * (b.link_axis * s);
        }
        *R = b.link_rotation;
      }
      *t = b.origin_xyz + b.origin_rotation * tc;
      return;
    }
    default:
      break;
  }
  const double ct = joint.ct, st = joint.st, d = joint.d;
  const double ca = b.ca, sa = b.sa;
  if (b.convention == LinkConvention::kModifiedDH) {
    (*R) << ct, -st, 0.0, ca * st, ca * ct, -sa, sa * st, sa * ct, ca;
    (*t) << p[kA], -sa * d, ca * d;
    return;
  }
  (*R) << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0.0, sa, ca;
  (*t) << p[kA] * ct, p[kA] * st, d;
  if (b.convention == LinkConvention::kHayati) {
    const double cb = b.cb, sb = b.sb;
    const Vector3d c0 = R->col(0), c2 = R->col(2);
    R->col(0) = c0 * cb - c2 * sb;
    R->col(2) = c0 * sb + c2 * cb;
  }
}

// d(L x)/d p_k of entry k of block b, in the block's parent frame, for the
// point y = L x (parent frame) at joint reading q; `joint` the transform's
// DH joint (its cos and sin are the columns' for a revolute joint).
class BlockColumns {
 public:
  BlockColumns(const BlockPlan& b, double q, const DhJoint& joint,
               const Vector3d& y)
      : b_(b), q_(q), y_(y) {
    const double* p = b.p;
    switch (b.convention) {
      case LinkConvention::kFrame:
        w_ = Vector3d(y[0] - p[0], y[1] - p[1], y[2] - p[2]);
        break;
      case LinkConvention::kUrdf:
        w_ = b.origin_rotation.transpose() * (y - b.origin_xyz) -
             Vector3d(p[kUrdfX], p[kUrdfY], p[kUrdfZ]);
        break;
      case LinkConvention::kModifiedDH: {
        uz_ = Vector3d(0.0, -b.sa, b.ca);
        const Vector3d o(p[kA], 0.0, 0.0);
        about_ = uz_.cross(y - o);
        break;
      }
      default: {
        const bool revolute = b.joint_type == JointType::kRevolute;
        const bool prismatic = b.joint_type == JointType::kPrismatic;
        // gamma + gain q, d + gain q: the transform's; gamma + 0.0, d + 0.0
        // from the plan.
        ct_ = revolute ? joint.ct : b.column_ct;
        st_ = revolute ? joint.st : b.column_st;
        const double d = prismatic ? joint.d : b.column_d;
        const Vector3d o(p[kA] * ct_, p[kA] * st_, d);
        w_ = y - o;
        about_ = Vector3d(-y[1], y[0], 0.0);
        break;
      }
    }
  }

  Vector3d operator()(int k) const {
    const BlockPlan& b = b_;
    const Vector3d& y = y_;
    const bool revolute = b.joint_type == JointType::kRevolute;
    const bool prismatic = b.joint_type == JointType::kPrismatic;
    switch (b.convention) {
      case LinkConvention::kFrame:
        switch (k) {
          case 0:
            return Vector3d::UnitX();
          case 1:
            return Vector3d::UnitY();
          case 2:
            return Vector3d::UnitZ();
          case 3:
            return b.ax.cross(w_);
          case 4:
            return b.ay.cross(w_);
          default:
            return Vector3d::UnitZ().cross(w_);
        }
      case LinkConvention::kUrdf: {
        const Matrix3d& Ro = b.origin_rotation;
        switch (k) {
          case kUrdfX:
          case kUrdfY:
          case kUrdfZ:
            return Ro.col(k);
          case kUrdfRx:
            return Ro * b.ax.cross(w_);
          case kUrdfRy:
            return Ro * b.ay.cross(w_);
          case kUrdfRz:
            return Ro * Vector3d::UnitZ().cross(w_);
          default: {
            Vector3d motion = Vector3d::Zero();
            if (b.joint_type != JointType::kFixed) {
              motion = Ro * (revolute ? Vector3d(b.axis.cross(w_)) : b.axis);
            }
            return k == kUrdfOffset ? motion : Vector3d(q_ * motion);
          }
        }
      }
      case LinkConvention::kModifiedDH:
        switch (k) {
          case kGamma:
            return about_;
          case kAlpha:
            return Vector3d(0.0, -y[2], y[1]);
          case kA:
            return Vector3d::UnitX();
          case kD:
            return uz_;
          case kBeta:
            return Vector3d::Zero();
          default:
            return revolute
                       ? Vector3d(q_ * about_)
                       : (prismatic ? Vector3d(q_ * uz_) : Vector3d::Zero());
        }
      default:
        switch (k) {
          case kGamma:
            return about_;
          case kAlpha:
            return Vector3d(ct_, st_, 0.0).cross(w_);
          case kA:
            return Vector3d(ct_, st_, 0.0);
          case kD:
            return Vector3d::UnitZ();
          case kBeta:
            if (b.convention == LinkConvention::kHayati) {
              return Vector3d(-st_ * b.ca, ct_ * b.ca, b.sa).cross(w_);
            }
            return Vector3d::Zero();
          default:
            return revolute ? Vector3d(q_ * about_)
                            : (prismatic ? Vector3d(q_ * Vector3d::UnitZ())
                                         : Vector3d::Zero());
        }
    }
  }

 private:
  const BlockPlan& b_;
  const double q_;
  const Vector3d& y_;
  Vector3d w_, about_, uz_;
  double ct_ = 1, st_ = 0;
};

}  // namespace

PointJacobianKernel::PointJacobianKernel(const RobotModel& model,
                                         const double* const* blocks,
                                         int marker) {
  auto plan = std::make_unique<Plan>();
  const int n = model.num_joints();
  plan->num_joints = n;
  plan->links.resize(n + 1);
  // The output column of every free parameter.
  std::vector<int> column_of(model.num_parameters(), -1);
  const std::vector<int> free = model.FreeParameterIndices();
  for (int j = 0; j < static_cast<int>(free.size()); ++j)
    column_of[free[j]] = j;
  plan->num_columns = static_cast<int>(free.size());
  for (int b = 0; b <= n; ++b) {
    BlockPlan& bp = plan->links[b];
    const Link& link = model.link(b);
    bp.origin_xyz = link.origin_xyz;
    bp.link_axis = link.axis;
    bp.convention = link.convention;
    bp.joint_type = link.joint_type;
    const int size = model.block_size(b);
    std::copy(blocks[b], blocks[b] + size, bp.p);
    const double* p = bp.p;
    switch (link.convention) {
      case LinkConvention::kFrame:
        LinkTransform(link, p, 0.0, &bp.frame_rotation, &bp.frame_translation);
        RpyAxes(p[4], p[5], &bp.ax, &bp.ay);
        break;
      case LinkConvention::kUrdf:
        bp.origin_rotation = link.origin_rotation;
        bp.correction_rotation =
            RpyRotation(p[kUrdfRx], p[kUrdfRy], p[kUrdfRz]);
        bp.link_rotation = bp.origin_rotation * bp.correction_rotation;
        bp.axis = bp.correction_rotation * link.axis;
        RpyAxes(p[kUrdfRy], p[kUrdfRz], &bp.ax, &bp.ay);
        break;
      default:
        bp.ca = std::cos(p[kAlpha]);
        bp.sa = std::sin(p[kAlpha]);
        if (link.convention == LinkConvention::kHayati) {
          bp.cb = std::cos(p[kBeta]);
          bp.sb = std::sin(p[kBeta]);
        }
        {
          const double theta = p[kGamma] + 0.0;
          bp.column_ct = std::cos(theta);
          bp.column_st = std::sin(theta);
          bp.column_d = p[kD] + 0.0;
        }
        break;
    }
    const int offset = model.block_offset(b);
    for (int k = 0; k < size; ++k) {
      const int c = column_of[offset + k];
      if (c < 0) continue;
      bp.entry[bp.num_free] = k;
      bp.column[bp.num_free] = c;
      ++bp.num_free;
    }
  }
  for (int k = 0; k < model.num_markers(); ++k) {
    const int b = model.marker_block(k);
    const int offset = model.block_offset(b);
    for (int e = 0; e < model.block_size(b); ++e) {
      const int c = column_of[offset + e];
      if (c < 0) continue;
      if (k == marker && e < 3) {
        plan->marker_entry[plan->num_marker_free] = e;
        plan->marker_column[plan->num_marker_free] = c;
        ++plan->num_marker_free;
      } else {
        plan->zero_columns.push_back(c);
      }
    }
  }
  const double* m = blocks[model.marker_block(marker)];
  plan->marker = Vector3d(m[0], m[1], m[2]);
  plan->has_tip = !model.tip.IsIdentity();
  plan->tip_rotation = model.tip.rotation;
  plan->tip_translation = model.tip.translation;
  // The base: the same operations as a pose's first step, done once.
  const Matrix3d identity = Matrix3d::Identity();
  const Vector3d zero = Vector3d::Zero();
  Matrix3d R;
  Vector3d t;
  const BlockPlan& base = plan->links[0];
  const DhJoint base_joint = base.convention == LinkConvention::kFrame
                                 ? DhJoint()
                                 : PlannedDhJoint(base, 0.0);
  PlannedTransform(base, 0.0, base_joint, &R, &t);
  plan->base_translation = zero + identity * t;
  plan->base_rotation = identity * R;
  plan_ = std::move(plan);
}

PointJacobianKernel::~PointJacobianKernel() = default;
PointJacobianKernel::PointJacobianKernel(PointJacobianKernel&&) noexcept =
    default;
PointJacobianKernel& PointJacobianKernel::operator=(
    PointJacobianKernel&&) noexcept = default;

int PointJacobianKernel::num_columns() const { return plan_->num_columns; }

void PointJacobianKernel::Evaluate(int64_t num_poses, const double* joints,
                                   int64_t pose_stride, int64_t joint_stride,
                                   double* jacobian) const {
  const Plan& plan = *plan_;
  const int n = plan.num_joints;
  const int p = plan.num_columns;
  // Rp[b], tp[b]: the parent frame of block b (b = 0 base .. n links); the
  // entry n + 1 is the marker's parent (the tip frame).
  std::vector<Matrix3d> Rp(n + 2);
  std::vector<Vector3d> tp(n + 2);
  std::vector<double> q(n + 1, 0.0);  // q[b]: block b's reading
  std::vector<DhJoint> dh(n + 1);     // dh[b]: a DH-family block's joint
  if (plan.links[0].convention != LinkConvention::kFrame) {
    dh[0] = PlannedDhJoint(plan.links[0], 0.0);
  }
  Rp[0].setIdentity();
  tp[0].setZero();
  Rp[1] = plan.base_rotation;
  tp[1] = plan.base_translation;
  Matrix3d R;
  Vector3d t;
  for (int64_t i = 0; i < num_poses; ++i) {
    const double* qi = joints + i * pose_stride;
    for (int j = 0; j < n; ++j) q[j + 1] = qi[j * joint_stride];
    for (int b = 1; b <= n; ++b) {
      const BlockPlan& bp = plan.links[b];
      const bool dh_family = bp.convention != LinkConvention::kUrdf &&
                             bp.convention != LinkConvention::kFrame;
      if (dh_family) dh[b] = PlannedDhJoint(bp, q[b]);
      PlannedTransform(bp, q[b], dh[b], &R, &t);
      tp[b + 1] = tp[b] + Rp[b] * t;
      Rp[b + 1] = Rp[b] * R;
    }
    if (plan.has_tip) {
      tp[n + 1] += Rp[n + 1] * plan.tip_translation;
      Rp[n + 1] = Rp[n + 1] * plan.tip_rotation;
    }
    const Vector3d point = Rp[n + 1] * plan.marker + tp[n + 1];

    double* J = jacobian + 3 * p * i;
    for (int b = 0; b <= n; ++b) {
      const BlockPlan& bp = plan.links[b];
      if (bp.num_free == 0) continue;
      const Vector3d y = Rp[b].transpose() * (point - tp[b]);
      const BlockColumns columns(bp, q[b], dh[b], y);
      for (int f = 0; f < bp.num_free; ++f) {
        const Vector3d col = Rp[b] * columns(bp.entry[f]);
        const int c = bp.column[f];
        J[c] = col[0];
        J[p + c] = col[1];
        J[2 * p + c] = col[2];
      }
    }
    // The marker's point moves with the tip frame; its angles do not move
    // it.
    for (int f = 0; f < plan.num_marker_free; ++f) {
      const int c = plan.marker_column[f];
      const int e = plan.marker_entry[f];
      J[c] = Rp[n + 1](0, e);
      J[p + c] = Rp[n + 1](1, e);
      J[2 * p + c] = Rp[n + 1](2, e);
    }
    for (const int c : plan.zero_columns) {
      J[c] = 0.0;
      J[p + c] = 0.0;
      J[2 * p + c] = 0.0;
    }
  }
}

PointJacobianWorkspace::PointJacobianWorkspace(const RobotModel&) {}
PointJacobianWorkspace::~PointJacobianWorkspace() = default;

void MeasuredPointJacobian(const RobotModel& model, const double* const* blocks,
                           const double* q, int marker,
                           PointJacobianWorkspace* workspace,
                           double* jacobian) {
  // The key: the marker, every block's values and what the kernel takes
  // from the model (free set, conventions, URDF origins and axes, tip),
  // compared bit for bit.
  std::vector<double> key;
  key.reserve(2 + 2 * model.num_parameters() + 20 * model.num_blocks());
  key.push_back(marker);
  key.push_back(model.num_joints());
  for (int b = 0; b < model.num_blocks(); ++b) {
    const int size = model.block_size(b);
    key.insert(key.end(), blocks[b], blocks[b] + size);
    const int offset = model.block_offset(b);
    for (int k = 0; k < size; ++k) key.push_back(model.IsFree(offset + k));
    if (model.is_marker_block(b)) continue;
    const Link& link = model.link(b);
    key.push_back(static_cast<int>(link.convention));
    key.push_back(static_cast<int>(link.joint_type));
    key.insert(key.end(), link.origin_rotation.data(),
               link.origin_rotation.data() + 9);
    key.insert(key.end(), link.origin_xyz.data(), link.origin_xyz.data() + 3);
    key.insert(key.end(), link.axis.data(), link.axis.data() + 3);
  }
  key.insert(key.end(), model.tip.rotation.data(),
             model.tip.rotation.data() + 9);
  key.insert(key.end(), model.tip.translation.data(),
             model.tip.translation.data() + 3);
  if (!workspace->kernel_ || key.size() != workspace->key_.size() ||
      std::memcmp(key.data(), workspace->key_.data(),
                  key.size() * sizeof(double)) != 0) {
    workspace->kernel_ =
        std::make_unique<PointJacobianKernel>(model, blocks, marker);
    workspace->key_ = std::move(key);
  }
  workspace->kernel_->Evaluate(1, q, model.num_joints(), 1, jacobian);
}

}  // namespace activecal
