// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_select: choose calibration poses for a robot (the paper's PUMA
// 560 by default) from a joint lattice or a pool read from CSV, by a
// D-optimal design algorithm or for the task accuracy (--criterion=task_rms),
// of a given size or of the fewest poses meeting a target (--target_rms_m),
// counting the poses already measured (--measured_csv). With --cell, only
// the poses a real cell can run (joint margins, collisions, the device's
// range and view of the targets) are candidates, and --order=shortest
// sorts the design into a short tour whose moves are checked.

#include <gflags/gflags.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/defaults.h"
#include "activecal/calibration/iso9283_cube.h"
#include "activecal/calibration/pool_builder.h"
#include "activecal/calibration/select_design.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/cell/measurable_pool.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/cell/tour.h"
#include "activecal/core/joint_sampling.h"
#include "activecal/core/lattice.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "activecal/selection/task_criterion.h"
#include "app_common.h"

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
  Iso9283CubeOptions options;
  std::string error;
  if (!ParseIso9283Cube(FLAGS_iso9283_cube, FLAGS_iso9283_orientation, &options,
                        &error)) {
    app::Fail(error);
  }
  if (cell.checker) options.check = CellCompensationCheck(*cell.checker);
  Iso9283CubeSummary summary;
  const bool ok = DesignIso9283Cube(model, model.nominal, options, &summary);
  std::printf("%s", summary.TableText().c_str());
  if (!ok) app::Fail("--iso9283_cube: " + summary.message);
  app::WriteTextOrDie(FLAGS_poses_csv, Iso9283CubePosesCsvText(model, summary));
  std::printf("  wrote %s\n", FLAGS_poses_csv.c_str());
  if (!FLAGS_iso9283_targets_csv.empty()) {
    app::WriteTextOrDie(FLAGS_iso9283_targets_csv,
                        Iso9283CubeTargetsCsvText(model, summary));
    std::printf("  wrote %s\n", FLAGS_iso9283_targets_csv.c_str());
  }
  return 0;
}

std::string Number(double x, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", digits, x);
  return buffer;
}

int Main() {
  const int64_t start = app::NowNs();
  RobotDescription robot = app::LoadRobotOrDie();
  const app::ProgramRequest program = app::ProgramRequestOrDie(
      robot.model, FLAGS_program_out, FLAGS_program_language, FLAGS_controller);
  app::CheckTourFlagsOrDie(FLAGS_order, FLAGS_order_resolution_deg);
  if (!FLAGS_rejected_csv.empty() && FLAGS_cell.empty()) {
    app::Fail("--rejected_csv needs --cell");
  }
  app::CheckWritableOrDie(FLAGS_rejected_csv, "rejected_csv");
  UrdfChainOptions chain;
  chain.base_link = FLAGS_base_link;
  chain.tip_link = FLAGS_tip_link;
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
  {
    std::string error;
    if (!ParseDesignAlgorithm(FLAGS_algorithm, &algorithm, &error) ||
        !ParseDesignCriterion(FLAGS_criterion, &criterion, &error)) {
      app::Fail("--" + error);
    }
  }
  if (criterion == DesignCriterion::kTaskRms &&
      gflags::GetCommandLineFlagInfoOrDie("algorithm").is_default) {
    algorithm = DesignAlgorithm::kFedorov;
  }
  Eigen::MatrixXd pool_joints;
  std::vector<int64_t> labels;
  JointLattice lattice;
  JointSampling sampling = JointSampling::kSobol;
  const bool measurable = FLAGS_pool == "measurable";
  const bool sampled = FLAGS_pool != "lattice" && !measurable;
  if (sampled && !JointSamplingFromString(FLAGS_pool, &sampling)) {
    app::Fail("--pool must be lattice, sobol, random or measurable, got '" +
              FLAGS_pool + "'");
  }
  if ((sampled || measurable) && !FLAGS_pool_csv.empty()) {
    app::Fail("--pool=" + FLAGS_pool + " and --pool_csv: choose one");
  }
  if (measurable && !with_cell) {
    app::Fail(
        "--pool=measurable needs --cell (the device and the targets "
        "to sample for)");
  }
  MeasurablePoolSummary measurable_summary;
  const bool from_lattice = FLAGS_pool_csv.empty() && !sampled && !measurable;
  // --pool_size sizes a drawn pool only: with the lattice (or a CSV) it was
  // silently ignored, so --pool_size=100000000000 exited 0 (issue 26).
  if (!sampled && !measurable &&
      !gflags::GetCommandLineFlagInfoOrDie("pool_size").is_default) {
    app::Fail("--pool_size sizes a --pool=sobol, random or measurable pool; " +
              std::string(from_lattice ? "the lattice has --levels poses per "
                                         "joint"
                                       : "--pool_csv has its rows") +
              ": give --pool or drop --pool_size");
  }
  // A pool too large for memory is refused before it is listed (it was a
  // std::bad_alloc), by the check the Python module uses (for a lattice in
  // MakeLatticeOrDie).
  std::string size_error;
  if ((sampled || measurable) &&
      !CheckSelectionPoolSize(FLAGS_pool_size, model, type, &size_error)) {
    app::Fail("--pool_size: " + size_error);
  }
  if (!measurable &&
      !gflags::GetCommandLineFlagInfoOrDie("max_draws").is_default) {
    app::Fail("--max_draws caps the draws of --pool=measurable, got --pool=" +
              FLAGS_pool);
  }
  if (FLAGS_max_draws < 0) {
    app::Fail("--max_draws must be >= 0, got " +
              std::to_string(FLAGS_max_draws));
  }
  if (measurable) {
    MeasurablePoolOptions o;
    o.num_poses = FLAGS_pool_size;
    o.max_draws = FLAGS_max_draws;
    o.seed = FLAGS_seed;
    o.num_threads = FLAGS_threads;
    {
      app::ProgressLine line("measurable poses");
      o.progress = line.callback();
      if (!SampleMeasurablePool(*cell.checker, o, &measurable_summary)) {
        app::Fail("--pool=measurable: " + measurable_summary.message);
      }
    }
    // Too few poses for the design (or none): one line with the counts.
    const int64_t needed =
        gflags::GetCommandLineFlagInfoOrDie("target_rms_m").is_default
            ? std::max(1, FLAGS_num_poses)
            : 1;
    if (measurable_summary.joints.rows() < needed) {
      app::Fail("--pool=measurable: " +
                measurable_summary.FailureText(*cell.checker) +
                (measurable_summary.gave_up
                     ? ""
                     : " (raise --max_draws, or fix the cell)"));
    }
    std::printf("  %s", measurable_summary.BriefReport().c_str());
    if (!measurable_summary.message.empty()) {
      std::printf("  --pool=measurable: note: %s\n",
                  measurable_summary.message.c_str());
    }
    pool_joints = measurable_summary.joints;
  } else if (from_lattice) {
    // With a cell the lattice spans the ranges inside the joint margins.
    lattice = app::MakeLatticeOrDie(
        with_cell ? WithinJointMargins(*cell.checker, model) : model,
        FLAGS_levels, type);
    pool_joints = lattice.AllJointValues();
  } else if (sampled) {
    std::string error;
    if (!SampleJointValues(
            with_cell ? WithinJointMargins(*cell.checker, model) : model,
            sampling, FLAGS_pool_size, FLAGS_seed, &pool_joints, &error)) {
      app::Fail("--pool=" + FLAGS_pool + ": " + error);
    }
  } else {
    PoseList list;
    std::string error;
    if (!ReadPosesCsv(FLAGS_pool_csv, model, /*reject_duplicates=*/true, &list,
                      &error)) {
      app::Fail("--pool_csv: " + error);
    }
    pool_joints = std::move(list.joints);
    labels = std::move(list.pose_indices);
  }
  if (gflags::GetCommandLineFlagInfoOrDie("target_rms_m").is_default &&
      (FLAGS_num_poses <= 0 || FLAGS_num_poses > pool_joints.rows())) {
    app::Fail("--num_poses must be in [1, " +
              std::to_string(pool_joints.rows()) + "] (the pool size), got " +
              std::to_string(FLAGS_num_poses));
  }
  // How the pool is stored: single precision where the double blocks would
  // not fit the budget (and the algorithm reads such pools).
  SelectionPoolOptions pool_options;
  pool_options.reads_float = ReadsFloatPool(algorithm, criterion);
  if (!PoolStorageFromString(FLAGS_pool_storage, &pool_options.storage)) {
    app::Fail("--pool_storage must be auto, double or float, got '" +
              FLAGS_pool_storage + "'");
  }
  if (pool_options.storage == PoolStorage::kFloat &&
      !pool_options.reads_float) {
    app::Fail(
        "--pool_storage=float needs --algorithm=fedorov or approx with "
        "the D criterion (got --algorithm=" +
        FLAGS_algorithm + " --criterion=" + FLAGS_criterion + ")");
  }
  if (pool_options.storage == PoolStorage::kAuto &&
      FLAGS_max_double_pool_mib < 0) {
    app::Fail("--max_double_pool_mib must be >= 0, got " +
              std::to_string(FLAGS_max_double_pool_mib));
  }
  pool_options.max_double_pool_mib = FLAGS_max_double_pool_mib;
  // The parameters the design is for: a named set is reduced to what the
  // pool separates, and the pool is linearised at the generic point of that
  // analysis.
  pool_options.parameter_set = app::ParameterSetOrDie(IsUrdfPath(FLAGS_robot));
  pool_options.type = type;
  pool_options.rotation_weight_m_per_rad = FLAGS_rotation_weight;
  pool_options.auto_fix = FLAGS_auto_fix;
  pool_options.num_threads = FLAGS_threads;
  // The preprocess: the cell's checks of every pose.
  PoolFilterSummary feasibility;
  if (with_cell) {
    pool_options.filter = [&](const Eigen::MatrixXd& joints,
                              std::vector<int64_t>* kept, std::string* note) {
      PoolFilterOptions o;
      o.num_threads = FLAGS_threads;
      app::ProgressLine line("cell checks");
      o.progress = line.callback();
      return CellPoolFilter(*cell.checker, o, &feasibility)(joints, kept, note);
    };
    // Several targets as the markers: each pose's rows are those seen.
    if (CellTargetsAreMarkers(*cell.checker, model)) {
      pool_options.kept_marker_masks = &feasibility.targets_seen;
    }
  }
  CandidatePool pool;
  SelectionPoolSummary pool_summary;
  bool pool_built;
  {
    app::ProgressLine line("Jacobians of the pool poses");
    pool_options.progress = line.callback();
    pool_built = BuildSelectionPool(&model, pool_joints, pool_options, &pool,
                                    &pool_summary);
    pool_options.progress = nullptr;  // the line ends here
  }
  if (pool_summary.filtered && !pool_summary.kept.empty()) {
    std::printf("  %s", feasibility.BriefReport(*cell.checker).c_str());
  }
  if (pool_summary.filtered && pool_summary.kept.empty()) {
    app::Fail("--cell: " + pool_summary.message);
  }
  if (pool_summary.reduction_failed) app::Fail("--" + pool_summary.message);
  if (pool_summary.termination_type == TerminationType::kUserFailure) {
    app::Fail(pool_summary.message);
  }
  for (const HeldParameter& d : pool_summary.dropped) {
    std::printf("  --parameter_set=%s: %s held fixed: %s\n",
                ParameterSetToString(pool_options.parameter_set),
                d.name.c_str(), d.reason.c_str());
  }
  if (pool_summary.single_precision) {
    std::printf(
        "  pool stored in single precision: %.4g MiB instead of %.4g MiB "
        "(design log det and certificate computed in double)\n",
        pool_summary.double_mib / 2, pool_summary.double_mib);
  }
  if (!pool_built) {
    const IdentifiabilityReport& report = pool_summary.pool.identifiability;
    if (!report.identifiable() && report.num_free > 0) {
      app::FailUnidentifiable(
          report,
          pool_summary.filtered
              ? "the feasible pool (" + pool_summary.filter_note + ")"
              : "the pool",
          FLAGS_auto_fix);
    }
    app::Fail(pool_summary.message);
  }
  app::NoteAutoFixed(HeldNames(pool_summary.pool.held),
                     pool_summary.pool.num_free_before, "the pool",
                     "--auto_fix");
  const double jacobian_seconds = pool_summary.pool.jacobian_seconds;
  // From here on the pool is the feasible one: its rows, labelled by their
  // place in the pool drawn (or their pose_index).
  const int64_t drawn_pool_size = pool_joints.rows();
  std::string rejected_csv_text;
  if (pool_summary.filtered && !FLAGS_rejected_csv.empty()) {
    rejected_csv_text =
        RejectedCsvText(*cell.checker, pool_joints, labels, feasibility);
  }
  if (pool_summary.filtered) {
    std::vector<int64_t> kept_labels;
    for (int64_t row : pool_summary.kept) {
      kept_labels.push_back(labels.empty() ? row : labels[row]);
    }
    pool_joints = feasibility.FeasibleJoints(pool_joints);
    labels = std::move(kept_labels);
    if (gflags::GetCommandLineFlagInfoOrDie("target_rms_m").is_default &&
        FLAGS_num_poses > pool_joints.rows()) {
      app::Fail("--num_poses=" + std::to_string(FLAGS_num_poses) +
                ": the feasible pool has only " + pool_summary.filter_note);
    }
  }
  const std::vector<std::string> auto_fixed = pool_summary.HeldFixed();

  // The design's options.
  SelectDesignOptions options;
  options.algorithm = algorithm;
  options.criterion = criterion;
  const bool task = options.task();
  options.num_poses = FLAGS_num_poses;
  options.restarts = FLAGS_restarts;
  options.seed = FLAGS_seed;
  options.num_threads = FLAGS_threads;
  options.certificate = FLAGS_certificate;
  options.approx_tolerance = FLAGS_approx_tolerance;
  // The task design: 1e-2 unless set (docs/design_algorithms.md).
  if (!gflags::GetCommandLineFlagInfoOrDie("approx_tolerance").is_default) {
    options.task_approx_tolerance = FLAGS_approx_tolerance;
  }
  options.polish_pool_size = FLAGS_polish_pool_size;
  options.initial_poses = FLAGS_initial_poses;
  options.random_designs = FLAGS_random_designs;
  options.noise_m = FLAGS_noise_m;
  const bool with_target =
      !gflags::GetCommandLineFlagInfoOrDie("target_rms_m").is_default;
  if (with_target) options.target_rms_m = FLAGS_target_rms_m;
  {
    std::string error;
    if (!options.IsValid(&error)) {
      // The options' names are the flags'.
      const std::string task_prefix = "criterion=task_rms: ";
      app::Fail(error.rfind(task_prefix, 0) == 0
                    ? "--" + task_prefix + "--" +
                          error.substr(task_prefix.size())
                    : "--" + error);
    }
  }
  if (!FLAGS_measured_csv.empty() && !task) {
    app::Fail(
        "--measured_csv needs --criterion=task_rms (the D-criterion "
        "algorithms take no prior information)");
  }

  // The task: position rows at the task poses (the pool by default).
  Eigen::MatrixXd W;
  int64_t num_task_poses = pool_joints.rows();
  {
    Eigen::MatrixXd task_joints;
    if (!FLAGS_task_poses_csv.empty()) {
      PoseList list;
      std::string error;
      if (!ReadPosesCsv(FLAGS_task_poses_csv, model,
                        /*reject_duplicates=*/false, &list, &error)) {
        app::Fail("--task_poses_csv: " + error);
      }
      task_joints = std::move(list.joints);
      num_task_poses = task_joints.rows();
    }
    CandidatePool task_pool;
    bool task_is_pool = false;
    std::string error;
    if (!BuildTaskPool(model, pool_joints, task_joints, pool_options,
                       &task_pool, &task_is_pool, &error)) {
      app::Fail("--task_poses_csv: " + error);
    }
    W = TaskMatrix(task_is_pool ? pool : task_pool);
  }
  // The poses already measured, whitened to --noise_m.
  RowMatrixXd prior(0, pool.num_parameters());
  int num_measured = 0;
  if (!FLAGS_measured_csv.empty()) {
    std::vector<Measurement> measured;
    std::string error;
    MeasurementsCsvOptions options;
    options.column_map = app::ColumnMapOrDie();
    if (!ReadMeasurementsCsv(FLAGS_measured_csv, model, options, &measured,
                             nullptr, &error)) {
      app::Fail("--measured_csv: " + error);
    }
    if (!MeasuredInformationRows(model, model.nominal, measured,
                                 FLAGS_rotation_weight, FLAGS_noise_m, &prior,
                                 &error)) {
      app::Fail("--measured_csv: " + error);
    }
    num_measured = static_cast<int>(measured.size());
  }
  const bool with_prior = prior.rows() > 0;
  // Several targets as the markers: a pose gives the rows of the targets it
  // sees only, so the pool's block rows overstate what --num_poses poses
  // give. The most the best --num_poses feasible poses can give, up front
  // as for one target (the exchange algorithms would otherwise return a
  // design of more poses, greedy fail on the first singular step).
  if (pool_options.kept_marker_masks != nullptr &&
      gflags::GetCommandLineFlagInfoOrDie("target_rms_m").is_default &&
      model.num_markers() > 0 && FLAGS_num_poses > 0) {
    const int rows_per_target = pool.block_rows() / model.num_markers();
    std::vector<int> rows;
    for (uint32_t mask : feasibility.targets_seen) {
      rows.push_back(rows_per_target * __builtin_popcount(mask));
    }
    std::sort(rows.begin(), rows.end(), std::greater<int>());
    int64_t equations = prior.rows();
    for (size_t k = 0;
         k < rows.size() && k < static_cast<size_t>(FLAGS_num_poses); ++k) {
      equations += rows[k];
    }
    if (equations < pool.num_parameters()) {
      const int most = rows.empty() ? 0 : rows[0] / rows_per_target;
      app::Fail(std::to_string(FLAGS_num_poses) + " poses give " +
                std::to_string(equations) + " equations, fewer than the " +
                std::to_string(pool.num_parameters()) +
                " parameters: every such design is singular (a feasible "
                "pose sees at most " +
                std::to_string(most) + " of the " +
                std::to_string(model.num_markers()) + " targets" +
                (with_prior ? "; with --measured_csv's rows" : "") + ")");
    }
  }

  SelectDesignSummary select;
  {
    app::ProgressLine approx_line("approximate design, rounds");
    app::ProgressLine restarts_line(
        std::string(DesignAlgorithmToString(options.algorithm)) + " restarts");
    options.approximate_progress = approx_line.callback();
    options.restarts_progress = restarts_line.callback();
    if (!SelectDesign(pool, W, prior, options, &select)) {
      // The target's failures name the flag.
      app::Fail(select.message.rfind("target_rms_m: ", 0) == 0
                    ? "--" + select.message
                    : select.message);
    }
  }
  // The D-efficiency lost to the cell: the design's det against that of the
  // same design problem on an unconstrained pool of the same size.
  nlohmann::json cell_efficiency_json;
  std::string cell_efficiency_line;  // printed after the design's report
  if (with_cell && FLAGS_cell_efficiency && !task && !with_target &&
      !with_prior) {
    const JointSampling free_sampling =
        sampled ? sampling : JointSampling::kSobol;
    Eigen::MatrixXd free_joints;
    std::string error;
    if (!SampleJointValues(model, free_sampling, pool_joints.rows(), FLAGS_seed,
                           &free_joints, &error)) {
      app::Fail("--cell_efficiency: the unconstrained pool: " + error);
    }
    SelectionPoolOptions free_options = pool_options;
    free_options.filter = nullptr;
    free_options.kept_marker_masks = nullptr;
    free_options.progress = nullptr;
    // The cell's targets as the markers: the cell's pool measures those a
    // pose sees; unconstrained, every one is seen at every pose (marker 0's
    // rows alone would leave the others' information out). The masks go
    // with a filter that keeps every row.
    std::vector<uint32_t> every_marker;
    if (pool_options.kept_marker_masks != nullptr) {
      every_marker.assign(free_joints.rows(), EveryMarkerMask(model));
      free_options.filter = [](const Eigen::MatrixXd& joints,
                               std::vector<int64_t>* kept, std::string*) {
        kept->resize(joints.rows());
        for (int64_t i = 0; i < joints.rows(); ++i) (*kept)[i] = i;
        return true;
      };
      free_options.kept_marker_masks = &every_marker;
    }
    RobotModel free_model = model;
    CandidatePool free_pool;
    SelectionPoolSummary free_summary;
    SelectDesignOptions free_design = options;
    free_design.num_poses = static_cast<int>(select.selection.design.size());
    free_design.certificate = false;
    free_design.approximate_progress = nullptr;
    free_design.restarts_progress = nullptr;
    SelectDesignSummary free_select;
    const RowMatrixXd no_prior(0, pool.num_parameters());
    if (!BuildSelectionPool(&free_model, free_joints, free_options, &free_pool,
                            &free_summary)) {
      cell_efficiency_line =
          "  D-efficiency lost to the cell: not computed: the unconstrained "
          "pool: " +
          free_summary.message + "\n";
    } else if (free_pool.num_parameters() != pool.num_parameters()) {
      cell_efficiency_line =
          "  D-efficiency lost to the cell: not computed: the unconstrained "
          "pool identifies " +
          std::to_string(free_pool.num_parameters()) +
          " parameters, the feasible pool " +
          std::to_string(pool.num_parameters()) + "\n";
    } else if (!SelectDesign(free_pool, TaskMatrix(free_pool), no_prior,
                             free_design, &free_select)) {
      app::Fail("--cell_efficiency: the unconstrained design: " +
                free_select.message);
    } else {
      const int p = static_cast<int>(pool.num_parameters());
      const double log10_cell = select.selection.log10_det();
      const double log10_free = free_select.selection.log10_det();
      const double efficiency = std::pow(10.0, (log10_cell - log10_free) / p);
      cell_efficiency_json = {
          {"d_efficiency", efficiency},
          {"log10_det_cell", log10_cell},
          {"log10_det_unconstrained", log10_free},
          {"num_parameters", p},
          {"unconstrained_pool", sampled ? FLAGS_pool : "sobol"},
          {"unconstrained_pool_size", free_joints.rows()}};
      char line[256];
      std::snprintf(
          line, sizeof(line),
          "  D-efficiency lost to the cell: %.4f = 10^((%.4f - %.4f) / %d) "
          "against an unconstrained %s pool of %lld poses\n",
          efficiency, log10_cell, log10_free, p,
          (sampled ? FLAGS_pool.c_str() : "sobol"),
          static_cast<long long>(free_joints.rows()));
      cell_efficiency_line = line;
    }
  }
  // The order to run the design in.
  TourSummary tour;
  const bool ordered = FLAGS_order == "shortest";
  const std::vector<double> velocity_limits =
      ordered ? RobotVelocityLimits(FLAGS_robot, chain, model)
              : std::vector<double>();
  if (ordered) {
    const std::vector<int64_t> design = select.selection.design;
    Eigen::MatrixXd design_joints(design.size(), pool_joints.cols());
    for (size_t k = 0; k < design.size(); ++k) {
      design_joints.row(k) = pool_joints.row(design[k]);
    }
    TourOptions o;
    o.velocity_limits = velocity_limits;
    o.resolution_rad = FLAGS_order_resolution_deg * M_PI / 180.0;
    o.resolution_m = FLAGS_order_resolution_deg * 1e-3;
    o.check_moves = with_cell;
    if (!OrderTour(with_cell ? cell.checker.get() : nullptr, design_joints, o,
                   &tour)) {
      app::Fail("--order=shortest: " + tour.message);
    }
    for (size_t k = 0; k < design.size(); ++k) {
      select.selection.design[k] = design[tour.order[k]];
    }
  }
  const SelectionSummary& summary = select.selection;
  const TargetSizeSummary& target = select.target;
  const ApproximateDesignSummary& approx = select.approx;
  const TaskApproximateSummary& task_approx = select.task_approx;
  const bool need_approx = select.with_approx;
  const bool need_task_approx = select.with_task_approx;
  const double predicted_rms = select.predicted_task_rms_m;
  const double total_seconds = app::Seconds(start);
  std::printf("%s", select.BriefReport().c_str());
  if (need_approx && pool.single_precision()) {
    std::printf(
        "  (the approximate design's bound is over the stored float blocks; "
        "the design's log det and certificate are over the double ones)\n");
  }
  std::printf("  predicted task RMS %.6g m over %lld task poses (sigma %g m",
              predicted_rms, static_cast<long long>(num_task_poses),
              FLAGS_noise_m);
  if (with_prior) {
    std::printf(", %d measured poses counted", num_measured);
  }
  std::printf(")\n");
  if (task && with_prior && FLAGS_certificate) {
    std::printf("  no certificate: its bounds assume no measured poses\n");
  }
  if (with_target) {
    std::printf("  target %g m: %s\n  %-10s %s\n", FLAGS_target_rms_m,
                target.message.c_str(), "num_poses", "predicted_task_rms_m");
    for (size_t k = 0; k < target.sizes.size(); ++k) {
      std::printf("  %-10d %.6g\n", target.sizes[k], target.rms_by_size_m[k]);
    }
    if (!FLAGS_curve_csv.empty()) {
      std::string csv = "num_poses,predicted_task_rms_m\n";
      for (size_t k = 0; k < target.sizes.size(); ++k) {
        csv += std::to_string(target.sizes[k]) + "," +
               Number(target.rms_by_size_m[k], 17) + "\n";
      }
      app::WriteTextOrDie(FLAGS_curve_csv, csv);
    }
  }
  std::printf("  Jacobians of %lld poses: %.3f s\n",
              static_cast<long long>(pool.size()), jacobian_seconds);
  std::printf("%s", cell_efficiency_line.c_str());
  if (ordered) {
    const nlohmann::json checked = MovesCheckedJson(with_cell, cell);
    std::printf(
        "  %s",
        tour.BriefReport(checked["moves_checked"].get<bool>()
                             ? std::string()
                             : checked["moves_not_checked"].get<std::string>())
            .c_str());
    const std::string note = AssumedVelocityNote(model, velocity_limits);
    if (!note.empty())
      std::printf("  --order=shortest: note: %s\n", note.c_str());
    for (size_t b = 0; b < tour.blocked_moves.size(); ++b) {
      std::printf(
          "  warning: the move from pose %d to pose %d is blocked: %s\n",
          tour.blocked_moves[b], tour.blocked_moves[b] + 1,
          tour.blocked_reasons[b].c_str());
    }
  }
  bool any_prismatic = false;
  for (int c = 0; c < model.num_joints(); ++c) {
    any_prismatic =
        any_prismatic || model.links[c].joint_type == JointType::kPrismatic;
  }
  std::printf("  %-6s %-8s %s\n", "#", "index",
              from_lattice    ? "levels (joint 1..n)"
              : any_prismatic ? "joints (deg; prismatic mm)"
                              : "joints (deg)");
  for (size_t k = 0; k < summary.design.size(); ++k) {
    const int64_t i = summary.design[k];
    std::printf("  %-6zu %-8lld", k,
                static_cast<long long>(labels.empty() ? i : labels[i]));
    if (from_lattice) {
      for (int l : lattice.Levels(labels.empty() ? i : labels[i])) {
        std::printf(" %d", l);
      }
    } else {
      for (int c = 0; c < pool_joints.cols(); ++c) {
        const bool prismatic =
            model.links[c].joint_type == JointType::kPrismatic;
        std::printf(" %.3f",
                    pool_joints(i, c) * (prismatic ? 1000.0 : 180.0 / M_PI));
      }
    }
    std::printf("\n");
  }
  if (!FLAGS_poses_csv.empty() || !program.path.empty()) {
    PoseList chosen;
    chosen.joints.resize(summary.design.size(), model.num_joints());
    for (size_t k = 0; k < summary.design.size(); ++k) {
      const int64_t i = summary.design[k];
      chosen.joints.row(k) = pool_joints.row(i);
      chosen.pose_indices.push_back(labels.empty() ? i : labels[i]);
    }
    if (!FLAGS_poses_csv.empty()) {
      std::string text = PosesCsvText(model, chosen);
      if (with_cell && !cell.cell.targets.empty()) {
        // Which targets to measure at each pose: those the cell sees.
        std::vector<uint32_t> seen;
        for (int64_t i : summary.design) {
          seen.push_back(feasibility.targets_seen[i]);
        }
        text = PosesCsvWithTargets(text, cell.cell, seen);
      }
      app::WriteTextOrDie(FLAGS_poses_csv, text);
    }
    app::WriteProgramOrDie(model, program, chosen, "activecal_select's design");
  }
  if (!FLAGS_rejected_csv.empty()) {
    app::WriteTextOrDie(FLAGS_rejected_csv, rejected_csv_text);
  }
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j = app::SelectionJson(summary, pool_joints, labels);
    if (with_cell) {
      // The preprocess: what the cell kept and why the rest went.
      j["cell"] = FLAGS_cell;
      j["drawn_pool_size"] = drawn_pool_size;
      if (!cell_efficiency_json.is_null()) {
        j["cell_d_efficiency"] = cell_efficiency_json;
      }
      j.update(CellPoolJson(cell.cell, feasibility));
      if (!cell.cell.targets.empty()) {
        nlohmann::json seen = nlohmann::json::array();
        for (int64_t i : summary.design) {
          seen.push_back(
              TargetsSeenJson(cell.cell, feasibility.targets_seen[i]));
        }
        j["targets_seen"] = seen;
      }
    }
    if (measurable) {
      j["measurable_pool"] = {
          {"poses", measurable_summary.joints.rows()},
          {"draws", measurable_summary.draws},
          {"ik_solves", measurable_summary.ik_solves},
          {"draws_per_pose", measurable_summary.DrawsPerPose()},
          {"ik_solves_per_pose", measurable_summary.SolvesPerPose()},
          {"seconds", measurable_summary.seconds}};
    }
    if (ordered) {
      std::vector<int64_t> run;
      for (int64_t i : summary.design) {
        run.push_back(labels.empty() ? i : labels[i]);
      }
      j["order"] = "shortest";
      j["tour"] = {{"motion_time_before_s", tour.time_before_s},
                   {"motion_time_after_s", tour.time_after_s},
                   {"velocities", tour.velocities},
                   {"resolution_deg", FLAGS_order_resolution_deg},
                   {"blocked_moves", tour.blocked_moves.size()},
                   {"blocked", BlockedMovesJson(tour.blocked_moves,
                                                tour.blocked_reasons, run)},
                   {"blocked_moves_before", tour.blocked_before}};
      j["tour"].update(MovesCheckedJson(with_cell, cell));
      const std::string note = AssumedVelocityNote(model, velocity_limits);
      if (!note.empty()) j["tour"]["velocity_note"] = note;
    }
    j["criterion"] = task ? "task_rms" : "d";
    j["num_poses"] = summary.design.size();
    j["noise_m"] = FLAGS_noise_m;
    j["predicted_task_rms_m"] = predicted_rms;
    j["num_task_poses"] = num_task_poses;
    j["task_poses_csv"] = FLAGS_task_poses_csv;
    j["measured_csv"] = FLAGS_measured_csv;
    j["num_measured"] = num_measured;
    if (with_target) {
      j["target_rms_m"] = FLAGS_target_rms_m;
      j["best_reachable_rms_m"] = target.best_reachable_rms_m;
      nlohmann::json curve = nlohmann::json::array();
      for (size_t k = 0; k < target.sizes.size(); ++k) {
        curve.push_back({target.sizes[k], target.rms_by_size_m[k]});
      }
      j["predicted_task_rms_by_size_m"] = curve;
    }
    j["robot"] = model.name;
    j["measurement"] = FLAGS_measurement;
    j["free_parameters"] = model.FreeParameterNames();
    j["auto_fixed"] = auto_fixed;
    j["seed"] = FLAGS_seed;
    j["pool"] = FLAGS_pool_csv.empty() ? FLAGS_pool : "csv";
    j["pool_storage"] = pool.single_precision() ? "float" : "double";
    j["pool_storage_mib"] = pool.storage_bytes() / (1024.0 * 1024.0);
    if (from_lattice) {
      j["levels"] = FLAGS_levels;
    } else if (!FLAGS_pool_csv.empty()) {
      j["pool_csv"] = FLAGS_pool_csv;
    }
    // Wall-clock times: the only fields that vary between runs.
    j["timing"] = {
        {"jacobian_seconds", jacobian_seconds},
        {"selection_seconds", summary.seconds},
        {"approximate_seconds", task ? task_approx.seconds : approx.seconds},
        {"total_seconds", total_seconds}};
    if (FLAGS_certificate && !task) {
      j["efficiency_lower_bound"] = summary.efficiency_lower_bound;
      j["log10_det_upper_bound"] = summary.log_det_upper_bound / std::log(10.0);
    }
    if (FLAGS_certificate && task && !with_prior) {
      // Task efficiency: RMS^2 of the best design of this size over this
      // design's, bounded below.
      j["efficiency_lower_bound"] = summary.efficiency_lower_bound;
      j["task_rms_lower_bound_m"] =
          PredictedTaskRms(summary.task_criterion_lower_bound, FLAGS_noise_m);
    }
    if (need_task_approx) {
      j["approximate_task"] = {
          {"support", task_approx.support},
          {"weights", task_approx.weights},
          {"predicted_task_rms_m",
           PredictedTaskRms(task_approx.criterion, FLAGS_noise_m)},
          {"efficiency_lower_bound", task_approx.efficiency_lower_bound},
          {"converged",
           task_approx.termination_type == TerminationType::kConvergence}};
    }
    if (need_approx) {
      j["approximate"] = {{"support", approx.support},
                          {"weights", approx.weights},
                          {"log10_det", approx.log_det / std::log(10.0)},
                          {"max_variance", approx.max_variance},
                          {"log10_det_upper_bound",
                           approx.log_det_upper_bound / std::log(10.0)},
                          {"tolerance", FLAGS_approx_tolerance},
                          {"converged", approx.termination_type ==
                                            TerminationType::kConvergence}};
    }
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
  {
    // The one-line result (what --quiet prints).
    char result[256];
    std::snprintf(result, sizeof(result),
                  "%s: %zu poses of %lld (%s), log10 det %.4f",
                  app::ProgramName().c_str(), summary.design.size(),
                  static_cast<long long>(pool_joints.rows()),
                  summary.algorithm.c_str(), summary.log10_det());
    std::string line = result;
    if (std::isfinite(summary.efficiency_lower_bound)) {
      std::snprintf(result, sizeof(result), ", D-efficiency >= %.4f",
                    summary.efficiency_lower_bound);
      line += result;
    }
    app::PrintResult(line);
  }
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Selects calibration poses from a lattice of joint values (or a pool "
      "read from CSV), maximising det(X^T X) of the measurement Jacobian at "
      "the nominal parameters, or (--criterion=task_rms) minimising the "
      "predicted RMS position error over the task poses; --target_rms_m "
      "finds the fewest poses meeting a target, --measured_csv counts the "
      "poses already measured. The robot is --robot (default: the Sun & "
      "Hollerbach PUMA 560).\n  activecal_select --algorithm=fedorov "
      "--seed=1 --json_out=design.json --poses_csv=poses.csv");
  return activecal::app::Finish(activecal::Main());
}
