// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/active_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "activecal/calibration/active_session.h"
#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/pool_builder.h"
#include "activecal/calibration/pool_reduction.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/cell/tour.h"
#include "activecal/core/lattice.h"
#include "activecal/core/random.h"
#include "activecal/driver/driver_client.h"
#include "activecal/io/robot_file.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/task_criterion.h"
#include "activecal/selection/task_exchange.h"
#include "restart_options.h"
#include "seconds_since.h"

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

// printf to `out` (null: nothing).
void Print(FILE* out, const char* format, ...)
    __attribute__((format(printf, 2, 3)));
void Print(FILE* out, const char* format, ...) {
  if (out == nullptr) return;
  va_list args;
  va_start(args, format);
  std::vfprintf(out, format, args);
  va_end(args);
}

using internal::SecondsSince;

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

// Prints a line per answer (verbose).
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

// The batches: round 0 D-optimal, later rounds task-optimal counting what
// is measured, each batch's new poses optionally as a tour; the tours'
// totals for the report.
class BatchDesigner {
 public:
  BatchDesigner(const RobotModel& model, const Eigen::MatrixXd& joints,
                const CellSetup* cell, const ActiveCalibrationOptions& options)
      : joints_(joints), cell_(cell), options_(options) {
    if (options.order_shortest) {
      tour_options_.velocity_limits =
          RobotVelocityLimits(options.robot_path, options.chain, model);
      tour_options_.resolution_rad =
          options.order_resolution_deg * M_PI / 180.0;
      tour_options_.resolution_m = options.order_resolution_deg * 1e-3;
      tour_options_.check_moves = cell != nullptr;
    }
  }

  // The options of the batch's design of n poses.
  template <typename AlgorithmOptions>
  AlgorithmOptions Options(int n) const {
    return internal::RestartOptions<AlgorithmOptions>(
        n, options_.restarts, options_.loop.seed, options_.loop.num_threads);
  }

  // The design of s into *out when `designed`; else false with *why.
  static bool Designed(bool designed, const SelectionSummary& s,
                       std::vector<int64_t>* out, std::string* why) {
    if (!designed) {
      *why = s.message;
      return false;
    }
    *out = s.design;
    return true;
  }

  bool DOptimal(const CandidatePool& pool, int n, const DesignConstraints& c,
                std::vector<int64_t>* out, std::string* why) const {
    SelectionSummary s;
    return Designed(
        FedorovExchange(pool, c, Options<FedorovOptions>(n), nullptr, &s), s,
        out, why);
  }

  bool TaskOptimal(const CandidatePool& pool, const Eigen::MatrixXd& W,
                   const RowMatrixXd& prior, const DesignConstraints& c, int n,
                   std::vector<int64_t>* out, std::string* why) const {
    SelectionSummary s;
    return Designed(TaskExchange(pool, W, prior, c,
                                 Options<TaskExchangeOptions>(n), nullptr, &s),
                    s, out, why);
  }

  // The new poses of the batch as a tour, run from the end nearer the last
  // pose measured (the fixed poses of a repair are measured already).
  bool Order(const BatchRequest& request, std::vector<int64_t>* batch,
             std::string* why) {
    std::vector<int64_t> fixed, fresh;
    for (int64_t i : *batch) {
      const bool is_fixed =
          std::find(request.fixed.begin(), request.fixed.end(), i) !=
          request.fixed.end();
      (is_fixed ? fixed : fresh).push_back(i);
    }
    if (fresh.size() < 2) return true;
    Eigen::MatrixXd q(fresh.size(), joints_.cols());
    for (size_t k = 0; k < fresh.size(); ++k) q.row(k) = joints_.row(fresh[k]);
    TourSummary tour;
    if (!OrderTour(cell_ ? cell_->checker.get() : nullptr, q, tour_options_,
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
      const Eigen::VectorXd from = joints_.row(last).transpose();
      if (MoveTime(from, joints_.row(run.back()).transpose(), tour.velocities) <
          MoveTime(from, joints_.row(run.front()).transpose(),
                   tour.velocities)) {
        std::reverse(run.begin(), run.end());
      }
    }
    tour_before_s_ += tour.time_before_s;
    tour_after_s_ += tour.time_after_s;
    blocked_moves_ += static_cast<int>(tour.blocked_moves.size());
    {
      std::vector<int64_t> tour_run;
      for (int k : tour.order) tour_run.push_back(fresh[k]);
      for (nlohmann::json b : BlockedMovesJson(
               tour.blocked_moves, tour.blocked_reasons, tour_run)) {
        b["batch"] = tours_;
        blocked_list_.push_back(b);
      }
    }
    ++tours_;
    *batch = fixed;
    batch->insert(batch->end(), run.begin(), run.end());
    return true;
  }

  BatchSelector Selector() {
    return [this](const CandidatePool& pool, const Eigen::MatrixXd& W,
                  const RowMatrixXd& prior, const BatchRequest& request,
                  std::vector<int64_t>* batch, std::string* why) {
      DesignConstraints c;
      c.fixed = request.fixed;
      c.excluded = request.excluded;
      const bool chosen =
          request.round == 0
              ? DOptimal(pool, request.num_poses, c, batch, why)
              : TaskOptimal(pool, W, prior, c, request.num_poses, batch, why);
      return chosen && (!options_.order_shortest || Order(request, batch, why));
    };
  }

  // Prints the tours' line and adds "order" and "tour" to the report.
  void Report(FILE* out, const RobotModel& model, nlohmann::json* j) const {
    // Summed over the batches' tours (the moves between batches not
    // counted).
    const nlohmann::json moves =
        MovesCheckedJson(cell_ != nullptr, cell_ ? *cell_ : no_cell_);
    const std::string checked =
        moves["moves_checked"].get<bool>()
            ? ", " + std::to_string(blocked_moves_) + " blocked moves left"
            : " (moves not checked for collisions: " +
                  moves["moves_not_checked"].get<std::string>() + ")";
    Print(out,
          "  --order=shortest: %d batch tours, estimated motion time %.4g s "
          "-> %.4g s%s\n",
          tours_, tour_before_s_, tour_after_s_, checked.c_str());
    const std::string note =
        AssumedVelocityNote(model, tour_options_.velocity_limits);
    if (!note.empty()) {
      Print(out, "  --order=shortest: note: %s\n", note.c_str());
    }
    (*j)["order"] = "shortest";
    (*j)["tour"] = {{"batches", tours_},
                    {"motion_time_before_s", tour_before_s_},
                    {"motion_time_after_s", tour_after_s_},
                    {"resolution_deg", options_.order_resolution_deg},
                    {"blocked_moves", blocked_moves_},
                    {"blocked", blocked_list_}};
    (*j)["tour"].update(moves);
    if (!note.empty()) (*j)["tour"]["velocity_note"] = note;
  }

 private:
  const Eigen::MatrixXd& joints_;
  const CellSetup* cell_;
  const ActiveCalibrationOptions& options_;
  const CellSetup no_cell_;
  TourOptions tour_options_;
  double tour_before_s_ = 0.0, tour_after_s_ = 0.0;
  int tours_ = 0, blocked_moves_ = 0;
  nlohmann::json blocked_list_ = nlohmann::json::array();
};

// Prints a round's row; a round whose residuals exceed the noise gets a
// warning, added to *warnings and passed to `warn` (may be empty).
void PrintRound(FILE* out, int r, const ActiveRound& a, double seconds,
                double sigma_m, std::vector<std::string>* warnings,
                const std::function<void(const std::string&)>& warn) {
  Print(out, "  %-6d %-6d %-14.6g %-14s %-14.6g %-14.6g %-14s %-9zu %.1f%s\n",
        r, a.num_poses, a.predicted_task_rms_m,
        Number(a.true_task_rms_m).c_str(), a.parameter_change_task_rms_m,
        a.parameter_change_max_abs, Number(a.residual_sigma_m).c_str(),
        a.excluded.size(), seconds,
        a.residuals_exceed_noise ? "  (above the noise)" : "");
  if (out) std::fflush(out);
  if (a.residuals_exceed_noise) {
    const char* format =
        "warning: round %d: the residual sigma %.3g m is %.1f times "
        "--noise_m: the identified model does not fit the measurements (a "
        "wrong local minimum?); its predicted task RMS does not hold";
    const double ratio = a.residual_sigma_m / sigma_m;
    std::string line(
        std::snprintf(nullptr, 0, format, r, a.residual_sigma_m, ratio) + 1,
        '\0');
    std::snprintf(&line[0], line.size(), format, r, a.residual_sigma_m, ratio);
    line.pop_back();
    warnings->push_back(line);
    if (warn) warn(line);
  }
}

}  // namespace

std::string ActiveCalibrationSummary::ResultLine(double target_rms_m) const {
  const double predicted =
      loop.rounds.empty() ? HUGE_VAL : loop.rounds.back().predicted_task_rms_m;
  char result[256];
  std::snprintf(result, sizeof(result),
                "%s after %d round%s, %d poses measured, predicted task RMS "
                "%.4g mm (target %.4g mm)",
                TerminationTypeToString(loop.termination_type),
                static_cast<int>(loop.rounds.size()),
                loop.rounds.size() == 1 ? "" : "s",
                static_cast<int>(loop.measured.size()), 1e3 * predicted,
                1e3 * target_rms_m);
  return result;
}

bool ActiveCalibrationOptions::IsValidFor(bool truth_known,
                                          std::string* error) const {
  std::string e;
  if (driver.empty() && !truth_known) {
    e = "--robot has no true values to simulate from (add 'true:' entries, "
        "docs/formats.md, or measure with --driver)";
  } else if (!(nominal_error_scale >= 0) ||
             !std::isfinite(nominal_error_scale)) {
    e = "--nominal_error_scale must be >= 0";
  } else if (!truth_known && nominal_error_scale != 1) {
    e = "--nominal_error_scale needs the robot's true values";
  } else if (!driver.empty() && compare) {
    e = "--compare simulates one-shot designs from the true values: not "
        "with --driver";
  }
  if (!e.empty() && error) *error = e;
  return e.empty();
}

bool MakeActivePool(const RobotModel& model, const Eigen::VectorXd& truth,
                    const CellSetup* cell,
                    const ActiveCalibrationOptions& options, ActivePool* pool) {
  *pool = ActivePool();
  pool->model = model;
  if (truth.size() == model.num_parameters()) {
    pool->model.nominal =
        truth + options.nominal_error_scale * (model.nominal - truth);
  }
  JointLattice lattice;
  if (!MakeLatticePool(model, cell ? cell->checker.get() : nullptr,
                       options.levels, MeasurementType::kPosition, "--",
                       &lattice, &pool->report, &pool->message)) {
    return false;
  }
  pool->joints = lattice.AllJointValues();
  if (cell == nullptr) return true;
  PoolFilterSummary& feasibility = pool->feasibility;
  PoolFilterOptions o;
  o.num_threads = options.loop.num_threads;
  if (options.stage_progress)
    o.progress = options.stage_progress("cell checks");
  const bool filtered =
      FilterPool(*cell->checker, pool->joints, o, &feasibility);
  o.progress = nullptr;  // the stage ends here
  if (!filtered) {
    pool->message = "--cell: " + feasibility.message;
    return false;
  }
  // As activecal_select: one line with the counts per reason.
  if (feasibility.num_feasible() == 0) {
    pool->message = "--cell: no pose of the pool is left: " +
                    FeasibleNote(*cell->checker, feasibility);
    return false;
  }
  if (feasibility.num_feasible() < options.loop.first_batch) {
    pool->message =
        "--first_batch=" + std::to_string(options.loop.first_batch) +
        ": the feasible pool has only " +
        FeasibleNote(*cell->checker, feasibility);
    return false;
  }
  pool->report += "  " + feasibility.BriefReport(*cell->checker);
  return true;
}

bool ReduceForActivePool(ParameterSet set, const CellSetup* cell,
                         ActivePool* pool) {
  RobotModel* model = &pool->model;
  // Each pose measuring the targets it sees when they are the markers.
  // Several markers otherwise: each pose measures every one (the driver is
  // asked for all), so the reduction counts every marker's rows (marker
  // 0's alone held the others' offsets fixed).
  const bool masked = cell && CellTargetsAreMarkers(*cell->checker, *model);
  const Eigen::MatrixXd joints =
      cell ? pool->feasibility.FeasibleJoints(pool->joints) : pool->joints;
  std::vector<uint32_t> every_marker;
  if (!masked && model->num_markers() > 1) {
    every_marker.assign(joints.rows(), EveryMarkerMask(*model));
  }
  PoolReduction reduction;
  if (!ReduceModelForPool(set, joints,
                          masked ? &pool->feasibility.targets_seen
                          : every_marker.empty() ? nullptr
                                                 : &every_marker,
                          model, &pool->report, &pool->message, &reduction)) {
    return false;
  }
  // At the exact nominal the UR10e's first batch was singular for the kept
  // parameters ("round 0: no restart produced a non-singular design").
  model->nominal = reduction.point;
  return true;
}

bool RunActiveCalibration(const RobotModel& model, const Eigen::VectorXd& truth,
                          const Eigen::MatrixXd& joints, const CellSetup* cell,
                          const PoolFilterSummary* feasibility,
                          const ActiveCalibrationOptions& o,
                          ActiveCalibrationSummary* summary) {
  *summary = ActiveCalibrationSummary();
  FILE* out = o.log_to_stdout ? stdout : nullptr;
  const bool with_cell = cell != nullptr && feasibility != nullptr;
  const bool simulate = o.driver.empty();
  const bool truth_known = truth.size() == model.num_parameters();
  ActiveLoopOptions options = o.loop;
  options.true_parameters = truth_known ? truth : Eigen::VectorXd();
  if (with_cell) {
    options.pool_filter = [feasibility](int64_t i) {
      return feasibility->verdicts[i].feasible();
    };
    // Several targets as the markers: each pose plans and measures those
    // it sees.
    if (CellTargetsAreMarkers(*cell->checker, model)) {
      for (const PoseVerdict& v : feasibility->verdicts) {
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
  if (simulate && !truth_known) {
    summary->message =
        "no true parameters to simulate from (or measure with a driver)";
    return false;
  }
  if (!options.IsValid(&error)) {
    // The options' names are the flags' but for sigma_m (--noise_m).
    if (error.rfind("sigma_m", 0) == 0) error.replace(0, 7, "noise_m");
    summary->message = "--" + error;
    return false;
  }

  // The session: what its results depend on must not change between runs.
  std::unique_ptr<ActiveSession> session;
  if (!o.session_dir.empty()) {
    std::string cell_text = o.cell_text;
    if (with_cell && cell_text.empty()) {
      std::ifstream in(o.cell_path, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      cell_text = text.str();
    }
    RobotFileOptions robot_text;
    robot_text.true_parameters = options.true_parameters;
    // The cell decides which poses may be designed: "none", or its file
    // by content. First: its targets are the robot's markers, so a change
    // of the targets alone changes robot_hash too, and the cell is what to
    // name.
    SessionIdentity identity = {
        {"cell", with_cell ? o.cell_path + " (hash " +
                                 std::to_string(Fnv1a(cell_text)) + ")"
                           : "none"},
        {"robot", model.name},
        {"robot_hash", std::to_string(Fnv1a(
                           RobotFileText(model, model.nominal, robot_text)))},
        {"measured_by", simulate ? "simulation" : "driver"},
        {"levels", std::to_string(o.levels)},
        {"pool_poses", std::to_string(joints.rows())},
        {"first_batch", std::to_string(options.first_batch)},
        {"batch_size", std::to_string(options.batch_size)},
        {"noise_m", Text(options.sigma_m)},
        {"restarts", std::to_string(o.restarts)},
        {"seed", std::to_string(options.seed)},
        {"nominal_error_scale", Text(o.nominal_error_scale)},
    };
    identity.push_back({"order", o.order_shortest ? "shortest" : "none"});
    if (!ActiveSession::Open(o.session_dir, o.resume, model, identity, &session,
                             &summary->message)) {
      return false;
    }
    for (const std::string& n : session->notes()) {
      Print(out, "note: %s\n", n.c_str());
    }
  }
  BatchDesigner designer(model, joints, with_cell ? cell : nullptr, o);

  // The measurers: the cell (or the simulation), the session's log around
  // it, the per-measurement lines around that.
  std::unique_ptr<DriverClient> client;
  std::unique_ptr<Measurer> source;
  if (simulate) {
    source.reset(
        new SimulatedMeasurer(model, truth, options.sigma_m, options.seed));
  } else {
    DriverClientOptions driver_options;
    driver_options.driver = o.driver;
    driver_options.timeout_s = o.driver_timeout_s;
    DriverHello hello;
    for (const Link& link : model.links) hello.joint_names.push_back(link.name);
    hello.markers = model.num_markers();
    hello.robot = model.name;
    if (!driver_options.IsValid(&error)) {
      summary->message = "--" + error;
      return false;
    }
    if (!DriverClient::Start(driver_options, hello, &client, &error)) {
      summary->message =
          error + (session ? " (the session in " + o.session_dir +
                                 " is kept: continue it with --resume)"
                           : "");
      return false;
    }
    if (o.verbose) {
      Print(out, "%s: %s\n", client->name().c_str(),
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
  if (o.verbose && out) {
    verbose.reset(new VerboseMeasurer(measurer, logged.get()));
    measurer = verbose.get();
  }

  Print(out, "activecal active loop: robot '%s', %lld pool poses, %s\n",
        model.name.c_str(), static_cast<long long>(joints.rows()),
        simulate ? "simulated from the robot file's true values"
                 : ("measured by " + client->name() +
                    (truth_known ? " (true error from the robot file's true "
                                   "values)"
                                 : ""))
                       .c_str());
  if (truth_known) {
    Print(out,
          "  nominal model: true task RMS %.6g m (--nominal_error_scale %g)\n",
          TaskRmsDistance(model, model.nominal, truth, joints),
          o.nominal_error_scale);
  }
  Print(out, "  %-6s %-6s %-14s %-14s %-14s %-14s %-14s %-9s %s\n", "round",
        "poses", "predicted_m", "true_m", "change_m", "change_max",
        "resid_sigma_m", "excluded", "seconds");
  const ActiveLoopState* resume = session ? session->resume_state() : nullptr;
  if (resume != nullptr) {
    for (size_t r = 0; r < resume->rounds.size(); ++r) {
      PrintRound(out, static_cast<int>(r), resume->rounds[r], 0.0,
                 options.sigma_m, &summary->warnings, o.warning);
    }
  }
  options.round_callback = [&](const ActiveLoopState& state, std::string* why) {
    PrintRound(out, state.round - 1, state.rounds.back(), SecondsSince(o.start),
               options.sigma_m, &summary->warnings, o.warning);
    // On stderr, flushed (stdout may sit in a pipe's buffer): a round can
    // take seconds (a measurement per pose, a selection, a fit).
    const ActiveRound& a = state.rounds.back();
    char line[160];
    std::snprintf(line, sizeof(line),
                  "round %d done: %d poses, predicted task RMS %.3g m (%.1f s)",
                  state.round - 1, a.num_poses, a.predicted_task_rms_m,
                  SecondsSince(o.start));
    if (o.progress) o.progress(line);
    return !session || session->SaveState(state, why);
  };
  ActiveLoopSummary& loop = summary->loop;
  const bool ok = RunActiveLoop(model, joints, joints, options,
                                designer.Selector(), measurer, resume, &loop);
  summary->loop_ok = ok;
  const std::string closing = client ? client->Close() : "";
  if (!closing.empty()) Print(out, "note: %s\n", closing.c_str());
  const std::string kept =
      session ? " (the session in " + o.session_dir +
                    " keeps every answer: continue it with --resume)"
              : "";
  if (!ok) summary->message = loop.message + kept;
  if (!ok && loop.rounds.empty()) return false;
  Print(out, "activecal active loop: %s\n  %s\n",
        TerminationTypeToString(loop.termination_type), loop.message.c_str());
  if (out) std::fflush(out);
  nlohmann::json& j = summary->report;
  j["termination_type"] = TerminationTypeToString(loop.termination_type);
  j["message"] = loop.message;
  j["robot"] = model.name;
  j["levels"] = o.levels;
  j["noise_m"] = options.sigma_m;
  j["target_rms_m"] = options.target_rms_m;
  j["seed"] = options.seed;
  j["nominal_error_scale"] = o.nominal_error_scale;
  j["nominal_true_task_rms_m"] = Finite(loop.nominal_true_task_rms_m);
  j["measured_by"] = simulate ? "simulation" : "driver";
  j["rounds"] = nlohmann::json::array();
  for (const ActiveRound& a : loop.rounds) j["rounds"].push_back(RoundJson(a));
  j["measured_pose_indices"] = loop.measured;
  if (o.order_shortest) designer.Report(out, model, &j);
  if (with_cell) {
    // The preprocess, and the targets each measured pose sees.
    j["cell"] = o.cell_path;
    j.update(CellPoolJson(cell->cell, *feasibility));
    if (!cell->cell.targets.empty()) {
      nlohmann::json seen = nlohmann::json::array();
      for (int64_t i : loop.measured) {
        seen.push_back(
            TargetsSeenJson(cell->cell, feasibility->verdicts[i].targets_seen));
      }
      j["targets_seen"] = seen;
    }
  }
  j["excluded_poses"] = nlohmann::json::array();
  for (const ExcludedPose& e : loop.excluded) {
    j["excluded_poses"].push_back({{"pose_index", e.pose},
                                   {"round", e.round},
                                   {"status", e.status},
                                   {"message", e.message}});
  }

  if (o.compare && !loop.measured.empty()) {
    const int n = static_cast<int>(loop.measured.size());
    CandidatePoolOptions pool_options;
    pool_options.num_threads = options.num_threads;
    CandidatePool pool;
    CandidatePoolSummary pool_summary;
    if (!BuildCandidatePool(model, model.nominal, joints, pool_options, &pool,
                            &pool_summary)) {
      summary->message = "pool at nominal: " + pool_summary.message;
      return false;
    }
    const Eigen::MatrixXd W = TaskMatrix(pool);
    std::vector<std::pair<std::string, std::vector<int64_t>>> designs(3);
    designs[0].first = "d_optimal_at_nominal";
    designs[1].first = "task_optimal_at_nominal";
    designs[2].first = "random";
    if (!designer.DOptimal(pool, n, {}, &designs[0].second, &error) ||
        !designer.TaskOptimal(pool, W, RowMatrixXd(0, pool.num_parameters()),
                              {}, n, &designs[1].second, &error)) {
      summary->message = "one-shot design: " + error;
      return false;
    }
    Random random(Random::StreamSeed(options.seed, 1000));
    designs[2].second = random.SampleWithoutReplacement(pool.size(), n);
    Print(out, "  one-shot designs of %d poses at the nominal values:\n", n);
    Print(out, "  %-26s %-14s %s\n", "design", "predicted_m", "true_m");
    j["one_shot"] = nlohmann::json::object();
    for (const auto& [name, design] : designs) {
      ActiveRound r;
      if (!EvaluateOneShot(model, truth, joints, joints, design, options, &r,
                           &error)) {
        Print(out, "  %-26s failed: %s\n", name.c_str(), error.c_str());
        j["one_shot"][name] = {{"error", error}};
        continue;
      }
      Print(out, "  %-26s %-14.6g %.6g\n", name.c_str(), r.predicted_task_rms_m,
            r.true_task_rms_m);
      j["one_shot"][name] = RoundJson(r);
    }
  }
  PoseList& poses = summary->measured_poses;
  poses.joints.resize(loop.measured.size(), joints.cols());
  for (size_t k = 0; k < loop.measured.size(); ++k) {
    poses.joints.row(k) = joints.row(loop.measured[k]);
  }
  poses.pose_indices = loop.measured;
  return true;
}

}  // namespace activecal
