// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_select: choose calibration poses for a robot (the paper's PUMA
// 560 by default) from a joint lattice or a pool read from CSV, by a
// D-optimal design algorithm or for the task accuracy (--criterion=task_rms),
// of a given size or of the fewest poses meeting a target (--target_rms_m),
// counting the poses already measured (--measured_csv). With --cell, only
// the poses a real cell can run (joint margins, collisions, the device's
// range and view of the targets) are candidates, and --order=shortest
// sorts the design into a short tour whose moves are checked. The work is
// the library's Select (calibration/select_workflow.h): this program turns
// the flags into its options and prints and writes what it returns.

#include <gflags/gflags.h>

#include <cstdio>
#include <memory>
#include <string>

#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/defaults.h"
#include "activecal/calibration/iso9283_cube_poses.h"
#include "activecal/calibration/select_workflow.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/io/robot_loader.h"
#include "app_common.h"

constexpr char kUsage[] =
    "Selects calibration poses from a lattice of joint values (or a pool "
    "read from CSV), maximising det(X^T X) of the measurement Jacobian at "
    "the nominal parameters, or (--criterion=task_rms) minimising the "
    "predicted RMS position error over the task poses; --target_rms_m "
    "finds the fewest poses meeting a target, --measured_csv counts the "
    "poses already measured. The robot is --robot (default: the Sun & "
    "Hollerbach PUMA 560).\n  activecal_select --algorithm=fedorov "
    "--seed=1 --json_out=design.json --poses_csv=poses.csv";

DEFINE_int32(levels, activecal::defaults::kLevels,
             "Lattice values per joint, both range ends included (>= 2). "
             "The pool has levels^(number of joints) poses.");
DEFINE_string(pool, "lattice",
              "Candidate poses: lattice (--levels values per joint), sobol "
              "(quasi-random) or random (--pool_size poses inside the joint "
              "ranges, seeded by --seed; for 7 or more joints), or "
              "measurable (with --cell: --pool_size poses solved by inverse "
              "kinematics for target poses the device can measure, each "
              "checked).");
DEFINE_int64(pool_size, activecal::defaults::kPoolSize,
             "sobol, random, measurable: number of candidate poses.");
DEFINE_int64(max_draws, 0,
             "measurable: stop after this many target poses drawn (0: 10 x "
             "--pool_size); a cell that gives no pose in the first 1000 "
             "draws stops there. Fewer poses found than --num_poses: one "
             "line with the counts per rejection reason, exit 1.");
DEFINE_string(pool_csv, "",
              "Read the candidate poses from this poses CSV "
              "(docs/formats.md) instead of the lattice; duplicates are an "
              "error. pose_index labels the poses in the output.");
DEFINE_string(poses_csv, "",
              "If set, write the selected poses here (pose_index, joints in "
              "rad and deg) to run on the robot.");
DEFINE_string(measurement, "position",
              "What the device measures at each pose: position (3D point) "
              "or pose (6D: point and orientation).");
DEFINE_double(rotation_weight, activecal::defaults::kRotationWeightMPerRad,
              "pose: weight of the orientation rows, m per rad (set it to "
              "sigma_position / sigma_rotation of the device).");
DEFINE_bool(auto_fix, false,
            "If the pool cannot identify some free parameters, hold them "
            "at their nominal values (named on stderr) instead of failing.");
DEFINE_string(algorithm, activecal::defaults::kSelectAlgorithm,
              "eae: the paper's exchange-add-exchange; random: best of "
              "--random_designs random designs; fedorov: Fedorov exchange "
              "(best swap over all pairs), restart 0 from the rounded "
              "approximate design; detmax: Mitchell's excursions; greedy: "
              "sequential best additions; approx: the approximate "
              "(continuous-weight) D-optimal design, rounded to its "
              "--num_poses heaviest poses.");
DEFINE_string(criterion, activecal::defaults::kSelectCriterion,
              "det (d): D-optimal (eae: svd scores it by SVD); task_rms: "
              "least predicted RMS position error over the task poses.");
DEFINE_string(task_poses_csv, "",
              "Poses CSV of where the robot will work (default: the pool).");
DEFINE_double(noise_m, activecal::defaults::kDesignNoiseM,
              "Measurement noise sigma per coordinate (m).");
DEFINE_double(target_rms_m, 0.0,
              "If set: the fewest poses whose predicted task RMS is <= this.");
DEFINE_string(measured_csv, "",
              "Measurements CSV of poses already measured (task_rms): fixed.");
DEFINE_string(curve_csv, "", "With --target_rms_m: write the curve here.");
DEFINE_int32(num_poses, activecal::defaults::kNumPoses, "Poses in the design.");
DEFINE_int32(initial_poses, activecal::defaults::kInitialPoses,
             "eae: random poses in the initial design.");
DEFINE_int32(random_designs, activecal::defaults::kRandomDesigns,
             "random: number of designs drawn.");
DEFINE_int32(restarts, 0,
             "eae, fedorov, detmax: independent restarts, run in parallel; "
             "the best is kept. 0: the algorithm's default (eae 1, fedorov "
             "16, or 8 for pools of more than 200,000 poses, detmax 4).");
DEFINE_bool(certificate, true,
            "Solve the approximate design and report a certified lower "
            "bound on the design's D-efficiency (efficiency_lower_bound) "
            "and the upper bound on log10 det it rests on.");
DEFINE_double(approx_tolerance, activecal::defaults::kApproxTolerance,
              "Approximate design: stop when max_i d_i <= p (1 + tol). The "
              "bounds hold for any value; smaller is tighter and slower.");
DEFINE_int64(polish_pool_size, activecal::defaults::kPolishPoolSize,
             "fedorov: a pool larger than this is polished in rounds over "
             "this many poses of largest variance rather than over every "
             "pose (<= 0: always every pose).");
DEFINE_string(pool_storage, "auto",
              "How the pool's Jacobian blocks are stored: double, float "
              "(single precision, half the memory; the design's log det and "
              "the certificate are still computed in double, from Jacobians "
              "recomputed as they are swept), or auto (float when the "
              "double blocks would take more than --max_double_pool_mib and "
              "the algorithm is fedorov or approx). Float needs "
              "--algorithm=fedorov or approx with the D criterion.");
DEFINE_int64(max_double_pool_mib, activecal::defaults::kMaxDoublePoolMib,
             "--pool_storage=auto: the largest pool kept in double (MiB).");
DEFINE_uint64(seed, activecal::defaults::kSeed, "Seed of every random choice.");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");
DEFINE_string(json_out, "", "If set, write the selected design here.");
DEFINE_string(program_out, "",
              "Also write the design as a controller program (the poses CSV "
              "unchanged): docs/driver_protocol.md.");
DEFINE_string(program_language, "urscript", "urscript, krl or rapid.");
DEFINE_string(controller, "",
              "The controller's joint convention (YAML, data/controllers/).");
DEFINE_string(cell, "",
              "Cell file (YAML, docs/formats.md): joint margins, clearance, "
              "obstacles, the measuring device and the targets on the "
              "robot. The pool keeps only the poses the cell can run (the "
              "counts per reason are printed) before the identifiability "
              "check and the design. Without --frames the cell's targets are "
              "the markers.");
DEFINE_string(rejected_csv, "",
              "With --cell: write each rejected pose here (poses CSV with "
              "reason, obstacle and detail columns).");
DEFINE_bool(cell_efficiency, true,
            "With --cell and the D criterion: also design from an "
            "unconstrained pool of the feasible pool's size (the same "
            "--pool draw, or Sobol, over the full joint limits, no checks) "
            "and report the D-efficiency lost to the cell, (det ratio)^(1/p) "
            "(JSON cell_d_efficiency).");
DEFINE_string(order, "none",
              "none: the poses in the design's order; shortest: a short "
              "tour in joint space (time at the URDF's velocity limits, "
              "nearest neighbour + 2-opt), with --cell every move checked "
              "for collisions. The poses CSV and the JSON keep the order.");
DEFINE_double(order_resolution_deg, 1.0,
              "--order=shortest with --cell: a move is checked at joint "
              "steps of at most this many degrees (mm for prismatic "
              "joints).");

DEFINE_string(iso9283_cube, "",
              "Instead of a design: the ISO 9283 (6.8) test poses P1..P5 of "
              "the cube cx,cy,cz,edge_m (m, the robot's base frame; "
              "optionally ,qw,qx,qy,qz: the cube's axes), solved to joints "
              "by the inverse kinematics (checked against --cell if given) "
              "and written to --poses_csv with a 'pose' column "
              "(docs/iso9283.md).");
DEFINE_string(iso9283_orientation, "",
              "With --iso9283_cube: the orientation qw,qx,qy,qz of the "
              "measured target frame at all five poses (base frame). "
              "Default: its orientation at the middle of the joint ranges.");
DEFINE_string(iso9283_targets_csv, "",
              "With --iso9283_cube: write the five targets here (targets "
              "CSV, device frame, with the joints and a 'pose' column).");

namespace activecal {
namespace {

// --iso9283_cube: the cube's five test poses instead of a design.
int Iso9283CubeMain(const RobotModel& model, const CellSetup& cell) {
  if (FLAGS_poses_csv.empty()) app::Fail("--iso9283_cube needs --poses_csv");
  app::CheckWritableOrDie(FLAGS_poses_csv, "poses_csv");
  app::CheckWritableOrDie(FLAGS_iso9283_targets_csv, "iso9283_targets_csv");
  Iso9283CubePoses poses;
  const bool ok = MakeIso9283CubePoses(
      model,
      {FLAGS_iso9283_cube, FLAGS_iso9283_orientation, cell.checker.get()},
      &poses);
  std::printf("%s", poses.table.c_str());
  if (!ok) app::Fail(poses.message);
  for (const auto& [path, text] :
       {std::pair(FLAGS_poses_csv, poses.poses_csv),
        std::pair(FLAGS_iso9283_targets_csv, poses.targets_csv)}) {
    if (path.empty()) continue;
    app::WriteTextOrDie(path, text);
    std::printf("  wrote %s\n", path.c_str());
  }
  return 0;
}

int Main() {
  const int64_t start = app::NowNs();
  RobotDescription robot = app::LoadRobotOrDie();
  const ProgramRequest program = app::ProgramRequestOrDie(
      robot.model, FLAGS_program_out, FLAGS_program_language, FLAGS_controller);
  app::CheckTourFlagsOrDie(FLAGS_order, FLAGS_order_resolution_deg);
  if (!FLAGS_rejected_csv.empty() && FLAGS_cell.empty()) {
    app::Fail("--rejected_csv needs --cell");
  }
  app::CheckWritableOrDie(FLAGS_rejected_csv, "rejected_csv");
  // The cell: its checks, and its targets as the markers unless --frames
  // gives them.
  const bool with_cell = !FLAGS_cell.empty();
  const CellSetup cell =
      with_cell ? app::SetUpCellOrDie(FLAGS_cell, FLAGS_frames.empty(), &robot)
                : CellSetup();
  RobotModel model = robot.model;
  if (!FLAGS_iso9283_cube.empty()) return Iso9283CubeMain(model, cell);
  MeasurementType type;
  if (!ParseMeasurementType(FLAGS_measurement, &type) ||
      type == MeasurementType::kDistance) {
    app::Fail("--measurement must be position or pose, got '" +
              FLAGS_measurement + "'");
  }
  // The design's algorithm and criterion; the task criterion's algorithm is
  // the best the library has for it (fedorov) unless set, not the paper's
  // EAE.
  DesignAlgorithm algorithm;
  DesignCriterion criterion;
  std::string error;
  if (!ParseDesignAlgorithm(FLAGS_algorithm, &algorithm, &error) ||
      !ParseDesignCriterion(FLAGS_criterion, &criterion, &error)) {
    app::Fail("--" + error);
  }
  if (criterion == DesignCriterion::kTaskRms && app::IsDefault("algorithm")) {
    algorithm = DesignAlgorithm::kFedorov;
  }
  SelectOptions options;
  if (!StringToSelectPool(FLAGS_pool, &options.pool)) {
    app::Fail("--pool must be lattice, sobol, random or measurable, got '" +
              FLAGS_pool + "'");
  }
  options.pool_csv = FLAGS_pool_csv;
  options.cell = with_cell ? &cell : nullptr;
  options.type = type;
  if (!app::IsDefault("pool_size")) options.pool_size = FLAGS_pool_size;
  if (!app::IsDefault("max_draws")) options.max_draws = FLAGS_max_draws;
  // The pool's checks first: they name the pool's flags before the
  // storage's and the parameters'.
  if (!options.IsValid(model, &error)) app::Fail(error);
  options.levels = FLAGS_levels;
  options.cell_path = FLAGS_cell;
  options.rotation_weight_m_per_rad = FLAGS_rotation_weight;
  options.auto_fix = FLAGS_auto_fix;
  // How the pool is stored: single precision where the double blocks would
  // not fit the budget (and the algorithm reads such pools).
  app::EnumFlagOrDie(PoolStorageFromString, "pool_storage", FLAGS_pool_storage,
                     "auto, double or float", &options.storage);
  if (options.storage == PoolStorage::kFloat &&
      !ReadsFloatPool(algorithm, criterion)) {
    app::Fail(
        "--pool_storage=float needs --algorithm=fedorov or approx with "
        "the D criterion (got --algorithm=" +
        FLAGS_algorithm + " --criterion=" + FLAGS_criterion + ")");
  }
  if (options.storage == PoolStorage::kAuto && FLAGS_max_double_pool_mib < 0) {
    app::Fail("--max_double_pool_mib must be >= 0, got " +
              std::to_string(FLAGS_max_double_pool_mib));
  }
  options.max_double_pool_mib = FLAGS_max_double_pool_mib;
  options.parameter_set = app::ParameterSetOrDie(IsUrdfPath(FLAGS_robot));
  // The design's options.
  SelectDesignOptions& design = options.design;
  design.algorithm = algorithm;
  design.criterion = criterion;
  design.num_poses = FLAGS_num_poses;
  design.restarts = FLAGS_restarts;
  design.seed = FLAGS_seed;
  design.num_threads = FLAGS_threads;
  design.certificate = FLAGS_certificate;
  design.approx_tolerance = FLAGS_approx_tolerance;
  // The task design: 1e-2 unless set (docs/design_algorithms.md).
  if (!app::IsDefault("approx_tolerance")) {
    design.task_approx_tolerance = FLAGS_approx_tolerance;
  }
  design.polish_pool_size = FLAGS_polish_pool_size;
  design.initial_poses = FLAGS_initial_poses;
  design.random_designs = FLAGS_random_designs;
  design.noise_m = FLAGS_noise_m;
  if (!app::IsDefault("target_rms_m")) design.target_rms_m = FLAGS_target_rms_m;
  options.task_poses_csv = FLAGS_task_poses_csv;
  options.measured_csv = FLAGS_measured_csv;
  if (!FLAGS_measured_csv.empty()) options.column_map = app::ColumnMapOrDie();
  options.cell_efficiency = FLAGS_cell_efficiency;
  options.order_shortest = FLAGS_order == "shortest";
  options.order_resolution_deg = FLAGS_order_resolution_deg;
  options.robot_path = FLAGS_robot;
  options.chain = app::Chain();
  options.rejected_csv = !FLAGS_rejected_csv.empty();
  app::NameProgramAndShowStages(&options);

  SelectSummary summary;
  const bool ok = Select(model, options, &summary);
  std::printf("%s", summary.report.c_str());
  if (!ok) app::Fail(summary.message);
  if (!FLAGS_curve_csv.empty() && design.target_rms_m) {
    app::WriteTextOrDie(FLAGS_curve_csv, summary.curve_csv);
  }
  if (!FLAGS_poses_csv.empty()) {
    app::WriteTextOrDie(FLAGS_poses_csv, summary.poses_csv);
  }
  if (!FLAGS_poses_csv.empty() || !program.path.empty()) {
    app::WriteProgramOrDie(model, program, summary.chosen,
                           "activecal_select's design");
  }
  if (!FLAGS_rejected_csv.empty()) {
    app::WriteTextOrDie(FLAGS_rejected_csv, summary.rejected_csv);
  }
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j = summary.json;
    j["timing"]["total_seconds"] = app::Seconds(start);
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
  app::PrintResult(summary.ResultLine(app::ProgramName()));
  return 0;
}

}  // namespace
}  // namespace activecal

ACTIVECAL_APP_MAIN(kUsage, activecal::Main)
