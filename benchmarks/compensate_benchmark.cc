// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Speed of program compensation (compensation.h): targets per second for
// 6-axis arms on 1 and 2 threads, and the iterations each target needs.
//
//   build/benchmarks/activecal_compensate_benchmark [--targets=10000]
//       [--repeats=5] [--ur10e=data/ur10e.urdf]
//
// Cases:
//   ur10e position / pose   data/ur10e.urdf (6 URDF joints, tool0) against a
//                           calibrated model with realistic errors (joint
//                           offsets ~1 mrad, origins ~1 mm), the usual case
//   puma560 position        the paper's PUMA: true values (Table I) as the
//                           calibrated model, Table II as the nominal one,
//                           errors of hundreds of mm (a worst case)
// Prints one Markdown table row per case and thread count: the best of
// `repeats` runs (targets/s), mean iterations, converged count; and checks
// that 1 and 2 threads give bit-identical joints.
//
// Then inverse kinematics against orocos KDL's ChainIkSolverPos_LMA on the
// UR10e's URDF (base_link to tool0, as kdl_parser reads it; activecal's
// model of the same file), full pose, one thread, both to 1e-9 (LMA's eps
// on the norm of the pose error, activecal's 1e-9 m and 1e-9 rad): targets
// are the poses of random configurations (`--ik_targets`, joints inside
// the limits less 0.1 rad), starts either near (each joint 1 mrad off,
// Gaussian) or far (each joint off by up to `--far_rad`, uniform). The two
// solvers run alternately `repeats` times in one process; the best time of
// each is reported, with the targets each reaches and the ones only the
// other reaches. `--solver=activecal` or `kdl` runs one solver only, and
// `--starts=near` or `far` one kind of start (for callgrind instruction
// counts).

#include <gflags/gflags.h>

#include <chrono>
#include <cstdio>
#include <kdl/chain.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <string>
#include <vector>

#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/io/robot_loader.h"
#include "activecal/kinematics/compensation.h"

DEFINE_int32(targets, 10000, "Targets per program.");
DEFINE_int32(repeats, 5, "Runs per case; the fastest is reported.");
DEFINE_string(ur10e, ACTIVECAL_DATA_DIR "/ur10e.urdf", "The UR10e URDF.");
DEFINE_int32(ik_targets, 2000,
             "Targets of the comparison with KDL's LMA (0: none).");
DEFINE_double(far_rad, 1.0,
              "Far starts: each joint off its target's by up to this (rad).");
DEFINE_string(solver, "both",
              "The IK comparison's solvers: both, activecal or kdl.");
DEFINE_bool(compensation, true, "Run the compensation cases.");
DEFINE_string(starts, "both", "The IK comparison's starts: both, near or far.");
DEFINE_int32(ik_restarts, -1,
             "The IK comparison's InverseKinematicsOptions::restarts (-1: the "
             "default).");

namespace activecal {
namespace {

Eigen::MatrixXd RandomProgram(const RobotModel& model, int n, uint64_t seed,
                              double margin) {
  Random random(seed);
  Eigen::MatrixXd program(n, model.num_joints());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j) {
      const Link& l = model.links[j];
      const double lo = std::isfinite(l.joint_min) ? l.joint_min : -M_PI;
      const double hi = std::isfinite(l.joint_max) ? l.joint_max : M_PI;
      program(i, j) = lo + margin + (hi - lo - 2 * margin) * random.Uniform();
    }
  }
  return program;
}

int Run(const std::string& name, const RobotModel& model,
        const Eigen::VectorXd& calibrated, const Eigen::VectorXd& nominal,
        IkMatch match) {
  const Eigen::MatrixXd program = RandomProgram(model, FLAGS_targets, 1, 0.1);
  CompensationSummary reference;
  int failures = 0;
  for (int threads : {1, 2}) {
    CompensationOptions options;
    options.ik.match = match;
    options.num_threads = threads;
    double best = 1e300;
    CompensationSummary summary;
    for (int r = 0; r < FLAGS_repeats; ++r) {
      CompensateProgram(model, calibrated, model, nominal, program, options,
                        &summary);
      best = std::min(best, summary.seconds);
    }
    int64_t iterations = 0;
    for (const InverseKinematicsResult& result : summary.results) {
      iterations += result.iterations;
    }
    std::printf("| %s | %s | %d | %d | %.0f | %.2f | %.1f | %d |\n",
                name.c_str(), IkMatchName(match), FLAGS_targets, threads,
                FLAGS_targets / best, 1e6 * best / FLAGS_targets,
                static_cast<double>(iterations) / FLAGS_targets,
                summary.num_converged);
    if (threads == 1) {
      reference = summary;
    } else {
      for (size_t i = 0; i < summary.results.size(); ++i) {
        if (!(summary.results[i].joints == reference.results[i].joints)) {
          ++failures;
        }
      }
    }
  }
  if (failures) {
    std::printf("ERROR: %s: %d targets differ between 1 and 2 threads\n",
                name.c_str(), failures);
  }
  return failures;
}

// The comparison with KDL's LMA (see the top of the file).
struct IkCase {
  std::vector<IkTarget> targets;
  std::vector<KDL::Frame> frames;
  Eigen::MatrixXd starts;
};

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since)
      .count();
}

int CompareWithKdl(const RobotModel& model) {
  KDL::Tree tree;
  KDL::Chain chain;
  if (!kdl_parser::treeFromFile(FLAGS_ur10e, tree) ||
      !tree.getChain("base_link", "tool0", chain) ||
      static_cast<int>(chain.getNrOfJoints()) != model.num_joints()) {
    std::fprintf(stderr,
                 "compensate_benchmark: error: %s: no KDL chain "
                 "base_link..tool0 of %d joints\n",
                 FLAGS_ur10e.c_str(), model.num_joints());
    return 1;
  }
  const bool run_ours = FLAGS_solver != "kdl";
  const bool run_kdl = FLAGS_solver != "activecal";
  const int n = FLAGS_ik_targets;
  const int dof = model.num_joints();
  const Eigen::MatrixXd truth = RandomProgram(model, n, 11, 0.1);
  std::printf(
      "| start | solver | targets | us/target | evaluations/target | "
      "reached | reached by it only |\n| --- | --- | --- | --- | --- | --- | "
      "--- |\n");
  int failures = 0;
  for (const bool far : {false, true}) {
    if (FLAGS_starts != "both" && (FLAGS_starts == "far") != far) continue;
    IkCase ik;
    ik.starts.resize(n, dof);
    Random random(far ? 13 : 12);
    for (int i = 0; i < n; ++i) {
      Eigen::Matrix3d R;
      Eigen::Vector3d t;
      Eigen::MatrixXd J;
      std::string error;
      JointJacobian(model, model.nominal, truth.row(i).transpose(), 0, &R, &t,
                    &J, &error);
      IkTarget target;
      target.point = t;
      target.rotation = R;
      ik.targets.push_back(target);
      KDL::Rotation rotation;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) rotation(r, c) = R(r, c);
      }
      ik.frames.emplace_back(rotation, KDL::Vector(t[0], t[1], t[2]));
      for (int j = 0; j < dof; ++j) {
        const Link& l = model.links[j];
        double q =
            truth(i, j) + (far ? FLAGS_far_rad * (2.0 * random.Uniform() - 1.0)
                               : 1e-3 * random.Gaussian());
        ik.starts(i, j) = std::min(std::max(q, l.joint_min), l.joint_max);
      }
    }
    InverseKinematicsOptions options;
    options.match = IkMatch::kPose;
    options.position_tolerance_m = 1e-9;
    options.rotation_tolerance_rad = 1e-9;
    if (FLAGS_ik_restarts >= 0) options.restarts = FLAGS_ik_restarts;
    Eigen::Matrix<double, 6, 1> weights;
    weights.setOnes();
    KDL::ChainIkSolverPos_LMA lma(chain, weights, 1e-9, 500);
    std::vector<InverseKinematicsResult> ours(n);
    std::vector<char> kdl_reached(n, 0);
    double ours_best = HUGE_VAL, kdl_best = HUGE_VAL;
    int64_t kdl_iterations = 0;
    KDL::JntArray q_init(dof), q_out(dof);
    for (int r = 0; r < FLAGS_repeats; ++r) {
      if (run_ours) {
        const auto begin = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) {
          SolveInverseKinematics(model, model.nominal, ik.targets[i],
                                 ik.starts.row(i).transpose(), options,
                                 &ours[i]);
        }
        ours_best = std::min(ours_best, Seconds(begin));
      }
      if (run_kdl) {
        kdl_iterations = 0;
        const auto begin = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) {
          for (int j = 0; j < dof; ++j) q_init(j) = ik.starts(i, j);
          kdl_reached[i] = lma.CartToJnt(q_init, ik.frames[i], q_out) >= 0;
          kdl_iterations += lma.lastNrOfIter;
        }
        kdl_best = std::min(kdl_best, Seconds(begin));
      }
    }
    int ours_reached = 0, kdl_count = 0, ours_only = 0, kdl_only = 0;
    int64_t ours_iterations = 0;
    std::vector<int> missed;
    for (int i = 0; i < n; ++i) {
      const bool a = ours[i].status == IkStatus::kConverged ||
                     ours[i].status == IkStatus::kSingular;
      ours_reached += a;
      kdl_count += kdl_reached[i];
      ours_only += a && !kdl_reached[i];
      kdl_only += !a && kdl_reached[i];
      if (!a && kdl_reached[i]) missed.push_back(i);
      ours_iterations += ours[i].iterations;
    }
    const char* start = far ? "far" : "near";
    if (run_ours) {
      std::printf("| %s | activecal | %d | %.2f | %.1f | %d | %s |\n", start, n,
                  1e6 * ours_best / n, static_cast<double>(ours_iterations) / n,
                  ours_reached,
                  run_kdl ? std::to_string(ours_only).c_str() : "-");
    }
    if (run_kdl) {
      std::printf("| %s | KDL LMA | %d | %.2f | %.1f | %d | %s |\n", start, n,
                  1e6 * kdl_best / n, static_cast<double>(kdl_iterations) / n,
                  kdl_count, run_ours ? std::to_string(kdl_only).c_str() : "-");
    }
    if (run_ours && run_kdl) {
      std::printf("| %s | ratio KDL / activecal | | %.2f | | | |\n", start,
                  kdl_best / ours_best);
      for (int i : missed) {
        std::fprintf(stderr, "%s target %d: KDL reached, activecal %s: %s\n",
                     start, i, IkStatusName(ours[i].status),
                     ours[i].message.c_str());
      }
      if (ours_reached < kdl_count) ++failures;
    }
  }
  return failures;
}

int Main() {
  int failures = 0;
  RobotLoadOptions load;
  load.chain.tip_link = "tool0";
  RobotDescription ur;
  std::string error;
  if (!LoadRobot(FLAGS_ur10e, load, &ur, &error)) {
    std::fprintf(stderr, "compensate_benchmark: error: %s\n", error.c_str());
    return 1;
  }
  // A calibrated UR10e: every joint origin off by ~1 mm and ~1 mrad, every
  // offset by ~1 mrad; a tool 0.1 m out with an orientation.
  RobotModel& model = ur.model;
  Eigen::VectorXd nominal = model.nominal;
  const int tool = model.block_offset(model.marker_block(0));
  nominal.segment(tool, 6) << 0.01, 0.02, 0.1, 0.2, -0.1, 0.3;
  Eigen::VectorXd calibrated = nominal;
  Random random(3);
  for (int j = 0; j < model.num_joints(); ++j) {
    double* p = calibrated.data() + model.block_offset(j + 1);
    for (int k = 0; k < 3; ++k) p[k] += 1e-3 * random.Gaussian();
    for (int k = 3; k < 7; ++k) p[k] += 1e-3 * random.Gaussian();
  }
  if (FLAGS_ik_targets > 0) failures += CompareWithKdl(ur.model);
  if (!FLAGS_compensation) return failures ? 1 : 0;
  std::printf(
      "\n| robot | match | targets | threads | targets/s | us/target | "
      "iterations/target | converged |\n| --- | --- | --- | --- | --- | --- "
      "| --- | --- |\n");
  failures += Run("ur10e", model, calibrated, nominal, IkMatch::kPosition);
  failures += Run("ur10e", model, calibrated, nominal, IkMatch::kPose);
  const RobotModel puma = Puma560PaperModel();
  failures += Run("puma560 (Table I vs II)", puma, Puma560TrueParameters(),
                  puma.nominal, IkMatch::kPosition);
  return failures ? 1 : 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "Targets per second of CompensateProgram on 1 and 2 threads.");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  return activecal::Main();
}
