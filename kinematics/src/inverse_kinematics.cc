#include "activecal/kinematics/inverse_kinematics.h"

#include <ceres/jet.h>
#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "activecal/core/parallel.h"

namespace activecal {
namespace {

// Fixed-capacity matrices: no heap allocation inside an iteration.
using Jacobian =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, kMaxIkJoints>;
using Residual = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
using Square = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using Joints = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxIkJoints, 1>;

// Below this sigma_min / sigma_max a failure's message says the solver
// stopped near a singularity.
constexpr double kNearSingular = 1e-2;

std::string Number(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

// Where the joint reading enters link j's block: the entry that q is added
// to (gamma for a revolute DH link, d for a prismatic one, offset for a URDF
// joint) and the gain that scales it.
void JointEntries(const RobotModel& model, int j, int* offset, int* gain) {
  const Link& link = model.links[j];
  const int block = model.block_offset(j + 1);
  if (link.convention == LinkConvention::kUrdf) {
    *offset = block + kUrdfOffset;
    *gain = block + kUrdfGain;
  } else {
    *offset = block + (link.joint_type == JointType::kPrismatic ? kD : kGamma);
    *gain = block + kGain;
  }
}

// The marker frame and its exact joint Jacobian. The kinematics take joint
// readings as doubles, and each reading enters its link's block only as
// entry + gain * q; so the derivative of link j's transform in q_j is
// carried by a Jet<1> in that entry (value entry + gain * q_j, derivative
// gain) through the templated LinkTransform at q = 0: the same arithmetic
// as the double kinematics for the values. The chain is then composed in
// doubles, forward for the frames and backward for the marker's point in
// each link's frame:
//
//   dp/dq_j = R_{j-1} (dR_j s_j + dt_j),   w_j = R_{j-1} vee(dR_j R_j^T)
//
// with R_{j-1} the orientation before link j and s_j the marker point in
// link j's frame.
class ChainEvaluator {
 public:
  using Jet1 = ceres::Jet<double, 1>;

  ChainEvaluator(const RobotModel& model, const Eigen::VectorXd& parameters,
                 int marker)
      : model_(model), n_(model.num_joints()) {
    const std::vector<const double*> blocks =
        BlockPointers<double>(model, parameters.data());
    LinkTransform(model.base, blocks[0], 0.0, &base_R_, &base_t_);
    blocks_.resize(n_);
    fixed_R_.resize(n_);
    fixed_t_.resize(n_);
    offset_.resize(n_);
    entry_.resize(n_);
    gain_.resize(n_);
    for (int j = 0; j < n_; ++j) {
      const int size = model.block_size(j + 1);
      for (int k = 0; k < size; ++k) blocks_[j][k] = Jet1(blocks[j + 1][k]);
      int offset = 0, gain = 0;
      JointEntries(model, j, &offset, &gain);
      offset_[j] = offset - model.block_offset(j + 1);
      entry_[j] = parameters[offset];
      gain_[j] = parameters[gain];
      // A URDF joint's transform at motion 0: origin and correction.
      std::array<double, kMaxBlockSize> at_zero;
      std::copy(blocks[j + 1], blocks[j + 1] + size, at_zero.begin());
      at_zero[offset_[j]] = 0.0;
      LinkTransform(model.links[j], at_zero.data(), 0.0, &fixed_R_[j],
                    &fixed_t_[j]);
    }
    const double* m = blocks[model.marker_block(marker)];
    marker_point_ = Eigen::Vector3d(m[0], m[1], m[2]);
    marker_R_ = ToolRotation(m);
    R_.resize(n_);
    dR_.resize(n_);
    t_.resize(n_);
    dt_.resize(n_);
    before_.resize(n_);
  }

  // J: 3 rows (point) or 6 (point, then angular velocity).
  void Evaluate(const double* q, bool rotation, Eigen::Matrix3d* R,
                Eigen::Vector3d* t, Jacobian* J) {
    Eigen::Matrix3d Rc = base_R_;
    Eigen::Vector3d tc = base_t_;
    Matrix3<Jet1> Rj;
    Vector3<Jet1> tj;
    for (int j = 0; j < n_; ++j) {
      const Link& link = model_.links[j];
      const double value = entry_[j] + gain_[j] * q[j];
      if (link.convention == LinkConvention::kUrdf) {
        // Fixed part (origin and correction) times the motion along or
        // about the axis; only the motion depends on q.
        if (link.joint_type == JointType::kRevolute) {
          const Matrix3<Jet1> M = AxisRotation(link.axis, Jet1(value, 0));
          Eigen::Matrix3d Mv, dM;
          for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
              Mv(r, c) = M(r, c).a;
              dM(r, c) = M(r, c).v[0] * gain_[j];
            }
          }
          R_[j] = fixed_R_[j] * Mv;
          dR_[j] = fixed_R_[j] * dM;
          t_[j] = fixed_t_[j];
          dt_[j].setZero();
        } else {
          const Eigen::Vector3d direction = fixed_R_[j] * link.axis;
          R_[j] = fixed_R_[j];
          dR_[j].setZero();
          t_[j] = fixed_t_[j] + direction * value;
          dt_[j] = direction * gain_[j];
        }
      } else {
        Jet1& entry = blocks_[j][offset_[j]];
        entry.a = value;
        entry.v[0] = gain_[j];
        LinkTransform(link, blocks_[j].data(), 0.0, &Rj, &tj);
        for (int r = 0; r < 3; ++r) {
          t_[j][r] = tj[r].a;
          dt_[j][r] = tj[r].v[0];
          for (int c = 0; c < 3; ++c) {
            R_[j](r, c) = Rj(r, c).a;
            dR_[j](r, c) = Rj(r, c).v[0];
          }
        }
      }
      before_[j] = Rc;
      tc += Rc * t_[j];
      Rc = Rc * R_[j];
    }
    // As ForwardKinematics, then the marker (TargetFrame).
    Eigen::Vector3d s = marker_point_;
    if (!model_.tip.IsIdentity()) {
      tc += Rc * model_.tip.translation;
      Rc = Rc * model_.tip.rotation;
      s = model_.tip.rotation * marker_point_ + model_.tip.translation;
    }
    *t = Rc * marker_point_ + tc;
    *R = Rc * marker_R_;
    J->resize(rotation ? 6 : 3, n_);
    for (int j = n_ - 1; j >= 0; --j) {
      J->col(j).head<3>() = before_[j] * (dR_[j] * s + dt_[j]);
      if (rotation) {
        const Eigen::Matrix3d W = dR_[j] * R_[j].transpose();
        J->col(j).tail<3>() =
            before_[j] * Eigen::Vector3d(0.5 * (W(2, 1) - W(1, 2)),
                                         0.5 * (W(0, 2) - W(2, 0)),
                                         0.5 * (W(1, 0) - W(0, 1)));
      }
      s = R_[j] * s + t_[j];
    }
  }

 private:
  const RobotModel& model_;
  const int n_;
  Eigen::Matrix3d base_R_;
  Eigen::Vector3d base_t_;
  std::vector<std::array<Jet1, kMaxBlockSize>> blocks_;
  std::vector<int> offset_;
  std::vector<double> entry_;
  std::vector<double> gain_;
  Eigen::Vector3d marker_point_;
  Eigen::Matrix3d marker_R_;
  std::vector<Eigen::Matrix3d> fixed_R_;
  std::vector<Eigen::Vector3d> fixed_t_;
  std::vector<Eigen::Matrix3d> R_, dR_, before_;
  std::vector<Eigen::Vector3d> t_, dt_;
};

std::unique_ptr<ChainEvaluator> MakeEvaluator(const RobotModel& model,
                                              const Eigen::VectorXd& parameters,
                                              int marker) {
  return std::make_unique<ChainEvaluator>(model, parameters, marker);
}

bool CheckModelInputs(const RobotModel& model,
                      const Eigen::VectorXd& parameters, int marker,
                      std::string* error) {
  if (model.num_joints() < 1 || model.num_joints() > kMaxIkJoints) {
    *error = "inverse kinematics takes 1 to " + std::to_string(kMaxIkJoints) +
             " joints, robot '" + model.name + "' has " +
             std::to_string(model.num_joints());
    return false;
  }
  if (marker < 0 || marker >= model.num_markers()) {
    *error = "marker " + std::to_string(marker + 1) +
             " is not a marker of the model (it has " +
             std::to_string(model.num_markers()) + ")";
    return false;
  }
  return model.CheckParameters(parameters, error);
}

// The state of one iterate.
struct Iterate {
  Joints q;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  Jacobian J;  // weighted: rotation rows times the rotation weight
  Residual r;  // weighted residual, target - reached
  double position_error = 0.0;
  double rotation_error = 0.0;
  double cost = 0.0;
};

class IkSolver {
 public:
  IkSolver(const RobotModel& model, const Eigen::VectorXd& parameters,
           const InverseKinematicsOptions& options)
      : model_(model), options_(options), n_(model.num_joints()) {
    if (!options.IsValid(&setup_error_)) return;
    if (!CheckModelInputs(model, parameters, options.marker, &setup_error_)) {
      return;
    }
    evaluator_ = MakeEvaluator(model, parameters, options.marker);
    lower_.resize(n_);
    upper_.resize(n_);
    period_.resize(n_);
    for (int j = 0; j < n_; ++j) {
      lower_[j] = model.links[j].joint_min;
      upper_[j] = model.links[j].joint_max;
      // A revolute joint's reading enters as entry + gain * q into an
      // angle: the chain repeats itself every 2 pi / |gain| of q.
      int offset = 0, gain = 0;
      JointEntries(model, j, &offset, &gain);
      const double g = std::abs(parameters[gain]);
      period_[j] = model.links[j].joint_type == JointType::kRevolute && g > 0.0
                       ? 2.0 * M_PI / g
                       : 0.0;
    }
  }

  void Solve(const IkTarget& target, const Eigen::VectorXd& start,
             InverseKinematicsResult* result) {
    *result = InverseKinematicsResult();
    result->joints = start;
    result->status = IkStatus::kInvalid;
    if (!setup_error_.empty()) {
      result->message = setup_error_;
      return;
    }
    std::string why;
    if (!model_.CheckJointValues(start, &why)) {
      result->message = "start configuration: " + why;
      return;
    }
    if (!target.point.allFinite() || (pose() && !target.rotation.allFinite())) {
      result->message = "the target is not finite";
      return;
    }
    if (pose() && !(target.rotation.transpose() * target.rotation)
                       .isApprox(Eigen::Matrix3d::Identity(), 1e-9)) {
      result->message = "the target rotation is not a rotation matrix";
      return;
    }
    target_ = target;
    // CheckJointValues lets values a few ulps past a limit through.
    start_ = Clamp(start, /*limits=*/true);
    bool hit_cap = false;
    Run(options_.respect_limits, &current_, &hit_cap, &result->iterations);
    result->joints = current_.q;
    result->position_error_m = current_.position_error;
    result->rotation_error_rad = pose() ? current_.rotation_error : 0.0;
    result->conditioning = Conditioning(current_.J);
    const bool reached = Converged(current_);
    const bool singular = result->conditioning < options_.singular_threshold;
    if (reached) {
      result->status = singular ? IkStatus::kSingular : IkStatus::kConverged;
      if (singular) {
        result->message =
            "reached at a singular configuration "
            "(sigma_min / sigma_max = " +
            Number(result->conditioning) +
            "): nearby targets may need large joint motions";
      }
      return;
    }
    if (options_.respect_limits && AtALimit(current_.q)) {
      // Is it reachable with the limits lifted?
      Iterate free_iterate;
      bool free_cap = false;
      int free_iterations = 0;
      Run(false, &free_iterate, &free_cap, &free_iterations);
      result->iterations += free_iterations;
      if (Converged(free_iterate) && !OutsideLimits(free_iterate.q).empty()) {
        // The free run may have wound a revolute joint whole turns past a
        // wide range (a UR's +-2 pi): the same configuration, turned back
        // into the range, is a solution inside the limits.
        Joints wrapped = free_iterate.q;
        if (WrapIntoLimits(&wrapped)) {
          Iterate w;
          Evaluate(wrapped, &w);
          if (Converged(w)) free_iterate = w;
        }
      }
      if (Converged(free_iterate) && OutsideLimits(free_iterate.q).empty()) {
        // The path without limits found a solution inside them.
        current_ = free_iterate;
        result->joints = current_.q;
        result->position_error_m = current_.position_error;
        result->rotation_error_rad = pose() ? current_.rotation_error : 0.0;
        result->conditioning = Conditioning(current_.J);
        const bool at_singular =
            result->conditioning < options_.singular_threshold;
        result->status =
            at_singular ? IkStatus::kSingular : IkStatus::kConverged;
        if (at_singular) {
          result->message =
              "reached at a singular configuration "
              "(sigma_min / sigma_max = " +
              Number(result->conditioning) + ")";
        }
        return;
      }
      if (Converged(free_iterate)) {
        result->status = IkStatus::kLimit;
        result->message = "reachable only outside the joint limits:" +
                          OutsideLimits(free_iterate.q) +
                          "; the configuration returned stops at the limit "
                          "and misses by " +
                          Number(current_.position_error) + " m";
        return;
      }
    }
    if (hit_cap && singular) {
      result->status = IkStatus::kSingular;
      result->message =
          "not reached after " + std::to_string(result->iterations) +
          " iterations at a singular configuration (sigma_min / sigma_max = " +
          Number(result->conditioning) + "); misses by " +
          Number(current_.position_error) + " m";
      return;
    }
    result->status = IkStatus::kUnreachable;
    // Stalled at a singular configuration: a target beyond the workspace
    // (the arm at full stretch) or one behind a singularity on the start's
    // branch (a wrist flip) look alike from here.
    const bool stalled_singular =
        result->conditioning < options_.singular_threshold;
    result->message =
        std::string(stalled_singular
                        ? "out of reach, or behind a singularity on the "
                          "start's branch: "
                        : "out of reach: ") +
        "the closest configuration found misses "
        "the target by " +
        Number(current_.position_error) + " m" +
        (pose() ? " and " + Number(current_.rotation_error) + " rad"
                : std::string());
    if (result->conditioning < kNearSingular) {
      result->message +=
          ", stopped near a singularity (sigma_min / "
          "sigma_max = " +
          Number(result->conditioning) + ")";
    }
  }

 private:
  bool pose() const { return options_.match == IkMatch::kPose; }

  void Evaluate(const Joints& q, Iterate* it) const {
    it->q = q;
    evaluator_->Evaluate(q.data(), pose(), &it->R, &it->t, &it->J);
    it->r.resize(pose() ? 6 : 3);
    it->r.head<3>() = target_.point - it->t;
    it->position_error = it->r.head<3>().norm();
    if (pose()) {
      const Eigen::AngleAxisd e(target_.rotation * it->R.transpose());
      it->rotation_error = std::abs(e.angle());
      const double w = options_.rotation_weight_m;
      it->r.tail<3>() = w * e.angle() * e.axis();
      it->J.bottomRows<3>() *= w;
    }
    it->cost = it->r.squaredNorm();
  }

  bool Converged(const Iterate& it) const {
    return it.position_error <= options_.position_tolerance_m &&
           (!pose() || it.rotation_error <= options_.rotation_tolerance_rad);
  }

  bool AtALimit(const Joints& q) const {
    for (int j = 0; j < n_; ++j) {
      if (q[j] <= lower_[j] || q[j] >= upper_[j]) return true;
    }
    return false;
  }

  std::string OutsideLimits(const Joints& q) const {
    std::string text;
    for (int j = 0; j < n_; ++j) {
      if (q[j] >= lower_[j] && q[j] <= upper_[j]) continue;
      text += " joint " + std::to_string(j + 1) + " (" + model_.links[j].name +
              ") at " + Number(q[j]) + ", outside [" + Number(lower_[j]) +
              ", " + Number(upper_[j]) + "]";
    }
    return text;
  }

  // sigma_min / sigma_max of J (over its min(rows, cols) singular values),
  // from the eigenvalues of the smaller Gram matrix.
  static double Conditioning(const Jacobian& J) {
    double low = 0.0, top = 0.0;
    if (J.cols() < J.rows()) {
      const Eigen::MatrixXd JtJ = J.transpose() * J;
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(
          JtJ, Eigen::EigenvaluesOnly);
      low = eig.eigenvalues().minCoeff();
      top = eig.eigenvalues().maxCoeff();
    } else if (J.rows() == 3) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(Eigen::Matrix3d(J * J.transpose()),
                        Eigen::EigenvaluesOnly);
      low = eig.eigenvalues().minCoeff();
      top = eig.eigenvalues().maxCoeff();
    } else {
      using Matrix6d = Eigen::Matrix<double, 6, 6>;
      Eigen::SelfAdjointEigenSolver<Matrix6d> eig(Matrix6d(J * J.transpose()),
                                                  Eigen::EigenvaluesOnly);
      low = eig.eigenvalues().minCoeff();
      top = eig.eigenvalues().maxCoeff();
    }
    if (!(top > 0.0)) return 0.0;
    return std::sqrt(std::max(low, 0.0) / top);
  }

  // The damped step from `it` (see the header), holding joints at a limit
  // whose step points outward; with `pull`, the null-space pull to the
  // start.
  Joints Step(const Iterate& it, double mu, bool pull, bool limits) const {
    const int m = static_cast<int>(it.r.size());
    Eigen::Array<bool, Eigen::Dynamic, 1, 0, kMaxIkJoints, 1> held(n_);
    held.setConstant(false);
    Joints dq(n_);
    const Joints z = it.q - start_;
    for (int pass = 0; pass <= n_; ++pass) {
      Jacobian Jf = it.J;
      Joints zf = z;
      for (int j = 0; j < n_; ++j) {
        if (held[j]) {
          Jf.col(j).setZero();
          zf[j] = 0.0;
        }
      }
      if (!pull) zf.setZero();
      Square A = Jf * Jf.transpose();
      const double scale = std::max(A.trace() / m, 1e-12);
      A.diagonal().array() += mu * scale;
      const Residual b = it.r + Jf * zf;
      const Residual y = A.llt().solve(b);
      dq = Jf.transpose() * y - zf;
      if (!limits) break;
      bool changed = false;
      for (int j = 0; j < n_; ++j) {
        if (held[j]) continue;
        if ((it.q[j] <= lower_[j] && dq[j] < 0.0) ||
            (it.q[j] >= upper_[j] && dq[j] > 0.0)) {
          held[j] = true;
          changed = true;
        }
      }
      if (!changed) break;
    }
    return dq;
  }

  // Turns each revolute joint outside its range by whole periods into it,
  // as near the start as possible; false if some joint cannot be.
  bool WrapIntoLimits(Joints* q) const {
    for (int j = 0; j < n_; ++j) {
      double& v = (*q)[j];
      if (v >= lower_[j] && v <= upper_[j]) continue;
      const double p = period_[j];
      if (!(p > 0.0)) return false;
      // The turn count that brings v nearest the start, then into range.
      double k = std::round((start_[j] - v) / p);
      double best = v + k * p;
      if (best < lower_[j]) best += p * std::ceil((lower_[j] - best) / p);
      if (best > upper_[j]) best -= p * std::ceil((best - upper_[j]) / p);
      if (!(best >= lower_[j] && best <= upper_[j])) return false;
      v = best;
    }
    return true;
  }

  Joints Clamp(Joints q, bool limits) const {
    if (!limits) return q;
    for (int j = 0; j < n_; ++j)
      q[j] = std::min(std::max(q[j], lower_[j]), upper_[j]);
    return q;
  }

  // Levenberg-Marquardt from start_; *out is the last accepted iterate.
  void Run(bool limits, Iterate* out, bool* hit_cap, int* iterations) const {
    Iterate it, candidate;
    Evaluate(start_, &it);
    *iterations = 1;
    *hit_cap = false;
    double mu = 1e-8, nu = 2.0;
    const double kTinyStep = 1e-15;
    const double kPullTolerance = 1e-7;
    while (true) {
      if (*iterations >= options_.max_iterations) {
        *hit_cap = !Converged(it);
        break;
      }
      const double z_norm = (it.q - start_).norm();
      if (Converged(it)) {
        // Reached: move along the null space towards the start while the
        // target stays reached.
        // Without spare joints the solution is locally unique.
        if (z_norm == 0.0 || n_ <= static_cast<int>(it.r.size())) break;
        const Joints dq = Step(it, mu, /*pull=*/true, limits);
        // Closer than this to the closest solution is not worth a step.
        if (dq.norm() <= kPullTolerance * (1.0 + z_norm)) break;
        Evaluate(Clamp(it.q + dq, limits), &candidate);
        ++*iterations;
        // Each pull step shrinks the component of q - start along the null
        // space quadratically; near the end the change of |q - start| is
        // rounding, so a step is kept unless it leaves the target or moves
        // away from the start.
        if (Converged(candidate) &&
            (candidate.q - start_).norm() <= z_norm + 1e-12 * (1.0 + z_norm)) {
          std::swap(it, candidate);
          continue;
        }
        break;
      }
      bool accepted = false;
      for (int pass = 0; pass < 2 && !accepted; ++pass) {
        const bool pull = pass == 0;
        if (pull && z_norm == 0.0) continue;
        const Joints dq = Step(it, mu, pull, limits);
        if (dq.norm() <= kTinyStep * (1.0 + it.q.norm())) continue;
        Evaluate(Clamp(it.q + dq, limits), &candidate);
        ++*iterations;
        if (candidate.cost < it.cost) {
          // Nielsen's damping update from the gain ratio.
          const Joints taken = candidate.q - it.q;
          const double predicted =
              it.cost - (it.r - it.J * taken).squaredNorm();
          const double rho =
              predicted > 0.0 ? (it.cost - candidate.cost) / predicted : 0.0;
          const double decrease = it.cost - candidate.cost;
          const bool stalled =
              decrease <= 1e-14 * it.cost && !Converged(candidate);
          std::swap(it, candidate);
          accepted = true;
          const double f = 2.0 * rho - 1.0;
          mu = std::max(mu * std::max(1.0 / 3.0, 1.0 - f * f * f), 1e-12);
          nu = 2.0;
          if (stalled) mu = 1e30;  // no progress left: stop below
        }
        if (*iterations >= options_.max_iterations) break;
      }
      if (!accepted) {
        mu = std::max(mu * nu, 1e-4);
        nu *= 2.0;
      }
      if (mu > 1e8) break;
    }
    *out = it;
  }

  const RobotModel& model_;
  const InverseKinematicsOptions options_;
  const int n_;
  std::string setup_error_;
  std::unique_ptr<ChainEvaluator> evaluator_;
  Joints lower_, upper_;
  Joints period_;  // revolute joints: 2 pi / |gain|; 0 otherwise
  IkTarget target_;
  Joints start_;
  Iterate current_;
};

}  // namespace

const char* IkMatchName(IkMatch match) {
  return match == IkMatch::kPose ? "pose" : "position";
}

bool ParseIkMatch(const std::string& text, IkMatch* match) {
  if (text == "position") {
    *match = IkMatch::kPosition;
    return true;
  }
  if (text == "pose") {
    *match = IkMatch::kPose;
    return true;
  }
  return false;
}

const char* IkStatusName(IkStatus status) {
  switch (status) {
    case IkStatus::kConverged:
      return "converged";
    case IkStatus::kSingular:
      return "singular";
    case IkStatus::kLimit:
      return "limit";
    case IkStatus::kUnreachable:
      return "unreachable";
    case IkStatus::kInvalid:
      return "invalid";
  }
  return "unknown";
}

bool InverseKinematicsOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(position_tolerance_m > 0.0) || !std::isfinite(position_tolerance_m)) {
    return fail("position_tolerance_m must be finite and > 0, got " +
                Number(position_tolerance_m));
  }
  if (!(rotation_tolerance_rad > 0.0) ||
      !std::isfinite(rotation_tolerance_rad)) {
    return fail("rotation_tolerance_rad must be finite and > 0, got " +
                Number(rotation_tolerance_rad));
  }
  if (!(rotation_weight_m > 0.0) || !std::isfinite(rotation_weight_m)) {
    return fail("rotation_weight_m must be finite and > 0, got " +
                Number(rotation_weight_m));
  }
  if (max_iterations < 1) {
    return fail("max_iterations must be >= 1, got " +
                std::to_string(max_iterations));
  }
  if (!(singular_threshold >= 0.0) || !(singular_threshold < 1.0)) {
    return fail("singular_threshold must be in [0, 1), got " +
                Number(singular_threshold));
  }
  return true;
}

bool JointJacobian(const RobotModel& model, const Eigen::VectorXd& parameters,
                   const Eigen::VectorXd& q, int marker, Eigen::Matrix3d* R,
                   Eigen::Vector3d* t, Eigen::MatrixXd* jacobian,
                   std::string* error) {
  CHECK(R != nullptr && t != nullptr && jacobian != nullptr);
  std::string why;
  if (!CheckModelInputs(model, parameters, marker, &why)) {
    if (error) *error = why;
    return false;
  }
  if (q.size() != model.num_joints() || !q.allFinite()) {
    if (error) {
      *error = "expected " + std::to_string(model.num_joints()) +
               " finite joint values, got " + std::to_string(q.size());
    }
    return false;
  }
  auto evaluator = MakeEvaluator(model, parameters, marker);
  Jacobian J;
  evaluator->Evaluate(q.data(), /*rotation=*/true, R, t, &J);
  *jacobian = J;
  return true;
}

void SolveInverseKinematics(const RobotModel& model,
                            const Eigen::VectorXd& parameters,
                            const IkTarget& target,
                            const Eigen::VectorXd& start,
                            const InverseKinematicsOptions& options,
                            InverseKinematicsResult* result) {
  CHECK(result != nullptr);
  IkSolver solver(model, parameters, options);
  solver.Solve(target, start, result);
}

void SolveInverseKinematicsBatch(
    const RobotModel& model, const Eigen::VectorXd& parameters,
    const std::vector<IkTarget>& targets, const Eigen::MatrixXd& starts,
    const InverseKinematicsOptions& options, int num_threads,
    std::vector<InverseKinematicsResult>* results) {
  CHECK(results != nullptr);
  CHECK_EQ(starts.rows(), static_cast<int64_t>(targets.size()));
  results->assign(targets.size(), InverseKinematicsResult());
  ParallelFor(static_cast<int64_t>(targets.size()), num_threads,
              [&](int64_t begin, int64_t end, int /*thread*/) {
                IkSolver solver(model, parameters, options);
                for (int64_t i = begin; i < end; ++i) {
                  solver.Solve(targets[i], starts.row(i).transpose(),
                               &(*results)[i]);
                }
              });
}

}  // namespace activecal
