// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_active: the active calibration loop. A D-optimal first batch
// at the nominal values, then, round by round, measure, identify, and
// select the next task-optimal batch at the new estimate, until the
// predicted task RMS meets --target_rms_m. The measurements come from a
// robot cell behind the driver protocol (--driver, docs/driver_protocol.md)
// or from a robot simulated here (the robot file's true values). With
// --session every answer and the loop's state are kept on disk as they
// come, and --resume continues after a crash. With --compare (simulation),
// one-shot designs of the same total size (D-optimal and task-optimal at
// nominal, random) are measured and identified too. With --cell every
// batch is chosen from the poses the cell can run (joint margins,
// collisions, the device's range and view of the targets).

#include <gflags/gflags.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "activecal/calibration/active_loop.h"
#include "activecal/calibration/active_session.h"
#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/pool_builder.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/cell/tour.h"
#include "activecal/core/random.h"
#include "activecal/driver/driver_client.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/robot_loader.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/task_criterion.h"
#include "activecal/selection/task_exchange.h"
#include "app_common.h"

DEFINE_int32(levels, 4,
             "Lattice values per joint of the pool (and of the task: the "
             "robot works over the whole lattice).");
DEFINE_double(noise_m, 1e-4,
              "The tracker's noise per axis (m): simulated without --driver; "
              "with one, what the prediction and the residual check assume.");
DEFINE_double(target_rms_m, 5e-5,
              "Stop when the predicted task RMS position error is at most "
              "this (m).");
DEFINE_int32(first_batch, 12, "Poses of the first, D-optimal batch.");
DEFINE_int32(batch_size, 6, "Poses of each later, task-optimal batch.");
DEFINE_int32(max_rounds, 30, "Rounds at most.");
DEFINE_double(nominal_error_scale, 1.0,
              "Start from truth + s (nominal - truth): 1 is the robot file's "
              "nominal, 0.1 one ten times closer to the truth, 2 farther.");
DEFINE_bool(compare, false,
            "Also measure one-shot designs of the loop's total size at the "
            "nominal values: D-optimal, task-optimal, random (simulation "
            "only).");
DEFINE_int32(restarts, 4, "Restarts of each design.");
DEFINE_uint64(seed, 1, "Seed of the noise and the random choices.");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");
DEFINE_string(json_out, "", "If set, write the per-round report here.");
DEFINE_string(driver, "",
              "Measure on a robot cell: the driver's command (run without a "
              "shell, e.g. \"python3 examples/driver_example.py\") or "
              "tcp://HOST:PORT of a running one (docs/driver_protocol.md). "
              "Empty: simulate the robot file's true values.");
DEFINE_double(driver_timeout_s, 120.0,
              "The longest wait for any answer of the driver (s).");
DEFINE_string(session, "",
              "Keep the session in this directory: every measurement "
              "appended to DIR/measurements.csv and synced as it comes, the "
              "loop's state after every round (docs/driver_protocol.md).");
DEFINE_bool(resume, false,
            "Continue the session in --session after a crash (of activecal "
            "or of the driver), without measuring again what it holds.");
DEFINE_bool(verbose, false, "One line per measurement.");
DEFINE_string(cell, "",
              "Cell file (YAML, docs/formats.md): joint margins, clearance, "
              "obstacles, the device and the targets. Every batch is chosen "
              "from the pool poses the cell can run; without --frames the "
              "cell's targets are the markers.");
DEFINE_string(order, "none",
              "none: each batch's poses in the design's order; shortest: "
              "a short tour in joint space (time at the URDF's velocity "
              "limits, nearest neighbour + 2-opt, as activecal_select), "
              "run from the end nearer the last pose measured; with --cell "
              "every move of the tour checked for collisions.");
DEFINE_double(order_resolution_deg, 1.0,
              "--order=shortest with --cell: a move is checked at joint "
              "steps of at most this (deg; mm for prismatic joints).");
DEFINE_string(program_out, "",
              "Also write the measured poses, in measuring order, as a "
              "program for the controller (docs/driver_protocol.md).");
DEFINE_string(program_language, "urscript",
              "--program_out's language: urscript, krl or rapid.");
DEFINE_string(controller, "",
              "The controller's joint convention (YAML: sign and zero of "
              "each joint, data/controllers/); empty: activecal's.");

namespace activecal {
namespace {

nlohmann::json Finite(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

nlohmann::json RoundJson(const ActiveRound& r) {
  return {{"num_poses", r.num_poses},
          {"batch", r.batch},
          {"excluded", r.excluded},
          {"predicted_task_rms_m", Finite(r.predicted_task_rms_m)},
          {"true_task_rms_m", Finite(r.true_task_rms_m)},
          {"parameter_change_task_rms_m", r.parameter_change_task_rms_m},
          {"parameter_change_max_abs", r.parameter_change_max_abs},
          {"residual_sigma_m", Finite(r.residual_sigma_m)},
          {"residuals_exceed_noise", r.residuals_exceed_noise}};
}

std::string Number(double v) {
  if (std::isnan(v)) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", v);
  return text;
}

// The measurer of a robot cell behind the driver protocol. Answers whose
// joint readings the model refuses are a failure (not recorded).
class DriverMeasurer : public Measurer {
 public:
  DriverMeasurer(const RobotModel& model, DriverClient* client)
      : model_(model), client_(client) {}
  bool Measure(const MeasureBatch& batch, int k, PoseAnswer* answer,
               std::string* error) override {
    MeasurementReply reply;
    std::vector<int> markers;  // the markers to measure (empty: all)
    for (int m = 0; !batch.markers.empty() && m < 32; ++m) {
      if (batch.markers[k] & (1u << m)) markers.push_back(m);
    }
    if (!client_->Measure(batch.joints.row(k).transpose(), &reply, error,
                          markers)) {
      return false;
    }
    *answer = PoseAnswer();
    if (reply.status != MeasureStatus::kOk) {
      answer->status = MeasureStatusToString(reply.status);
      answer->message = reply.message;
      return true;
    }
    answer->measurements = ReplyMeasurements(reply);
    for (const Measurement& m : answer->measurements) {
      std::string why;
      if (!CheckMeasurement(model_, m, &why)) {
        *error = client_->name() + ": the reply to measure " +
                 std::to_string(client_->last_id()) + ": " + why;
        return false;
      }
    }
    return true;
  }

 private:
  const RobotModel& model_;
  DriverClient* client_;
};

// Prints a line per answer (--verbose).
class VerboseMeasurer : public Measurer {
 public:
  VerboseMeasurer(Measurer* inner, const SessionMeasurer* session)
      : inner_(inner), session_(session) {}
  bool Measure(const MeasureBatch& batch, int k, PoseAnswer* answer,
               std::string* error) override {
    if (!inner_->Measure(batch, k, answer, error)) return false;
    std::printf("    round %d pose %lld (%d/%zu%s): ", batch.round,
                static_cast<long long>(batch.poses[k]), k + 1,
                batch.poses.size(), batch.attempt > 0 ? ", repair" : "");
    if (answer->measured()) {
      std::printf("ok, %zu marker%s seen", answer->measurements.size(),
                  answer->measurements.size() == 1 ? "" : "s");
    } else {
      std::printf("%s%s%s", answer->status.c_str(),
                  answer->message.empty() ? "" : ": ", answer->message.c_str());
    }
    std::printf("%s\n", session_ && session_->last_from_log()
                            ? " (from the session log)"
                            : "");
    std::fflush(stdout);
    return true;
  }

 private:
  Measurer* inner_;
  const SessionMeasurer* session_;
};

uint64_t Fnv1a(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string Text(double v) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", v);
  return text;
}

void PrintRound(int r, const ActiveRound& a, double seconds) {
  std::printf("  %-6d %-6d %-14.6g %-14s %-14.6g %-14.6g %-14s %-9zu %.1f%s\n",
              r, a.num_poses, a.predicted_task_rms_m,
              Number(a.true_task_rms_m).c_str(), a.parameter_change_task_rms_m,
              a.parameter_change_max_abs, Number(a.residual_sigma_m).c_str(),
              a.excluded.size(), seconds,
              a.residuals_exceed_noise ? "  (above the noise)" : "");
  std::fflush(stdout);
  if (a.residuals_exceed_noise) {
    std::fprintf(stderr,
                 "warning: round %d: the residual sigma %.3g m is %.1f "
                 "times --noise_m: the identified model does not fit the "
                 "measurements (a wrong local minimum?); its predicted task "
                 "RMS does not hold\n",
                 r, a.residual_sigma_m, a.residual_sigma_m / FLAGS_noise_m);
  }
}

int Main() {
  const int64_t start_ns = app::NowNs();
  RobotDescription robot = app::LoadRobotOrDie();
  // The cell: its checks, and its targets as the markers unless --frames
  // gives them (before the truth is read: the markers' true values come
  // with them).
  const bool with_cell = !FLAGS_cell.empty();
  const CellSetup cell =
      with_cell ? app::SetUpCellOrDie(FLAGS_cell, FLAGS_frames.empty(), &robot)
                : CellSetup();
  std::string cell_text;
  if (with_cell) {
    std::ifstream in(FLAGS_cell, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    cell_text = text.str();
  }
  const bool simulate = FLAGS_driver.empty();
  const bool truth_known =
      robot.true_parameters.size() == robot.model.num_parameters();
  if (simulate && !truth_known) {
    app::Fail(
        "--robot has no true values to simulate from (add 'true:' "
        "entries, docs/formats.md, or measure with --driver)");
  }
  if (!(FLAGS_nominal_error_scale >= 0) ||
      !std::isfinite(FLAGS_nominal_error_scale)) {
    app::Fail("--nominal_error_scale must be >= 0");
  }
  if (!truth_known && FLAGS_nominal_error_scale != 1) {
    app::Fail("--nominal_error_scale needs the robot's true values");
  }
  if (!simulate && FLAGS_compare) {
    app::Fail(
        "--compare simulates one-shot designs from the true values: not "
        "with --driver");
  }
  app::CheckTourFlagsOrDie(FLAGS_order, FLAGS_order_resolution_deg);
  if (FLAGS_resume && FLAGS_session.empty()) {
    app::Fail("--resume continues a --session: name its directory");
  }
  RobotModel model = robot.model;
  const Eigen::VectorXd truth =
      truth_known ? robot.true_parameters : Eigen::VectorXd();
  if (truth_known) {
    model.nominal = truth + FLAGS_nominal_error_scale * (model.nominal - truth);
  }
  // With a cell the lattice spans the ranges inside the joint margins.
  const JointLattice lattice = app::MakeLatticeOrDie(
      with_cell ? WithinJointMargins(*cell.checker, model) : model,
      FLAGS_levels);
  const Eigen::MatrixXd joints = lattice.AllJointValues();
  // The preprocess: the cell's checks of every pool pose, once; the loop
  // designs every batch (and every repair) from the feasible ones.
  PoolFilterSummary feasibility;
  if (with_cell) {
    PoolFilterOptions o;
    o.num_threads = FLAGS_threads;
    {
      app::ProgressLine line("cell checks");
      o.progress = line.callback();
      if (!FilterPool(*cell.checker, joints, o, &feasibility)) {
        app::Fail("--cell: " + feasibility.message);
      }
    }
    // As activecal_select: one line with the counts per reason.
    if (feasibility.num_feasible() == 0) {
      app::Fail("--cell: no pose of the pool is left: " +
                FeasibleNote(*cell.checker, feasibility));
    }
    if (feasibility.num_feasible() < FLAGS_first_batch) {
      app::Fail("--first_batch=" + std::to_string(FLAGS_first_batch) +
                ": the feasible pool has only " +
                FeasibleNote(*cell.checker, feasibility));
    }
    std::printf("  %s", feasibility.BriefReport(*cell.checker).c_str());
  }
  const bool urdf = !FLAGS_robot.empty() && IsUrdfPath(FLAGS_robot);
  if (urdf || !FLAGS_parameter_set.empty()) {
    // Reduced to what the poses the loop may design separate, each
    // measuring the targets it sees when they are the markers.
    // Several markers otherwise: each pose measures every one (the driver
    // is asked for all), so the reduction counts every marker's rows
    // (marker 0's alone held the others' offsets fixed).
    const bool masked =
        with_cell && CellTargetsAreMarkers(*cell.checker, model);
    const Eigen::MatrixXd reduction_joints =
        with_cell ? feasibility.FeasibleJoints(joints) : joints;
    std::vector<uint32_t> every_marker;
    if (!masked && model.num_markers() > 1) {
      every_marker.assign(reduction_joints.rows(), EveryMarkerMask(model));
    }
    // The loop starts at the reduction's point: a marker at the tip
    // frame's origin (no --frames) moved ~1 mm off the last axis, where the
    // kept parameters are separated. At the exact nominal the UR10e's
    // first batch was singular for them ("round 0: no restart produced a
    // non-singular design").
    Eigen::VectorXd point;
    model = WithFreeSet(model, app::ReducedParameterSetOrDie(
                                   model, urdf, reduction_joints,
                                   masked ? &feasibility.targets_seen
                                   : every_marker.empty() ? nullptr
                                                          : &every_marker,
                                   &point));
    model.nominal = point;
  }
  const app::ProgramRequest program = app::ProgramRequestOrDie(
      model, FLAGS_program_out, FLAGS_program_language, FLAGS_controller);
  app::CheckWritableOrDie(FLAGS_json_out, "json_out");
  ActiveLoopOptions options;
  options.sigma_m = FLAGS_noise_m;
  options.target_rms_m = FLAGS_target_rms_m;
  options.first_batch = FLAGS_first_batch;
  options.batch_size = FLAGS_batch_size;
  options.max_rounds = FLAGS_max_rounds;
  options.seed = FLAGS_seed;
  options.num_threads = FLAGS_threads;
  options.true_parameters = truth;
  if (with_cell) {
    options.pool_filter = [&feasibility](int64_t i) {
      return feasibility.verdicts[i].feasible();
    };
    // Several targets as the markers: each pose plans and measures those
    // it sees.
    if (CellTargetsAreMarkers(*cell.checker, model)) {
      for (const PoseVerdict& v : feasibility.verdicts) {
        options.marker_masks.push_back(v.targets_seen);
      }
    }
  }
  // Several markers, each measured at every pose: every marker's rows in
  // the design (without masks a pose's block is marker 0's).
  if (options.marker_masks.empty() && model.num_markers() > 1) {
    options.marker_masks.assign(joints.rows(), EveryMarkerMask(model));
  }
  std::string error;
  if (!options.IsValid(&error)) {
    // The options' names are the flags' but for sigma_m (--noise_m).
    if (error.rfind("sigma_m", 0) == 0) error.replace(0, 7, "noise_m");
    app::Fail("--" + error);
  }

  // The session: what its results depend on must not change between runs.
  std::unique_ptr<ActiveSession> session;
  if (!FLAGS_session.empty()) {
    RobotFileOptions robot_text;
    robot_text.true_parameters = truth;
    // The cell decides which poses may be designed: "none", or its file
    // by content. First: its targets are the robot's markers, so a change
    // of the targets alone changes robot_hash too, and the cell is what to
    // name.
    SessionIdentity identity = {
        {"cell", with_cell ? FLAGS_cell + " (hash " +
                                 std::to_string(Fnv1a(cell_text)) + ")"
                           : "none"},
        {"robot", model.name},
        {"robot_hash", std::to_string(Fnv1a(
                           RobotFileText(model, model.nominal, robot_text)))},
        {"measured_by", simulate ? "simulation" : "driver"},
        {"levels", std::to_string(FLAGS_levels)},
        {"pool_poses", std::to_string(joints.rows())},
        {"first_batch", std::to_string(FLAGS_first_batch)},
        {"batch_size", std::to_string(FLAGS_batch_size)},
        {"noise_m", Text(FLAGS_noise_m)},
        {"restarts", std::to_string(FLAGS_restarts)},
        {"seed", std::to_string(FLAGS_seed)},
        {"nominal_error_scale", Text(FLAGS_nominal_error_scale)},
    };
    identity.push_back({"order", FLAGS_order});
    if (!ActiveSession::Open(FLAGS_session, FLAGS_resume, model, identity,
                             &session, &error)) {
      app::Fail(error);
    }
    for (const std::string& n : session->notes()) {
      std::printf("note: %s\n", n.c_str());
    }
  }

  // Round 0: D-optimal; later rounds: task-optimal counting what is measured.
  auto d_optimal = [&](const CandidatePool& pool, int n,
                       const DesignConstraints& c, std::vector<int64_t>* out,
                       std::string* why) {
    FedorovOptions f;
    f.num_poses = n;
    f.restarts = FLAGS_restarts;
    f.seed = FLAGS_seed;
    f.num_threads = FLAGS_threads;
    SelectionSummary s;
    if (!FedorovExchange(pool, c, f, nullptr, &s)) {
      *why = s.message;
      return false;
    }
    *out = s.design;
    return true;
  };
  auto task_optimal = [&](const CandidatePool& pool, const Eigen::MatrixXd& W,
                          const RowMatrixXd& prior, const DesignConstraints& c,
                          int n, std::vector<int64_t>* out, std::string* why) {
    TaskExchangeOptions t;
    t.num_poses = n;
    t.restarts = FLAGS_restarts;
    t.seed = FLAGS_seed;
    t.num_threads = FLAGS_threads;
    SelectionSummary s;
    if (!TaskExchange(pool, W, prior, c, t, nullptr, &s)) {
      *why = s.message;
      return false;
    }
    *out = s.design;
    return true;
  };
  // --order=shortest: the new poses of each batch as a tour, run from the
  // end nearer the last pose measured (the fixed poses of a repair are
  // measured already).
  const bool ordered = FLAGS_order == "shortest";
  TourOptions tour_options;
  if (ordered) {
    UrdfChainOptions chain;
    chain.base_link = FLAGS_base_link;
    chain.tip_link = FLAGS_tip_link;
    tour_options.velocity_limits =
        RobotVelocityLimits(FLAGS_robot, chain, model);
    tour_options.resolution_rad = FLAGS_order_resolution_deg * M_PI / 180.0;
    tour_options.resolution_m = FLAGS_order_resolution_deg * 1e-3;
    tour_options.check_moves = with_cell;
  }
  double tour_before_s = 0.0, tour_after_s = 0.0;
  int tours = 0, blocked_moves = 0;
  nlohmann::json blocked_list = nlohmann::json::array();
  auto order_batch = [&](const BatchRequest& request,
                         std::vector<int64_t>* batch, std::string* why) {
    std::vector<int64_t> fixed, fresh;
    for (int64_t i : *batch) {
      const bool is_fixed =
          std::find(request.fixed.begin(), request.fixed.end(), i) !=
          request.fixed.end();
      (is_fixed ? fixed : fresh).push_back(i);
    }
    if (fresh.size() < 2) return true;
    Eigen::MatrixXd q(fresh.size(), joints.cols());
    for (size_t k = 0; k < fresh.size(); ++k) q.row(k) = joints.row(fresh[k]);
    TourSummary tour;
    if (!OrderTour(with_cell ? cell.checker.get() : nullptr, q, tour_options,
                   &tour)) {
      *why = "--order=shortest: " + tour.message;
      return false;
    }
    std::vector<int64_t> run;
    for (int k : tour.order) run.push_back(fresh[k]);
    const int64_t last = !request.fixed.empty()      ? request.fixed.back()
                         : !request.measured.empty() ? request.measured.back()
                                                     : -1;
    if (last >= 0) {
      const Eigen::VectorXd from = joints.row(last).transpose();
      if (MoveTime(from, joints.row(run.back()).transpose(), tour.velocities) <
          MoveTime(from, joints.row(run.front()).transpose(),
                   tour.velocities)) {
        std::reverse(run.begin(), run.end());
      }
    }
    tour_before_s += tour.time_before_s;
    tour_after_s += tour.time_after_s;
    blocked_moves += static_cast<int>(tour.blocked_moves.size());
    {
      std::vector<int64_t> tour_run;
      for (int k : tour.order) tour_run.push_back(fresh[k]);
      for (nlohmann::json b : BlockedMovesJson(
               tour.blocked_moves, tour.blocked_reasons, tour_run)) {
        b["batch"] = tours;
        blocked_list.push_back(b);
      }
    }
    ++tours;
    *batch = fixed;
    batch->insert(batch->end(), run.begin(), run.end());
    return true;
  };
  BatchSelector select = [&](const CandidatePool& pool,
                             const Eigen::MatrixXd& W, const RowMatrixXd& prior,
                             const BatchRequest& request,
                             std::vector<int64_t>* batch, std::string* why) {
    DesignConstraints c;
    c.fixed = request.fixed;
    c.excluded = request.excluded;
    const bool chosen =
        request.round == 0
            ? d_optimal(pool, request.num_poses, c, batch, why)
            : task_optimal(pool, W, prior, c, request.num_poses, batch, why);
    return chosen && (!ordered || order_batch(request, batch, why));
  };

  // The measurers: the cell (or the simulation), the session's log around
  // it, the per-measurement lines around that.
  std::unique_ptr<DriverClient> client;
  std::unique_ptr<Measurer> source;
  if (simulate) {
    source.reset(
        new SimulatedMeasurer(model, truth, FLAGS_noise_m, FLAGS_seed));
  } else {
    DriverClientOptions driver_options;
    driver_options.driver = FLAGS_driver;
    driver_options.timeout_s = FLAGS_driver_timeout_s;
    DriverHello hello;
    for (const Link& link : model.links) hello.joint_names.push_back(link.name);
    hello.markers = model.num_markers();
    hello.robot = model.name;
    if (!driver_options.IsValid(&error)) app::Fail("--" + error);
    if (!DriverClient::Start(driver_options, hello, &client, &error)) {
      app::Fail(error + (session ? " (the session in " + FLAGS_session +
                                       " is kept: continue it with --resume)"
                                 : ""));
    }
    if (FLAGS_verbose) {
      std::printf("%s: %s\n", client->name().c_str(),
                  client->driver_hello().c_str());
    }
    source.reset(new DriverMeasurer(model, client.get()));
  }
  Measurer* measurer = source.get();
  std::unique_ptr<SessionMeasurer> logged;
  if (session) {
    logged.reset(new SessionMeasurer(session.get(), measurer));
    measurer = logged.get();
  }
  std::unique_ptr<VerboseMeasurer> verbose;
  if (FLAGS_verbose) {
    verbose.reset(new VerboseMeasurer(measurer, logged.get()));
    measurer = verbose.get();
  }

  std::printf("activecal active loop: robot '%s', %lld pool poses, %s\n",
              model.name.c_str(), static_cast<long long>(joints.rows()),
              simulate
                  ? "simulated from the robot file's true values"
                  : ("measured by " + client->name() +
                     (truth_known ? " (true error from the robot file's true "
                                    "values)"
                                  : ""))
                        .c_str());
  if (truth_known) {
    std::printf(
        "  nominal model: true task RMS %.6g m (--nominal_error_scale %g)\n",
        TaskRmsDistance(model, model.nominal, truth, joints),
        FLAGS_nominal_error_scale);
  }
  std::printf("  %-6s %-6s %-14s %-14s %-14s %-14s %-14s %-9s %s\n", "round",
              "poses", "predicted_m", "true_m", "change_m", "change_max",
              "resid_sigma_m", "excluded", "seconds");
  const ActiveLoopState* resume = session ? session->resume_state() : nullptr;
  if (resume != nullptr) {
    for (size_t r = 0; r < resume->rounds.size(); ++r) {
      PrintRound(static_cast<int>(r), resume->rounds[r], 0.0);
    }
  }
  options.round_callback = [&](const ActiveLoopState& state, std::string* why) {
    PrintRound(state.round - 1, state.rounds.back(), app::Seconds(start_ns));
    // On stderr, flushed (stdout may sit in a pipe's buffer): a round can
    // take seconds (a measurement per pose, a selection, a fit).
    const ActiveRound& a = state.rounds.back();
    char line[160];
    std::snprintf(line, sizeof(line),
                  "round %d done: %d poses, predicted task RMS %.3g m (%.1f s)",
                  state.round - 1, a.num_poses, a.predicted_task_rms_m,
                  app::Seconds(start_ns));
    app::PrintProgress(line);
    return !session || session->SaveState(state, why);
  };
  ActiveLoopSummary summary;
  const bool ok = RunActiveLoop(model, joints, joints, options, select,
                                measurer, resume, &summary);
  const std::string closing = client ? client->Close() : "";
  if (!closing.empty()) std::printf("note: %s\n", closing.c_str());
  const std::string kept =
      session ? " (the session in " + FLAGS_session +
                    " keeps every answer: continue it with --resume)"
              : "";
  if (!ok && summary.rounds.empty()) app::Fail(summary.message + kept);
  std::printf("activecal active loop: %s\n  %s\n",
              TerminationTypeToString(summary.termination_type),
              summary.message.c_str());
  std::fflush(stdout);
  nlohmann::json j;
  j["termination_type"] = TerminationTypeToString(summary.termination_type);
  j["message"] = summary.message;
  j["robot"] = model.name;
  j["levels"] = FLAGS_levels;
  j["noise_m"] = FLAGS_noise_m;
  j["target_rms_m"] = FLAGS_target_rms_m;
  j["seed"] = FLAGS_seed;
  j["nominal_error_scale"] = FLAGS_nominal_error_scale;
  j["nominal_true_task_rms_m"] = Finite(summary.nominal_true_task_rms_m);
  j["measured_by"] = simulate ? "simulation" : "driver";
  j["rounds"] = nlohmann::json::array();
  for (const ActiveRound& a : summary.rounds)
    j["rounds"].push_back(RoundJson(a));
  j["measured_pose_indices"] = summary.measured;
  if (ordered) {
    // Summed over the batches' tours (the moves between batches not
    // counted).
    const nlohmann::json moves = MovesCheckedJson(with_cell, cell);
    const std::string checked =
        moves["moves_checked"].get<bool>()
            ? ", " + std::to_string(blocked_moves) + " blocked moves left"
            : " (moves not checked for collisions: " +
                  moves["moves_not_checked"].get<std::string>() + ")";
    std::printf(
        "  --order=shortest: %d batch tours, estimated motion time %.4g s "
        "-> %.4g s%s\n",
        tours, tour_before_s, tour_after_s, checked.c_str());
    const std::string note =
        AssumedVelocityNote(model, tour_options.velocity_limits);
    if (!note.empty()) {
      std::printf("  --order=shortest: note: %s\n", note.c_str());
    }
    j["order"] = "shortest";
    j["tour"] = {{"batches", tours},
                 {"motion_time_before_s", tour_before_s},
                 {"motion_time_after_s", tour_after_s},
                 {"resolution_deg", FLAGS_order_resolution_deg},
                 {"blocked_moves", blocked_moves},
                 {"blocked", blocked_list}};
    j["tour"].update(moves);
    if (!note.empty()) j["tour"]["velocity_note"] = note;
  }
  if (with_cell) {
    // The preprocess, and the targets each measured pose sees.
    j["cell"] = FLAGS_cell;
    j.update(CellPoolJson(cell.cell, feasibility));
    if (!cell.cell.targets.empty()) {
      nlohmann::json seen = nlohmann::json::array();
      for (int64_t i : summary.measured) {
        seen.push_back(
            TargetsSeenJson(cell.cell, feasibility.verdicts[i].targets_seen));
      }
      j["targets_seen"] = seen;
    }
  }
  j["excluded_poses"] = nlohmann::json::array();
  for (const ExcludedPose& e : summary.excluded) {
    j["excluded_poses"].push_back({{"pose_index", e.pose},
                                   {"round", e.round},
                                   {"status", e.status},
                                   {"message", e.message}});
  }

  if (FLAGS_compare && !summary.measured.empty()) {
    const int n = static_cast<int>(summary.measured.size());
    CandidatePoolOptions pool_options;
    pool_options.num_threads = FLAGS_threads;
    CandidatePool pool;
    CandidatePoolSummary pool_summary;
    if (!BuildCandidatePool(model, model.nominal, joints, pool_options, &pool,
                            &pool_summary)) {
      app::Fail("pool at nominal: " + pool_summary.message);
    }
    const Eigen::MatrixXd W = TaskMatrix(pool);
    std::vector<std::pair<std::string, std::vector<int64_t>>> designs(3);
    designs[0].first = "d_optimal_at_nominal";
    designs[1].first = "task_optimal_at_nominal";
    designs[2].first = "random";
    if (!d_optimal(pool, n, {}, &designs[0].second, &error) ||
        !task_optimal(pool, W, RowMatrixXd(0, pool.num_parameters()), {}, n,
                      &designs[1].second, &error)) {
      app::Fail("one-shot design: " + error);
    }
    Random random(Random::StreamSeed(FLAGS_seed, 1000));
    designs[2].second = random.SampleWithoutReplacement(pool.size(), n);
    std::printf("  one-shot designs of %d poses at the nominal values:\n", n);
    std::printf("  %-26s %-14s %s\n", "design", "predicted_m", "true_m");
    j["one_shot"] = nlohmann::json::object();
    for (const auto& [name, design] : designs) {
      ActiveRound r;
      if (!EvaluateOneShot(model, truth, joints, joints, design, options, &r,
                           &error)) {
        std::printf("  %-26s failed: %s\n", name.c_str(), error.c_str());
        j["one_shot"][name] = {{"error", error}};
        continue;
      }
      std::printf("  %-26s %-14.6g %.6g\n", name.c_str(),
                  r.predicted_task_rms_m, r.true_task_rms_m);
      j["one_shot"][name] = RoundJson(r);
    }
  }
  if (!FLAGS_json_out.empty()) app::WriteJsonOrDie(FLAGS_json_out, j);
  if (!program.path.empty()) {
    PoseList poses;
    poses.joints.resize(summary.measured.size(), joints.cols());
    for (size_t k = 0; k < summary.measured.size(); ++k) {
      poses.joints.row(k) = joints.row(summary.measured[k]);
    }
    poses.pose_indices = summary.measured;
    app::WriteProgramOrDie(model, program, poses,
                           "the poses activecal_active measured, in order");
  }
  if (!ok) app::Fail(summary.message + kept);
  // The result line (all that --quiet prints).
  const double predicted = summary.rounds.empty()
                               ? HUGE_VAL
                               : summary.rounds.back().predicted_task_rms_m;
  char result[256];
  std::snprintf(result, sizeof(result),
                "activecal_active: %s after %d round%s, %d poses measured, "
                "predicted task RMS %.4g mm (target %.4g mm)",
                TerminationTypeToString(summary.termination_type),
                static_cast<int>(summary.rounds.size()),
                summary.rounds.size() == 1 ? "" : "s",
                static_cast<int>(summary.measured.size()), 1e3 * predicted,
                1e3 * FLAGS_target_rms_m);
  app::PrintResult(result);
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "The active calibration loop: a D-optimal first batch, then "
      "task-optimal batches designed at each new estimate, until the "
      "predicted task RMS meets --target_rms_m. Measured by a robot cell "
      "(--driver, docs/driver_protocol.md) or simulated (--robot with "
      "'true:' values; default the Sun & Hollerbach PUMA 560).\n"
      "  activecal_active --target_rms_m=5e-5 --compare --json_out=loop.json\n"
      "  activecal_active --driver=\"activecal_sim_cell --seed=7\" "
      "--session=run1   (then --resume after a crash)");
  return activecal::app::Finish(activecal::Main());
}
