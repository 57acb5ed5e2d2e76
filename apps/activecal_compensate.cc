// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_compensate: rewrites a robot program so that the real robot,
// described by a calibrated model, reaches where the program meant
// ("filtering"). See kinematics/.../compensation.h for what a program
// means. With --cell a compensated configuration the robot cannot run in
// the cell (a collision, a joint margin left) gets status collision.

#include <gflags/gflags.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "activecal/calibration/cell_planning.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/targets_csv.h"
#include "activecal/kinematics/compensation.h"
#include "activecal/kinematics/corrected_compensation.h"
#include "app_common.h"

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

nlohmann::json Vector(const Eigen::VectorXd& v) {
  nlohmann::json j = nlohmann::json::array();
  for (int i = 0; i < v.size(); ++i) j.push_back(v[i]);
  return j;
}

Eigen::Vector3d RotationVector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

int Main() {
  if (FLAGS_out.empty()) app::Fail("--out is required");
  app::CheckWritableOrDie(FLAGS_out, "out");
  app::CheckWritableOrDie(FLAGS_json_out, "json_out");
  if (FLAGS_poses_csv.empty() == FLAGS_targets_csv.empty()) {
    app::Fail(
        "give exactly one of --poses_csv (joint targets) and "
        "--targets_csv (Cartesian targets)");
  }
  CompensationOptions options;
  if (!ParseIkMatch(FLAGS_match, &options.ik.match)) {
    app::Fail("--match must be position or pose, got '" + FLAGS_match + "'");
  }
  options.ik.position_tolerance_m = FLAGS_position_tolerance_m;
  options.ik.rotation_tolerance_rad = FLAGS_rotation_tolerance_rad;
  options.ik.rotation_weight_m = FLAGS_rotation_weight_m;
  options.ik.max_iterations = FLAGS_max_iterations;
  options.ik.singular_threshold = FLAGS_singular_threshold;
  options.num_threads = FLAGS_threads;
  if (!FLAGS_joint_weights.empty()) {
    std::istringstream in(FLAGS_joint_weights);
    std::string item;
    while (std::getline(in, item, ',')) {
      char* end = nullptr;
      const double w = std::strtod(item.c_str(), &end);
      if (item.empty() || *end != '\0') {
        app::Fail("--joint_weights: '" + item +
                  "' is not a number (comma-separated weights, one per "
                  "joint)");
      }
      options.ik.joint_weights.push_back(w);
    }
  }
  std::string error;
  if (!options.ik.IsValid(&error)) app::Fail(error);
  if (IsUrdfPath(FLAGS_robot) && FLAGS_frames.empty()) {
    // First, before anything else: a URDF carries neither the base frame
    // nor the markers a calibration found (they are in --frames_out), and
    // without them the joints move to fit a marker that is not there.
    const std::string tip =
        FLAGS_tip_link.empty() ? std::string() : " '" + FLAGS_tip_link + "'";
    std::fprintf(stderr,
                 "activecal_compensate: note: --robot=%s has no --frames: "
                 "the device frame is taken as the chain's base link and the "
                 "marker as the origin of the tip link%s, with no offset; "
                 "give the calibration's frames (activecal_identify "
                 "--frames_out) with --frames when it had a base frame or "
                 "markers\n",
                 FLAGS_robot.c_str(), tip.c_str());
  }

  RobotDescription robot = app::LoadRobotOrDie();
  const RobotModel& model = robot.model;
  // The cell, on the calibrated robot with its own markers (the program
  // places them; the cell's targets are for measuring).
  const CellSetup cell =
      FLAGS_cell.empty()
          ? CellSetup()
          : app::SetUpCellOrDie(FLAGS_cell, /*targets_as_markers=*/false,
                                &robot, FLAGS_nominal);
  if (cell.checker && cell.collision_source.empty()) {
    // A "converged" row must mean checked: without geometry the cell could
    // only check the joint margins.
    app::Fail("--cell: " +
              (FLAGS_nominal.empty()
                   ? "--robot=" + FLAGS_robot + " has no collision geometry"
                   : "neither --robot=" + FLAGS_robot + " nor --nominal=" +
                         FLAGS_nominal + " has collision geometry") +
              " (<collision> in a URDF, collision: in a robot file): the "
              "cell's collision checks cannot be made; give the nominal "
              "URDF with --nominal");
  }
  if (cell.checker) options.check = CellCompensationCheck(*cell.checker);
  options.ik.marker = model.MarkerIndex(FLAGS_marker);
  if (options.ik.marker < 0) {
    app::Fail("--marker: '" + FLAGS_marker + "' is not a marker of robot '" +
              model.name + "'");
  }
  CompensationSummary summary;
  std::vector<int64_t> labels;
  Eigen::MatrixXd starts;
  // The nominal model (with --poses_csv, what the program means; with
  // --targets_csv, optional: the size of the correction).
  RobotDescription nominal;
  Eigen::VectorXd meaning;
  if (!FLAGS_poses_csv.empty() && FLAGS_nominal.empty()) {
    app::Fail(
        "--poses_csv needs --nominal: the model the program was "
        "taught with");
  }
  if (!FLAGS_nominal.empty()) {
    RobotLoadOptions load;
    load.chain.base_link = FLAGS_base_link;
    load.chain.tip_link = FLAGS_tip_link;
    // The frames' markers are where the tracker's targets sit on the tool,
    // not geometry: the program means the point of that same marker. (The
    // frames' base is replaced by the calibrated one anyway.) Without
    // this, a URDF nominal kept its default marker at the tip link while
    // --robot's sat at the frames' marker: nominal == calibrated moved the
    // joints by up to 0.6 rad.
    load.frames_path = FLAGS_frames;
    if (!LoadRobot(FLAGS_nominal, load, &nominal, &error)) {
      app::Fail("--nominal: " + error);
    }
    if (!CheckSameChain(model, nominal.model, &error)) {
      app::Fail("--robot and --nominal: " + error);
    }
    meaning = ProgramMeaningParameters(model, model.nominal, nominal.model,
                                       nominal.model.nominal);
  }
  if (!FLAGS_poses_csv.empty()) {
    PoseList program;
    if (!ReadPosesCsv(FLAGS_poses_csv, model, /*reject_duplicates=*/false,
                      &program, &error)) {
      app::Fail("--poses_csv: " + error);
    }
    labels = program.pose_indices;
    starts = program.joints;
    CompensateProgram(model, model.nominal, nominal.model,
                      nominal.model.nominal, program.joints, options, &summary);
  } else {
    TargetList list;
    TargetsCsvOptions csv;
    csv.columns_strict = app::ColumnsStrict();
    std::vector<std::string> notes;
    if (!ReadTargetsCsv(FLAGS_targets_csv, model, csv, &list, &notes, &error)) {
      app::Fail("--targets_csv: " + error);
    }
    // On stdout: stderr keeps one line for an error.
    for (const std::string& n : notes) {
      std::printf("%s: note: %s\n", app::ProgramName().c_str(), n.c_str());
    }
    if (options.ik.match == IkMatch::kPose &&
        list.rotation_vectors.rows() == 0) {
      app::Fail("--match=pose needs the target orientations: --targets_csv " +
                FLAGS_targets_csv + " has no rx_rad, ry_rad, rz_rad columns");
    }
    const std::vector<IkTarget> targets = IkTargetsFromList(list);
    labels = list.pose_indices;
    CompensateTargets(model, model.nominal, targets, list.start_joints,
                      Eigen::VectorXd(), options, &summary);
    starts = list.start_joints;
  }
  if (summary.termination_type == TerminationType::kUserFailure) {
    app::Fail(summary.message);
  }
  // The learned correction of --robot's file (identify --learned_residual):
  // the targets reached by the hybrid model.
  const CorrectionRounds rounds = ApplyLearnedCorrection(
      model, model.nominal, robot.learned_correction, options, &summary);
  // The size of the correction: the nominal model's pose at the
  // compensated joints against the targets (the error compensation
  // removes); without --nominal (Cartesian targets) there is no nominal
  // to measure it with.
  const bool with_rotation = options.ik.match == IkMatch::kPose;
  const bool has_correction = !FLAGS_nominal.empty();
  const CorrectionSize correction =
      has_correction
          ? MeasureCorrection(nominal.model, meaning, options.ik.marker,
                              with_rotation, summary)
          : CorrectionSize();
  app::WriteTextOrDie(FLAGS_out,
                      CompensatedPosesCsvText(model, labels, summary));
  std::printf("%s", summary.BriefReport().c_str());
  if (!robot.learned_correction.empty()) {
    std::printf(
        "with --robot's learned correction (%d random Fourier features): %d "
        "fixed-point rounds, the last moved a correction by %.3g m; errors "
        "are of the corrected model\n",
        robot.learned_correction.num_features(), rounds.rounds,
        rounds.last_change_m);
  }
  if (has_correction) {
    std::printf(
        "correction (the nominal model at the compensated joints against "
        "the targets): position max %.3f mm, RMS %.3f mm",
        correction.max_position_m * 1e3, correction.rms_position_m * 1e3);
    if (with_rotation) {
      std::printf("; rotation max %.4f deg, RMS %.4f deg",
                  correction.max_rotation_rad * 180.0 / M_PI,
                  correction.rms_rotation_rad * 180.0 / M_PI);
    }
    std::printf("\n");
  }
  std::printf("wrote %zu compensated targets to %s\n", summary.results.size(),
              FLAGS_out.c_str());
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j;
    j["robot"] = model.name;
    j["nominal"] = FLAGS_nominal;
    j["program"] =
        FLAGS_poses_csv.empty() ? FLAGS_targets_csv : FLAGS_poses_csv;
    j["match"] = IkMatchName(options.ik.match);
    j["termination_type"] = TerminationTypeToString(summary.termination_type);
    j["all_converged"] = summary.AllConverged();
    j["num_targets"] = summary.results.size();
    j["num_converged"] = summary.num_converged;
    j["num_singular"] = summary.num_singular;
    j["num_limit"] = summary.num_limit;
    j["num_unreachable"] = summary.num_unreachable;
    j["num_invalid"] = summary.num_invalid;
    j["num_iteration_cap"] = summary.num_iteration_cap;
    j["num_collision"] = summary.num_collision;
    if (!FLAGS_cell.empty()) {
      j["cell"] = FLAGS_cell;
      j["collision_geometry"] = cell.collision_source;
    }
    // The inverse kinematics' residual of the calibrated model at its own
    // solution (about 0 when converged), and the size of the correction.
    j["max_ik_residual_m"] = summary.max_position_error_m;
    j["max_ik_residual_rad"] = summary.max_rotation_error_rad;
    if (has_correction) {
      nlohmann::json c = {{"num_targets", correction.num_targets},
                          {"max_position_m", correction.max_position_m},
                          {"rms_position_m", correction.rms_position_m}};
      if (with_rotation) {
        c["max_rotation_rad"] = correction.max_rotation_rad;
        c["rms_rotation_rad"] = correction.rms_rotation_rad;
      }
      j["correction"] = c;
    } else {
      j["correction"] = nullptr;
    }
    j["max_joint_change"] = summary.max_joint_change;
    j["rms_joint_change"] = summary.rms_joint_change;
    j["message"] = summary.message;
    j["learned_correction"] = !robot.learned_correction.empty();
    if (!robot.learned_correction.empty()) {
      j["learned_correction_rounds"] = rounds.rounds;
    }
    nlohmann::json rows = nlohmann::json::array();
    for (size_t i = 0; i < summary.results.size(); ++i) {
      const InverseKinematicsResult& r = summary.results[i];
      const IkTarget& t = summary.targets[i];
      nlohmann::json row = {{"pose_index", labels[i]},
                            {"status", IkStatusName(r.status)},
                            {"message", r.message},
                            {"position_error_m", r.position_error_m},
                            {"rotation_error_rad", r.rotation_error_rad},
                            {"iterations", r.iterations},
                            {"conditioning", r.conditioning},
                            {"joints", Vector(r.joints)},
                            {"target_m", Vector(t.point)}};
      if (options.ik.match == IkMatch::kPose) {
        row["target_rotation_vector_rad"] = Vector(RotationVector(t.rotation));
      }
      if (starts.rows() == static_cast<int64_t>(summary.results.size())) {
        const Eigen::VectorXd change = r.joints - starts.row(i).transpose();
        row["start_joints"] = Vector(starts.row(i).transpose());
        row["joint_change"] = Vector(change);
        row["max_joint_change"] = change.cwiseAbs().maxCoeff();
      }
      rows.push_back(row);
    }
    j["targets"] = rows;
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
  {
    // The one-line result (what --quiet prints): the JSON's num_converged,
    // num_targets, correction (mm, deg) and max_ik_residual_m (mm).
    char result[256];
    std::snprintf(result, sizeof(result), "%s: %d of %zu targets converged",
                  app::ProgramName().c_str(), summary.num_converged,
                  summary.results.size());
    std::string line = result;
    if (has_correction) {
      std::snprintf(
          result, sizeof(result), ", correction max %.3f mm, RMS %.3f mm",
          correction.max_position_m * 1e3, correction.rms_position_m * 1e3);
      line += result;
      if (with_rotation) {
        std::snprintf(result, sizeof(result), ", max %.4f deg, RMS %.4f deg",
                      correction.max_rotation_rad * 180.0 / M_PI,
                      correction.rms_rotation_rad * 180.0 / M_PI);
        line += result;
      }
    }
    std::snprintf(result, sizeof(result), ", IK residual max %.3g mm",
                  summary.max_position_error_m * 1e3);
    line += result;
    app::PrintResult(line);
  }
  if (!summary.AllConverged()) {
    // Not bad input: the files are complete, each target with its status.
    // The same counts as the summary's message, each first also by its
    // pose_index (a target refused by the cell converged, but is not to
    // be run: it is counted under collision, not converged).
    const std::string text = summary.NotConvergedText(labels);
    const size_t colon = text.find(':');
    std::fprintf(
        stderr, "activecal_compensate: %s, written with their status to %s%s\n",
        text.substr(0, colon).c_str(), FLAGS_out.c_str(),
        text.substr(colon).c_str());
    return 2;
  }
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
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
      "--out=path_joints.csv");
  return activecal::app::Finish(activecal::Main());
}
