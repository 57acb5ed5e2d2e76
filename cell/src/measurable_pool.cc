// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/measurable_pool.h"

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "activecal/core/kinematics.h"
#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/kinematics/inverse_kinematics.h"

namespace activecal {
namespace {

// Configurations sampled for the reach box.
constexpr int kReachSamples = 4000;
// Tries for a target point that passes the cheap tests, per draw.
constexpr int kPointTries = 1000;

// Joint j's sampling interval: its range inside the margin (one turn from
// -pi for an unbounded joint).
void SampleRange(const CellChecker& checker, int j, double* lo, double* hi) {
  const Link& l = checker.model().links[j];
  const double m = checker.joint_margin(j);
  *lo = std::isfinite(l.joint_min) ? l.joint_min + m : -M_PI;
  *hi = std::isfinite(l.joint_max) ? l.joint_max - m : M_PI;
  if (*hi < *lo) *hi = *lo;
}

bool InView(const CellCamera* c, const Eigen::Vector3d& eye,
            const Eigen::Vector3d& p) {
  if (c == nullptr) return true;
  const Eigen::Vector3d pc = c->rotation.transpose() * (p - eye);
  if (c->has_intrinsics) {
    if (!(pc.z() > 0)) return false;
    const double u = c->fx * pc.x() / pc.z() + c->cx;
    const double v = c->fy * pc.y() / pc.z() + c->cy;
    return u >= 0 && u <= c->width && v >= 0 && v <= c->height;
  }
  return std::atan2(pc.head<2>().norm(), pc.z()) <= c->half_fov_rad;
}

// What one draw found.
struct DrawResult {
  std::vector<Eigen::VectorXd> feasible;
  int solves = 0;
  int checked = 0;
  int ik_failures = 0;
  bool no_point = false;
  RejectionCounts counts;
};

}  // namespace

bool MeasurablePoolOptions::IsValid(std::string* error) const {
  std::string e;
  if (num_poses < 1) {
    e = "num_poses must be >= 1, got " + std::to_string(num_poses);
  } else if (seeds_per_target < 1) {
    e = "seeds_per_target must be >= 1, got " +
        std::to_string(seeds_per_target);
  } else if (ik_iterations < 1) {
    e = "ik_iterations must be >= 1, got " + std::to_string(ik_iterations);
  } else if (!(ik_position_tolerance_m > 0) ||
             !(ik_rotation_tolerance_rad > 0)) {
    e = "the inverse kinematics tolerances must be > 0";
  } else if (max_draws < 0) {
    e = "max_draws must be >= 0, got " + std::to_string(max_draws);
  } else if (give_up_draws < 0) {
    e = "give_up_draws must be >= 0, got " + std::to_string(give_up_draws);
  }
  if (e.empty()) return true;
  if (error) *error = e;
  return false;
}

int64_t MaxDraws(const MeasurablePoolOptions& options) {
  return options.max_draws > 0 ? options.max_draws
                               : kDefaultDrawsPerPose * options.num_poses;
}

std::string MeasurablePoolSummary::FailureText(
    const CellChecker& checker) const {
  std::string text =
      message + "; " + std::to_string(solutions_checked) +
      " inverse kinematics solutions checked, rejected: " +
      counts.CountsText(checker) + "; " + std::to_string(ik_failures) + " of " +
      std::to_string(ik_solves) + " solves failed; " +
      std::to_string(draws_without_point) + " of " + std::to_string(draws) +
      " draws found no target point in the device's range" +
      (checker.cell().has_device &&
               checker.cell().device.type != DeviceType::kLaserTracker
           ? " and view"
           : "") +
      " outside the obstacles";
  if (joints.rows() == 0 && counts.num_collisions() > 0) {
    text += "; " + counts.CollisionDiagnosis(checker);
  }
  return text;
}

double MeasurablePoolSummary::DrawsPerPose() const {
  return joints.rows() > 0 ? static_cast<double>(draws) / joints.rows() : 0.0;
}

double MeasurablePoolSummary::SolvesPerPose() const {
  return joints.rows() > 0 ? static_cast<double>(ik_solves) / joints.rows()
                           : 0.0;
}

std::string MeasurablePoolSummary::BriefReport() const {
  char line[256];
  std::snprintf(line, sizeof(line),
                "measurable pool: %lld feasible poses from %lld target "
                "poses, %lld IK solves (%.3g draws, %.3g solves per "
                "pose), %.3g s\n",
                static_cast<long long>(joints.rows()),
                static_cast<long long>(draws),
                static_cast<long long>(ik_solves), DrawsPerPose(),
                SolvesPerPose(), seconds);
  return line;
}

bool SampleMeasurablePool(const CellChecker& checker,
                          const MeasurablePoolOptions& options,
                          MeasurablePoolSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  *summary = MeasurablePoolSummary();
  MeasurablePoolSummary& s = *summary;
  auto fail = [&](const std::string& what) {
    s.termination_type = TerminationType::kUserFailure;
    s.message = what;
    return false;
  };
  std::string error;
  if (!options.IsValid(&error)) return fail(error);
  const Cell& cell = checker.cell();
  if (!cell.has_device || cell.targets.empty()) {
    return fail("a measurable pool needs a cell with a device and targets");
  }
  if (options.target < 0 ||
      options.target >= static_cast<int>(cell.targets.size())) {
    return fail("target must be in [0, " +
                std::to_string(cell.targets.size() - 1) + "], got " +
                std::to_string(options.target));
  }
  const RobotModel& model = checker.model();
  const int n = model.num_joints();
  if (n > kMaxIkJoints) {
    return fail("the inverse kinematics takes at most " +
                std::to_string(kMaxIkJoints) + " joints");
  }
  const CellTarget& target = cell.targets[options.target];
  double acceptance = target.acceptance_rad;
  if (cell.device.type == DeviceType::kCamera) {
    acceptance = std::min(acceptance, cell.device.max_viewing_angle_rad);
  }
  // The viewpoints a draw aims at.
  struct Eye {
    Eigen::Vector3d position;
    double min_range, max_range;
    const CellCamera* camera;
  };
  std::vector<Eye> eyes;
  if (cell.device.type == DeviceType::kLaserTracker) {
    eyes.push_back({cell.device.position, cell.device.min_range_m,
                    cell.device.max_range_m, nullptr});
  } else {
    for (const CellCamera& c : cell.device.cameras) {
      eyes.push_back({c.position, c.min_range_m, c.max_range_m, &c});
    }
  }
  // The inverse kinematics' model: one marker, the target, on the tip.
  RobotModel ik_model = model;
  ik_model.markers = {Marker()};
  const Eigen::VectorXd& parameters = checker.parameters();
  const int head = model.block_offset(model.marker_block(0));
  Eigen::VectorXd ik_parameters(head + kMarkerBlockSize);
  ik_parameters.head(head) = parameters.head(head);
  ik_parameters.tail(kMarkerBlockSize) << target.xyz_m, 0, 0, 0;
  ik_model.nominal = ik_parameters;
  // The base block: from the base frame (the cell's) to the device frame
  // (the inverse kinematics').
  Eigen::Matrix3d RB;
  Eigen::Vector3d tB;
  LinkTransform(model.base, parameters.data(), 0.0, &RB, &tB);
  // The reach box: the target's positions over random configurations.
  Eigen::Vector3d box_lo, box_hi;
  {
    Random random(Random::StreamSeed(options.seed, ~uint64_t{0}));
    Eigen::VectorXd q(n);
    for (int k = 0; k < kReachSamples; ++k) {
      for (int j = 0; j < n; ++j) {
        double lo, hi;
        SampleRange(checker, j, &lo, &hi);
        q[j] = lo + (hi - lo) * random.Uniform();
      }
      const FixedTransform tip = checker.TipFrame(q.data());
      const Eigen::Vector3d p = tip.rotation * target.xyz_m + tip.translation;
      if (k == 0) box_lo = box_hi = p;
      box_lo = box_lo.cwiseMin(p);
      box_hi = box_hi.cwiseMax(p);
    }
  }
  InverseKinematicsOptions ik;
  ik.match = IkMatch::kPose;
  ik.max_iterations = options.ik_iterations;
  ik.position_tolerance_m = options.ik_position_tolerance_m;
  ik.rotation_tolerance_rad = options.ik_rotation_tolerance_rad;
  ik.rotation_weight_m = 0.5;

  auto draw = [&](int64_t d, CellChecker::Workspace* w, DrawResult* out) {
    Random random(Random::StreamSeed(options.seed, static_cast<uint64_t>(d)));
    const Eye& eye =
        eyes[eyes.size() == 1 ? 0 : random.UniformInt(eyes.size())];
    Eigen::Vector3d p;
    bool found = false;
    for (int t = 0; t < kPointTries && !found; ++t) {
      for (int k = 0; k < 3; ++k) {
        p[k] = box_lo[k] + (box_hi[k] - box_lo[k]) * random.Uniform();
      }
      const double r = (p - eye.position).norm();
      if (!(r >= eye.min_range && r <= eye.max_range)) continue;
      if (!InView(eye.camera, eye.position, p)) continue;
      bool inside = false;
      for (const Obstacle& o : cell.obstacles) {
        inside = inside || PointInsideObstacle(o, p);
      }
      found = !inside;
    }
    if (!found) {
      out->no_point = true;
      return;
    }
    // The normal inside the acceptance cone about the direction to the
    // eye, uniform on the cap; a random roll about it.
    const Eigen::Vector3d axis = (eye.position - p).normalized();
    const Eigen::Vector3d helper = std::abs(axis.x()) < 0.9
                                       ? Eigen::Vector3d::UnitX()
                                       : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d a = helper.cross(axis).normalized();
    const Eigen::Vector3d b = axis.cross(a);
    const double cos_theta =
        1.0 - random.Uniform() * (1.0 - std::cos(acceptance));
    const double sin_theta =
        std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    const double phi = 2.0 * M_PI * random.Uniform();
    const Eigen::Vector3d u =
        cos_theta * axis + sin_theta * (std::cos(phi) * a + std::sin(phi) * b);
    const double roll = 2.0 * M_PI * random.Uniform();
    const Eigen::Matrix3d R_tip =
        Eigen::AngleAxisd(roll, u).toRotationMatrix() *
        Eigen::Quaterniond::FromTwoVectors(target.normal, u).toRotationMatrix();
    IkTarget goal;
    goal.point = RB * p + tB;
    goal.rotation = RB * R_tip;
    std::vector<Eigen::VectorXd> solutions;
    Eigen::VectorXd seed(n);
    InverseKinematicsResult result;
    for (int k = 0; k < options.seeds_per_target; ++k) {
      for (int j = 0; j < n; ++j) {
        double lo, hi;
        SampleRange(checker, j, &lo, &hi);
        seed[j] = lo + (hi - lo) * random.Uniform();
      }
      SolveInverseKinematics(ik_model, ik_parameters, goal, seed, ik, &result);
      ++out->solves;
      if (result.status == IkStatus::kInvalid) {
        ++out->ik_failures;
        continue;
      }
      bool seen = false;
      for (const Eigen::VectorXd& other : solutions) {
        seen = seen || (other - result.joints).cwiseAbs().maxCoeff() < 1e-4;
      }
      if (seen) continue;
      solutions.push_back(result.joints);
      ++out->checked;
      const PoseVerdict v = checker.Check(result.joints.data(), w);
      out->counts.Add(v, result.joints.data(), n);
      if (v.feasible()) out->feasible.push_back(result.joints);
    }
  };

  const int threads = ResolveNumThreads(options.num_threads);
  const int64_t max_draws = MaxDraws(options);
  std::vector<std::unique_ptr<CellChecker::Workspace>> workspaces(threads);
  for (auto& w : workspaces) w = checker.NewWorkspace();
  std::vector<Eigen::VectorXd> kept;
  const int64_t batch = 64 * threads;
  bool complete = false;
  bool gave_up = false;
  for (int64_t first = 0; first < max_draws && !complete && !gave_up;
       first += batch) {
    const int64_t count = std::min(batch, max_draws - first);
    std::vector<DrawResult> results(count);
    ParallelFor(count, threads, [&](int64_t begin, int64_t end, int thread) {
      for (int64_t i = begin; i < end; ++i) {
        draw(first + i, workspaces[thread].get(), &results[i]);
      }
    });
    for (int64_t i = 0; i < count && !complete; ++i) {
      const DrawResult& r = results[i];
      ++s.draws;
      s.ik_solves += r.solves;
      s.solutions_checked += r.checked;
      s.ik_failures += r.ik_failures;
      s.draws_without_point += r.no_point ? 1 : 0;
      s.counts.Merge(r.counts);
      for (const Eigen::VectorXd& q : r.feasible) {
        if (static_cast<int64_t>(kept.size()) < options.num_poses) {
          kept.push_back(q);
        }
      }
      complete = static_cast<int64_t>(kept.size()) >= options.num_poses;
      // Nothing in the first give_up_draws draws: the cap cannot be met
      // (draws stop in draw order, so at the same draw for every thread
      // count).
      if (!complete && kept.empty() && options.give_up_draws > 0 &&
          s.draws >= options.give_up_draws && s.draws < max_draws) {
        gave_up = true;
        break;
      }
    }
    if (options.progress) {
      options.progress(static_cast<int64_t>(kept.size()), options.num_poses);
    }
  }
  s.joints.resize(kept.size(), n);
  for (size_t k = 0; k < kept.size(); ++k)
    s.joints.row(k) = kept[k].transpose();
  s.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  for (int k = 0; k < kNumRejectionReasons; ++k) {
    s.rejected[k] = s.counts.rejected[k];
  }
  s.max_draws = max_draws;
  s.gave_up = gave_up;
  if (complete) {
    s.termination_type = TerminationType::kConvergence;
  } else if (gave_up) {
    s.termination_type = TerminationType::kNoConvergence;
    s.message = "found no measurable pose in " + std::to_string(s.draws) +
                " draws (the search gives up there; max_draws " +
                std::to_string(max_draws) + ")";
  } else {
    s.termination_type = TerminationType::kNoConvergence;
    s.message = "found " + std::to_string(kept.size()) + " of " +
                std::to_string(options.num_poses) + " measurable poses in " +
                std::to_string(s.draws) + " draws (max_draws)";
  }
  return true;
}

}  // namespace activecal
