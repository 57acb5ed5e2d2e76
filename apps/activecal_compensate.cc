// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_compensate: rewrites a robot program so that the real robot,
// described by a calibrated model, reaches where the program meant
// ("filtering"). See kinematics/.../compensation.h for what a program
// means. With --cell a compensated configuration the robot cannot run in
// the cell (a collision, a joint margin left) gets status collision.

#include <gflags/gflags.h>

#include <cstdio>

#include "activecal/calibration/compensate.h"
#include "activecal/io/robot_loader.h"
#include "app_common.h"

constexpr char kUsage[] =
    "Compensates a robot program with a calibrated model: the joints at "
    "which the real robot (--robot, calibrated) reaches what the program "
    "meant (--nominal geometry placed with the calibrated base frame), the "
    "smallest joint change inside the joint limits. Exit status 0: every "
    "target converged; 2: some did not (each is written with its status); "
    "1: bad input.\n  activecal_compensate --robot=calibrated.yaml "
    "--nominal=data/puma560.yaml --poses_csv=program.csv "
    "--out=compensated.csv --json_out=compensation.json\n  "
    "activecal_compensate --robot=cal.urdf --tip_link=tool0 "
    "--frames=frames.yaml --targets_csv=path.csv --match=pose "
    "--out=path_joints.csv";

DEFINE_string(nominal, "",
              "The nominal model the program was taught or computed with "
              "(YAML, or URDF with the same --base_link/--tip_link as "
              "--robot). --frames applies to it too: the markers are "
              "metrology, as the base (replaced by --robot's). Required "
              "with --poses_csv; with --targets_csv optional, to report the "
              "size of the correction (the nominal model's error at the "
              "compensated joints).");
DEFINE_string(poses_csv, "",
              "The program as joint targets (a poses CSV, docs/formats.md), "
              "taught or computed with --nominal.");
DEFINE_string(targets_csv, "",
              "The program as Cartesian targets in the device (base/tracker) "
              "frame: x_m,y_m,z_m[,rx_rad,ry_rad,rz_rad][,q1_rad,...] "
              "(docs/formats.md); the joints, when given, are each target's "
              "start, otherwise each starts from the previous result.");
DEFINE_string(match, "position",
              "position: match the marker's point (3 equations; the spare "
              "joints stay as close as possible to the program's); pose: "
              "point and orientation (6).");
DEFINE_string(marker, "1", "The marker the program places (name or number).");
DEFINE_string(out, "",
              "Compensated program to write (poses CSV: pose_index, q<j>_rad "
              "or _m, q<j>_deg or _mm, status, position_error_m). Required.");
DEFINE_string(json_out, "",
              "If set, a report: counts per status and, per target, status, "
              "message, errors left, joint change, iterations, the target.");
DEFINE_double(position_tolerance_m, 1e-9, "A target is reached within this.");
DEFINE_double(rotation_tolerance_rad, 1e-9,
              "--match=pose: orientation reached within this.");
DEFINE_double(rotation_weight_m, 1.0,
              "--match=pose: metres per radian of orientation error in the "
              "least-squares merit.");
DEFINE_int32(max_iterations, 100,
             "Jacobian evaluations per run of the solver (a target may take "
             "a run inside the limits, one without them and up to 24 short "
             "restarts).");
DEFINE_string(joint_weights, "",
              "The weight of each joint in the joint change the solver "
              "minimises, sum_j w_j (q_j - q_program_j)^2 (per rad, or per m "
              "for a prismatic joint), comma-separated, one per joint, e.g. "
              "10,10,1,1,1,1 to move the base joints less. Empty: 1 each.");
DEFINE_double(singular_threshold, 1e-6,
              "sigma_min / sigma_max of the Jacobian below which a "
              "configuration is reported singular.");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");
DEFINE_string(cell, "",
              "Cell file (YAML, docs/formats.md): a compensated "
              "configuration that leaves a joint margin or collides (with "
              "itself or an obstacle, closer than the clearances) gets "
              "status collision, the first reason in its message. Checked "
              "on the calibrated model (--robot), with --robot's collision "
              "geometry, or --nominal's when --robot's file has none (a "
              "--model_out YAML); refused when neither has any.");

namespace activecal {
namespace {

int Main() {
  if (FLAGS_out.empty()) app::Fail("--out is required");
  app::CheckWritableOrDie(FLAGS_out, "out");
  app::CheckWritableOrDie(FLAGS_json_out, "json_out");
  CompensateOptions options;
  options.poses_csv = FLAGS_poses_csv;
  options.targets_csv = FLAGS_targets_csv;
  std::string error;
  if (!options.HasOneProgram(&error)) app::Fail(error);
  InverseKinematicsOptions& ik = options.compensation.ik;
  if (!ParseIkMatch(FLAGS_match, &ik.match)) {
    app::Fail("--match must be position or pose, got '" + FLAGS_match + "'");
  }
  ik.position_tolerance_m = FLAGS_position_tolerance_m;
  ik.rotation_tolerance_rad = FLAGS_rotation_tolerance_rad;
  ik.rotation_weight_m = FLAGS_rotation_weight_m;
  ik.max_iterations = FLAGS_max_iterations;
  ik.singular_threshold = FLAGS_singular_threshold;
  options.compensation.num_threads = FLAGS_threads;
  if (!ParseJointWeights(FLAGS_joint_weights, &ik.joint_weights, &error)) {
    app::Fail(error);
  }
  if (!options.IsValid(&error)) app::Fail(error);
  // First, before anything else: a URDF carries neither the base frame nor
  // the markers a calibration found (they are in --frames_out), and without
  // them the joints move to fit a marker that is not there.
  std::fprintf(
      stderr, "%s",
      UrdfWithoutFramesNote(FLAGS_robot, FLAGS_frames, FLAGS_tip_link).c_str());
  RobotDescription robot = app::LoadRobotOrDie();
  // The cell, on the calibrated robot with its own markers (the program
  // places them; the cell's targets are for measuring).
  const CellSetup cell =
      FLAGS_cell.empty()
          ? CellSetup()
          : app::SetUpCellOrDie(FLAGS_cell, /*targets_as_markers=*/false,
                                &robot, FLAGS_nominal);
  options.cell = FLAGS_cell.empty() ? nullptr : &cell;
  options.cell_path = FLAGS_cell;
  options.marker = FLAGS_marker;
  options.robot_path = FLAGS_robot;
  options.chain = app::Chain();
  options.frames_path = FLAGS_frames;
  options.nominal_path = FLAGS_nominal;
  options.columns_strict = app::ColumnsStrict();
  options.out = FLAGS_out;
  options.json_out = FLAGS_json_out;
  options.program = app::ProgramName();
  CompensateSummary summary;
  Compensate(robot, options, &summary);
  // The targets file's notes on stdout: stderr keeps one line for an error.
  std::printf("%s", summary.notes.c_str());
  if (summary.termination_type == TerminationType::kUserFailure) {
    app::Fail(summary.message);
  }
  app::WriteFilesOrDie(summary.outputs);
  std::printf("%s", summary.report.c_str());
  app::PrintResult(summary.result_line);
  if (summary.termination_type == TerminationType::kFailure) {
    // Not bad input: the files are complete, each target with its status.
    std::fprintf(stderr, "activecal_compensate: %s\n",
                 summary.not_converged.c_str());
    return 2;
  }
  return 0;
}

}  // namespace
}  // namespace activecal

ACTIVECAL_APP_MAIN(kUsage, activecal::Main)
