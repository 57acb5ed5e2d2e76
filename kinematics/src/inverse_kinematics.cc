// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

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

#include "activecal/core/enum_name_list.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/parallel.h"
#include "activecal/core/text_table.h"

namespace activecal {
namespace {

// Fixed-capacity matrices: no heap allocation inside an iteration.
using Jacobian =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, kMaxIkJoints>;
using Residual = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
using Square = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using Joints = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxIkJoints, 1>;

// A^-1 c for a symmetric positive definite A of 3 or 6 rows (the damped
// normal matrix of a position or pose step) by a Cholesky factorisation of
// fixed size (a third of the instructions of the dynamic-size one).
template <typename Square, typename Residual>
Residual SolvePositiveDefinite(const Square& A, const Residual& c) {
  if (A.rows() == 6) {
    using Matrix6d = Eigen::Matrix<double, 6, 6>;
    using Vector6d = Eigen::Matrix<double, 6, 1>;
    return Residual(Eigen::LLT<Matrix6d>(Matrix6d(A)).solve(Vector6d(c)));
  }
  if (A.rows() == 3) {
    return Residual(Eigen::LLT<Eigen::Matrix3d>(Eigen::Matrix3d(A))
                        .solve(Eigen::Vector3d(c)));
  }
  return A.llt().solve(c);
}

// Below this sigma_min / sigma_max a failure's message says the solver
// stopped near a singularity.
constexpr double kNearSingular = 1e-2;

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
    values_.resize(n_);
    fixed_R_.resize(n_);
    fixed_t_.resize(n_);
    offset_.resize(n_);
    entry_.resize(n_);
    gain_.resize(n_);
    for (int j = 0; j < n_; ++j) {
      const int size = model.block_size(j + 1);
      for (int k = 0; k < size; ++k) {
        blocks_[j][k] = Jet1(blocks[j + 1][k]);
        values_[j][k] = blocks[j + 1][k];
      }
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

  // The marker frame at q only, in doubles: the same arithmetic as the
  // values of Evaluate (a Jet's value is computed as the double), so the
  // same bits, at about half its cost. For trial steps, which are kept
  // only when they lower the merit.
  void Pose(const double* q, Eigen::Matrix3d* R, Eigen::Vector3d* t) {
    Eigen::Matrix3d Rc = base_R_;
    Eigen::Vector3d tc = base_t_;
    Eigen::Matrix3d Rj;
    Eigen::Vector3d tj;
    for (int j = 0; j < n_; ++j) {
      const Link& link = model_.links[j];
      const double value = entry_[j] + gain_[j] * q[j];
      if (link.convention == LinkConvention::kUrdf) {
        if (link.joint_type == JointType::kRevolute) {
          Rj = fixed_R_[j] * AxisRotation(link.axis, value);
          tj = fixed_t_[j];
        } else {
          Rj = fixed_R_[j];
          tj = fixed_t_[j] + (fixed_R_[j] * link.axis) * value;
        }
      } else {
        values_[j][offset_[j]] = value;
        LinkTransform(link, values_[j].data(), 0.0, &Rj, &tj);
      }
      tc += Rc * tj;
      Rc = Rc * Rj;
    }
    if (!model_.tip.IsIdentity()) {
      tc += Rc * model_.tip.translation;
      Rc = Rc * model_.tip.rotation;
    }
    *t = Rc * marker_point_ + tc;
    *R = Rc * marker_R_;
  }

 private:
  const RobotModel& model_;
  const int n_;
  Eigen::Matrix3d base_R_;
  Eigen::Vector3d base_t_;
  std::vector<std::array<Jet1, kMaxBlockSize>> blocks_;
  std::vector<std::array<double, kMaxBlockSize>> values_;  // the same, doubles
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
    if (!options.joint_weights.empty() &&
        static_cast<int>(options.joint_weights.size()) != n_) {
      setup_error_ = "joint_weights: expected " + std::to_string(n_) +
                     " weights (one per joint), got " +
                     std::to_string(options.joint_weights.size());
      return;
    }
    evaluator_ = MakeEvaluator(model, parameters, options.marker);
    weight_.setOnes(n_);
    for (size_t j = 0; j < options.joint_weights.size(); ++j) {
      weight_[j] = options.joint_weights[j];
    }
    lower_.resize(n_);
    upper_.resize(n_);
    period_.resize(n_);
    wraps_.resize(n_);
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
      // A range of a whole period or more (a UR's +-2 pi, a continuous
      // joint) holds an equivalent of every value. On a chain without
      // spare joints (whose solutions are isolated points) the runs let
      // such a joint through its limits, and the solution found is turned
      // back inside them by whole periods (NearestEquivalentInLimits):
      // stopped at the limit instead, a run from a start near +-2 pi spent
      // its evaluations against it and left the target to a second run
      // without limits. A redundant chain keeps the limits: there the
      // solution inside them next to the start is the one wanted, and one
      // through the limit turned back by a period is a whole turn away.
      const bool spare = n_ > (options.match == IkMatch::kPose ? 6 : 3);
      wraps_[j] =
          !spare && period_[j] > 0.0 && upper_[j] - lower_[j] >= period_[j];
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
    // The rotation too when only the point is matched: a non-finite one is
    // bad input, not something to ignore.
    if (!target.point.allFinite() || !target.rotation.allFinite()) {
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
    const bool limits = options_.respect_limits;
    RunResult limited;
    Run(limits, start_, options_.max_iterations, &limited);
    result->iterations = limited.iterations;
    // The candidates (see the header): the run inside the limits; when it
    // met a limit on the way, the run without them; when the best of those
    // turns a joint by more than half a turn, runs from restart points.
    // Each is taken with its revolute joints turned by whole periods to the
    // equivalent inside the limits nearest the start, and the one of
    // smallest weighted joint change wins.
    Iterate best;
    double best_change = HUGE_VAL;
    auto consider = [&](const Iterate& candidate) {
      if (!Converged(candidate)) return;
      Iterate equivalent = candidate;
      if (limits) {
        Joints q = candidate.q;
        if (!NearestEquivalentInLimits(&q)) return;
        if (q != candidate.q) {
          Evaluate(q, &equivalent);
          if (!Converged(equivalent)) return;
        }
      }
      const double change = Change(equivalent.q);
      if (change < best_change) {
        best_change = change;
        best = equivalent;
      }
    };
    consider(limited.last);
    // Runs from the first `count` restart points while `more()` holds, each
    // with a shorter cap: a restart in the basin of a solution reaches it in
    // a few evaluations.
    auto restart = [&](int count, auto more) {
      constexpr int kRestartIterations = 30;
      const int cap = std::min(options_.max_iterations, kRestartIterations);
      for (int k = 0; k < count && more(); ++k) {
        RunResult again;
        Run(true, RestartPoint(k), cap, &again);
        result->iterations += again.iterations;
        consider(again.last);
      }
    };
    RunResult free;
    bool ran_free = false;
    if (limits && limited.met_limit) {
      Run(false, start_, options_.max_iterations, &free);
      ran_free = true;
      result->iterations += free.iterations;
      consider(free.last);
    }
    if (limits && best_change < HUGE_VAL && TurnsAJoint(best.q)) {
      // The best so far turns a joint by more than half a turn: other
      // solutions inside the limits near the start (another of the arm's
      // branches, close to it near a singularity) are looked for from
      // starts spread around the start, until one turns no joint by more
      // than half a turn.
      restart(options_.restarts, [&] { return TurnsAJoint(best.q); });
    }
    if (limits && best_change == HUGE_VAL && !limited.hit_cap &&
        !(ran_free && Converged(free.last))) {
      // Not reached, and not for the cap or a limit: the run stalled (a
      // local minimum of the merit, often at a singular configuration on
      // the start's branch) or the target is out of reach. A few runs from
      // the first restart points tell the two apart (measured in
      // docs/compensation.md: UR10e pose targets from starts 3 rad off).
      constexpr int kFailureRestarts = 4;
      restart(std::min(options_.restarts, kFailureRestarts),
              [&] { return best_change == HUGE_VAL; });
    }
    if (best_change < HUGE_VAL) {
      SetResult(best, result);
      const bool singular = result->conditioning < options_.singular_threshold;
      result->status = singular ? IkStatus::kSingular : IkStatus::kConverged;
      if (singular) {
        result->message =
            "reached at a singular configuration "
            "(sigma_min / sigma_max = " +
            FormatNumber("%.6g", result->conditioning) +
            "): nearby targets may need large joint motions";
      }
      return;
    }
    // Not reached inside the limits: the run inside them is returned, its
    // joints that wrap turned back inside the limits.
    Iterate at = limited.last;
    if (limits) {
      Joints q = at.q;
      if (NearestEquivalentInLimits(&q) && q != at.q) Evaluate(q, &at);
    }
    SetResult(at, result);
    const std::string misses =
        FormatNumber("%.6g", at.position_error) + " m" +
        (pose() ? " and " + FormatNumber("%.6g", at.rotation_error) + " rad"
                : std::string());
    const std::string near_singular =
        result->conditioning < kNearSingular
            ? ", near a singularity (sigma_min / sigma_max = " +
                  FormatNumber("%.6g", result->conditioning) + ")"
            : std::string();
    if (ran_free && Converged(free.last)) {
      result->status = IkStatus::kLimit;
      result->message = "reachable only outside the joint limits:" +
                        OutsideLimits(free.last.q) +
                        "; the configuration returned stops at the limit "
                        "and misses by " +
                        FormatNumber("%.6g", at.position_error) + " m";
      return;
    }
    if (limited.hit_cap) {
      result->status = IkStatus::kIterationCap;
      result->message = "the iteration cap (max_iterations = " +
                        std::to_string(options_.max_iterations) +
                        ") was hit before the target was reached: the "
                        "configuration returned misses by " +
                        misses + near_singular;
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
        "the closest configuration found misses the target by " + misses;
    if (result->conditioning < kNearSingular) {
      result->message +=
          ", stopped near a singularity (sigma_min / "
          "sigma_max = " +
          FormatNumber("%.6g", result->conditioning) + ")";
    }
  }

 private:
  // What one Levenberg-Marquardt run ends with.
  struct RunResult {
    Iterate last;            // the last accepted iterate
    bool hit_cap = false;    // stopped by max_iterations, not reached
    bool met_limit = false;  // some step was bounded by a joint limit
    int iterations = 0;      // Jacobian evaluations
  };

  // The weighted joint change sum_j w_j (q_j - start_j)^2.
  double Change(const Joints& q) const {
    return (q - start_).cwiseAbs2().cwiseProduct(weight_).sum();
  }

  // True when some revolute joint of q is more than half a turn from the
  // start.
  bool TurnsAJoint(const Joints& q) const {
    for (int j = 0; j < n_; ++j) {
      if (period_[j] > 0.0 && std::abs(q[j] - start_[j]) > 0.5 * period_[j]) {
        return true;
      }
    }
    return false;
  }

  // Restart k: the start with each revolute joint moved by up to
  // options_.restart_spread_rad, the k-th point of a Halton sequence (one
  // prime base per joint: deterministic, and evenly spread for any number
  // of restarts), clamped to the limits.
  Joints RestartPoint(int k) const {
    static constexpr int kPrimes[kMaxIkJoints] = {
        2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};
    Joints q = start_;
    for (int j = 0; j < n_; ++j) {
      if (!(period_[j] > 0.0)) continue;
      double u = 0.0, f = 1.0;
      for (int i = k + 1; i > 0; i /= kPrimes[j]) {
        f /= kPrimes[j];
        u += f * (i % kPrimes[j]);
      }
      q[j] += options_.restart_spread_rad * (2.0 * u - 1.0);
    }
    return Clamp(q, /*limits=*/true);
  }

  void SetResult(const Iterate& it, InverseKinematicsResult* result) const {
    result->joints = it.q;
    result->position_error_m = it.position_error;
    result->rotation_error_rad = pose() ? it.rotation_error : 0.0;
    result->conditioning = Conditioning(it.J);
  }

  bool pose() const { return options_.match == IkMatch::kPose; }

  // The iterate at q; without `jacobian` its pose and residual only (J is
  // left as it was: a trial step's, completed by Evaluate(q, it) when the
  // step is kept).
  void Evaluate(const Joints& q, Iterate* it, bool jacobian = true) const {
    it->q = q;
    if (jacobian) {
      evaluator_->Evaluate(q.data(), pose(), &it->R, &it->t, &it->J);
    } else {
      evaluator_->Pose(q.data(), &it->R, &it->t);
    }
    it->r.resize(pose() ? 6 : 3);
    it->r.head<3>() = target_.point - it->t;
    it->position_error = it->r.head<3>().norm();
    if (pose()) {
      const Eigen::AngleAxisd e(target_.rotation * it->R.transpose());
      it->rotation_error = std::abs(e.angle());
      const double w = options_.rotation_weight_m;
      it->r.tail<3>() = w * e.angle() * e.axis();
      if (jacobian) it->J.bottomRows<3>() *= w;
    }
    it->cost = it->r.squaredNorm();
  }

  bool Converged(const Iterate& it) const {
    return it.position_error <= options_.position_tolerance_m &&
           (!pose() || it.rotation_error <= options_.rotation_tolerance_rad);
  }

  std::string OutsideLimits(const Joints& q) const {
    std::string text;
    for (int j = 0; j < n_; ++j) {
      if (q[j] >= lower_[j] && q[j] <= upper_[j]) continue;
      text += " joint " + std::to_string(j + 1) + " (" + model_.links[j].name +
              ") at " + FormatNumber("%.6g", q[j]) + ", outside [" +
              FormatNumber("%.6g", lower_[j]) + ", " +
              FormatNumber("%.6g", upper_[j]) + "]";
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

  // The damped step from `it` (see the header): with `pull` the minimiser
  // of
  //
  //   |J dq - r|^2 + lambda |dq + z|_W^2,   z = q - q_start
  //
  // (|x|_W^2 = sum_j w_j x_j^2, the joint weights)
  // (without, z = 0), and with `limits` subject to lower <= q + dq <= upper,
  // so that the step itself respects the limits (a step clipped afterwards
  // is no longer a descent direction of the merit: joints pushed to their
  // limits one after the other stalled the solver away from solutions
  // inside them). The box-constrained problem is solved exactly by a
  // primal active-set method in u = dq + z: joints at a bound are fixed
  // there, the free ones take the damped minimum-norm solution
  // W_F^-1 J_F^T (J_F W_F^-1 J_F^T + lambda I)^-1 (b - J_A u_A),
  // b = r + J z; a free
  // joint that would cross its bound stops there and joins the active set;
  // an active joint whose multiplier says the merit falls inwards leaves
  // it. Every iterate of the method is feasible; it ends at the
  // Karush-Kuhn-Tucker point (a strictly convex problem: the minimiser).
  // *bounded: a joint limit was active at the end.
  Joints Step(const Iterate& it, double mu, bool pull, bool limits,
              bool* bounded) const {
    const int m = static_cast<int>(it.r.size());
    const Joints z = pull ? Joints(it.q - start_) : Joints::Zero(n_);
    const Residual b = it.r + it.J * z;
    // J W^-1: the weighted columns.
    Jacobian Jw = it.J;
    for (int j = 0; j < n_; ++j) Jw.col(j) /= weight_[j];
    // trace(J W^-1 J^T) / m
    const double scale = std::max((Jw.cwiseProduct(it.J)).sum() / m, 1e-12);
    const double lambda = mu * scale;
    // Bounds of u; joints at a limit start active (u = z is dq = 0).
    Joints lo(n_), hi(n_), u = z;
    // 0 free, -1 at its lower bound, +1 at its upper bound.
    Eigen::Array<int, Eigen::Dynamic, 1, 0, kMaxIkJoints, 1> active(n_);
    active.setZero();
    // Inside the limits each joint also moves at most kMaxStep per step (a
    // trust region): the exact box-constrained Gauss-Newton step from a
    // start far from the target (the PUMA's nominal geometry, 0.6 m off)
    // jumped to the limits of four joints at once and lowered the merit
    // enough to be kept, into a region it never left.
    constexpr double kMaxStep = 0.5;  // rad, or m
    Eigen::Array<bool, Eigen::Dynamic, 1, 0, kMaxIkJoints, 1> limit_lo(n_),
        limit_hi(n_);
    for (int j = 0; j < n_; ++j) {
      const double down = lower_[j] - it.q[j], up = upper_[j] - it.q[j];
      // A joint that wraps keeps the trust region, not the limits.
      const bool bound = limits && !wraps_[j];
      limit_lo[j] = bound && down >= -kMaxStep;
      limit_hi[j] = bound && up <= kMaxStep;
      lo[j] = limits ? (bound ? std::max(down, -kMaxStep) : -kMaxStep) + z[j]
                     : -HUGE_VAL;
      hi[j] = limits ? (bound ? std::min(up, kMaxStep) : kMaxStep) + z[j]
                     : HUGE_VAL;
      if (bound && it.q[j] >= upper_[j]) active[j] = 1;
      if (bound && it.q[j] <= lower_[j]) active[j] = -1;
    }
    for (int pass = 0; pass < 4 * n_ + 4; ++pass) {
      // The free joints' minimiser with the active ones held.
      Jacobian Jf = Jw;
      Residual c = b;
      for (int j = 0; j < n_; ++j) {
        if (active[j] != 0) {
          c -= it.J.col(j) * u[j];
          Jf.col(j).setZero();
        }
      }
      Square A = Jf * it.J.transpose();
      A.diagonal().array() += lambda;
      const Residual y = SolvePositiveDefinite(A, c);
      const Joints target = Jf.transpose() * y;
      // As far towards it as the bounds let the free joints go.
      double alpha = 1.0;
      int blocking = -1;
      for (int j = 0; j < n_; ++j) {
        if (active[j] != 0) continue;
        const double p = target[j] - u[j];
        if (u[j] + p > hi[j] && p > 0.0) {
          const double a = (hi[j] - u[j]) / p;
          if (a < alpha) alpha = a, blocking = j;
        } else if (u[j] + p < lo[j] && p < 0.0) {
          const double a = (lo[j] - u[j]) / p;
          if (a < alpha) alpha = a, blocking = j;
        }
      }
      for (int j = 0; j < n_; ++j) {
        if (active[j] == 0) u[j] += alpha * (target[j] - u[j]);
      }
      if (blocking >= 0) {
        const bool upper =
            target[blocking] > u[blocking] ||
            hi[blocking] - u[blocking] < u[blocking] - lo[blocking];
        u[blocking] = upper ? hi[blocking] : lo[blocking];
        active[blocking] = upper ? 1 : -1;
        continue;
      }
      if ((active == 0).all()) break;
      // Multipliers of the active bounds: half the gradient of the merit.
      const Joints g =
          it.J.transpose() * (it.J * u - b) + lambda * weight_.cwiseProduct(u);
      const double tolerance = 1e-13 * (1.0 + g.cwiseAbs().maxCoeff());
      int release = -1;
      double worst = tolerance;
      for (int j = 0; j < n_; ++j) {
        // At the lower bound the merit falls inwards when g_j < 0; at the
        // upper one when g_j > 0. A joint whose range is a point stays.
        const double inwards = active[j] < 0 ? -g[j] : active[j] > 0 ? g[j] : 0;
        if (inwards > worst && lo[j] < hi[j]) worst = inwards, release = j;
      }
      if (release < 0) break;
      active[release] = 0;
    }
    *bounded = false;
    for (int j = 0; j < n_; ++j) {
      *bounded |=
          (active[j] < 0 && limit_lo[j]) || (active[j] > 0 && limit_hi[j]);
    }
    return u - z;
  }

  // Turns each revolute joint by whole periods to the equivalent value
  // inside its limits nearest the start (the change |q - start| is a sum
  // over joints, so this is the closest equivalent configuration); false
  // when some joint has none (a joint outside a range narrower than a
  // turn, or a prismatic one outside its range).
  bool NearestEquivalentInLimits(Joints* q) const {
    for (int j = 0; j < n_; ++j) {
      double& v = (*q)[j];
      const double p = period_[j];
      if (!(p > 0.0)) {
        if (!(v >= lower_[j] && v <= upper_[j])) return false;
        continue;
      }
      // The turns k that keep v + k p inside [lower, upper] ...
      const double k_min = std::isfinite(lower_[j])
                               ? std::ceil((lower_[j] - v) / p - 1e-12)
                               : -HUGE_VAL;
      const double k_max = std::isfinite(upper_[j])
                               ? std::floor((upper_[j] - v) / p + 1e-12)
                               : HUGE_VAL;
      if (k_min > k_max) return false;
      // ... and of those the one nearest the start (|v + k p - s| is
      // convex in k).
      const double k =
          std::min(std::max(std::round((start_[j] - v) / p), k_min), k_max);
      if (k != 0.0) v = std::min(std::max(v + k * p, lower_[j]), upper_[j]);
      if (!(v >= lower_[j] && v <= upper_[j])) return false;
    }
    return true;
  }

  // q inside the limits (with `limits`); with `wrapping` the joints that
  // wrap are left where they are (a run's iterate).
  Joints Clamp(Joints q, bool limits, bool wrapping = false) const {
    if (!limits) return q;
    for (int j = 0; j < n_; ++j) {
      if (wrapping && wraps_[j]) continue;
      q[j] = std::min(std::max(q[j], lower_[j]), upper_[j]);
    }
    return q;
  }

  // Levenberg-Marquardt from `from` (inside the limits when `limits`), its
  // null-space pull towards start_, for at most max_iterations Jacobian
  // evaluations.
  void Run(bool limits, const Joints& from, int max_iterations,
           RunResult* out) const {
    Iterate it, candidate, corrected;
    Evaluate(from, &it);
    int iterations = 1;
    bool met_limit = false;
    bool hit_cap = false;
    double mu = 1e-8, nu = 2.0;
    const double kTinyStep = 1e-15;
    const double kPullTolerance = 1e-7;
    // The merit of the last kWindow passes, to tell at the cap a run still
    // making progress from one stalled on a target it cannot reach.
    constexpr int kWindow = 10;
    std::array<double, kWindow> recent;
    recent.fill(HUGE_VAL);
    int passes = 0;
    const bool spare = n_ > (pose() ? 6 : 3);
    while (true) {
      if (iterations >= max_iterations) {
        // Stopped by the cap with the merit still falling (by more than
        // kStillFalling of itself over the last kWindow passes): more
        // iterations may reach the target. Falling slower, the run has
        // stalled (a target out of reach, where damped steps creep to
        // the nearest configuration).
        constexpr double kStillFalling = 1e-2;
        // (Fewer passes: since the first. None: the cap hit at once.)
        const double before = recent[passes >= kWindow ? passes % kWindow : 0];
        hit_cap = !Converged(it) &&
                  (passes == 0 || before - it.cost > kStillFalling * before);
        break;
      }
      recent[passes % kWindow] = it.cost;
      ++passes;
      const double z_norm = (it.q - start_).norm();
      if (Converged(it)) {
        // Reached: move along the null space towards the start while the
        // target stays reached.
        // Without spare joints the solution is locally unique.
        if (z_norm == 0.0 || n_ <= static_cast<int>(it.r.size())) break;
        bool bounded = false;
        const Joints dq = Step(it, mu, /*pull=*/true, limits, &bounded);
        met_limit |= bounded;
        // Closer than this to the closest solution is not worth a step.
        if (dq.norm() <= kPullTolerance * (1.0 + z_norm)) break;
        // The pull step runs along the tangent of the (curved) set of
        // solutions: a predictor, brought back to the target by a few
        // steps without pull (a corrector: their minimum-norm motion is
        // across the set, so it changes |q - start|_W to second order
        // only). The predictor is halved until the corrected configuration
        // reaches the target closer to the start; near the end each step
        // shrinks the distance along the set quadratically.
        const double change = Change(it.q);
        bool improved = false;
        double alpha = 1.0;
        for (int halving = 0; halving < 3 && !improved; ++halving) {
          if (iterations >= max_iterations) break;
          Evaluate(Clamp(it.q + alpha * dq, limits, /*wrapping=*/true),
                   &candidate);
          ++iterations;
          for (int correct = 0; correct < 3 && !Converged(candidate) &&
                                iterations < max_iterations;
               ++correct) {
            bool ignored = false;
            const Joints dc =
                Step(candidate, 1e-12, /*pull=*/false, limits, &ignored);
            Evaluate(Clamp(candidate.q + dc, limits, /*wrapping=*/true),
                     &corrected);
            ++iterations;
            if (!(corrected.cost < candidate.cost)) break;
            std::swap(candidate, corrected);
          }
          // Near the end the change of |q - start|_W is rounding: a step
          // is kept unless it moves away from the start.
          improved = Converged(candidate) &&
                     Change(candidate.q) <= change + 1e-12 * (1.0 + change);
          alpha *= 0.25;
        }
        if (!improved) break;
        std::swap(it, candidate);
        continue;
      }
      bool accepted = false;
      for (int pass = 0; pass < 2 && !accepted; ++pass) {
        const bool pull = pass == 0;
        // The pull acts in the null space of J only as lambda -> 0; in the
        // damped step it also leaks into the directions the Jacobian
        // barely moves (sigma^2 ~ lambda), where it holds the iterate at a
        // point short of the target. A chain with no spare joints has no
        // null space to pull along: no pull at all (near a wrist
        // singularity the pulled step crept for ~150 evaluations 2.5 mm
        // from a UR10e pose target it then reached).
        if (pull && (z_norm == 0.0 || !spare)) continue;
        bool bounded = false;
        const Joints dq = Step(it, mu, pull, limits, &bounded);
        met_limit |= bounded;
        if (dq.norm() <= kTinyStep * (1.0 + it.q.norm())) continue;
        // The trial by its pose only: the Jacobian is evaluated when the
        // step is kept (a rejected trial costs a forward pass).
        Evaluate(Clamp(it.q + dq, limits, /*wrapping=*/true), &candidate,
                 /*jacobian=*/false);
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
          Evaluate(candidate.q, &candidate);
          ++iterations;
          std::swap(it, candidate);
          accepted = true;
          const double f = 2.0 * rho - 1.0;
          mu = std::max(mu * std::max(1.0 / 3.0, 1.0 - f * f * f), 1e-12);
          nu = 2.0;
          if (stalled) mu = 1e30;  // no progress left: stop below
        }
        if (iterations >= max_iterations) break;
      }
      if (!accepted) {
        mu = std::max(mu * nu, 1e-4);
        nu *= 2.0;
      }
      if (mu > 1e8) break;
    }
    out->last = it;
    out->hit_cap = hit_cap;
    out->met_limit = met_limit;
    out->iterations = iterations;
  }

  const RobotModel& model_;
  const InverseKinematicsOptions options_;
  const int n_;
  std::string setup_error_;
  std::unique_ptr<ChainEvaluator> evaluator_;
  Joints lower_, upper_;
  Joints period_;  // revolute joints: 2 pi / |gain|; 0 otherwise
  // Joints the runs let through their limits (see the constructor).
  Eigen::Array<bool, Eigen::Dynamic, 1, 0, kMaxIkJoints, 1> wraps_;
  Joints weight_;  // options_.joint_weights, or ones
  IkTarget target_;
  Joints start_;
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
  constexpr const char* kNames[] = {"converged",   "singular", "limit",
                                    "unreachable", "invalid",  "iteration_cap",
                                    "collision"};
  return EnumToString(kNames, status);
}

bool InverseKinematicsOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(position_tolerance_m > 0.0) || !std::isfinite(position_tolerance_m)) {
    return fail("position_tolerance_m must be finite and > 0, got " +
                FormatNumber("%.6g", position_tolerance_m));
  }
  if (!(rotation_tolerance_rad > 0.0) ||
      !std::isfinite(rotation_tolerance_rad)) {
    return fail("rotation_tolerance_rad must be finite and > 0, got " +
                FormatNumber("%.6g", rotation_tolerance_rad));
  }
  if (!(rotation_weight_m > 0.0) || !std::isfinite(rotation_weight_m)) {
    return fail("rotation_weight_m must be finite and > 0, got " +
                FormatNumber("%.6g", rotation_weight_m));
  }
  if (max_iterations < 1) {
    return fail("max_iterations must be >= 1, got " +
                std::to_string(max_iterations));
  }
  for (size_t j = 0; j < joint_weights.size(); ++j) {
    if (!(joint_weights[j] > 0.0) || !std::isfinite(joint_weights[j])) {
      return fail("joint_weights[" + std::to_string(j) +
                  "] must be finite and > 0, got " +
                  FormatNumber("%.6g", joint_weights[j]));
    }
  }
  if (restarts < 0) {
    return fail("restarts must be >= 0, got " + std::to_string(restarts));
  }
  if (!(restart_spread_rad > 0.0) || !std::isfinite(restart_spread_rad)) {
    return fail("restart_spread_rad must be finite and > 0, got " +
                FormatNumber("%.6g", restart_spread_rad));
  }
  if (!(singular_threshold >= 0.0) || !(singular_threshold < 1.0)) {
    return fail("singular_threshold must be in [0, 1), got " +
                FormatNumber("%.6g", singular_threshold));
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
