// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/select_workflow.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <functional>
#include <utility>

#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/pool_builder.h"
#include "activecal/calibration/pool_reduction.h"
#include "activecal/cell/measurable_pool.h"
#include "activecal/core/enum_name_list.h"
#include "activecal/core/joint_sampling.h"
#include "activecal/core/lattice.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/task_criterion.h"
#include "seconds_since.h"

namespace activecal {
namespace {

// Appends printf-formatted text to *out.
void Append(std::string* out, const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  if (n > 0) {
    std::string text(static_cast<size_t>(n) + 1, '\0');
    std::vsnprintf(&text[0], text.size(), format, args);
    text.resize(static_cast<size_t>(n));
    *out += text;
  }
  va_end(args);
}

std::string Number(double x, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", digits, x);
  return buffer;
}

using internal::SecondsSince;

// The progress callback of one stage (none without options.progress).
ProgressCallback Stage(const SelectOptions& options, const std::string& name) {
  return options.progress ? options.progress(name) : ProgressCallback();
}

bool IsDrawn(SelectPool pool) {
  return pool == SelectPool::kSobol || pool == SelectPool::kRandom;
}

// An option as options.option_spelling names it: "--<name>" (a flag) or
// "<name>" (a Python keyword).
std::string Flag(const SelectOptions& options, const std::string& name) {
  return (options.option_spelling == OptionSpelling::kFlags ? "--" : "") + name;
}

// A flag's text or, spelt as keywords, the keyword's.
std::string Spelt(const SelectOptions& options, const std::string& flag,
                  const std::string& keyword) {
  return options.option_spelling == OptionSpelling::kFlags ? flag : keyword;
}

}  // namespace

constexpr const char* kSelectPoolNames[] = {"lattice",    "sobol", "random",
                                            "measurable", "csv",   "poses"};

const char* SelectPoolToString(SelectPool pool) {
  return EnumToString(kSelectPoolNames, pool);
}

bool StringToSelectPool(const std::string& text, SelectPool* pool) {
  SelectPool named;
  // A CSV pool is named by its path, a pool in memory is given.
  if (!StringToEnum(kSelectPoolNames, text, &named) ||
      named == SelectPool::kCsv || named == SelectPool::kPoses) {
    return false;
  }
  *pool = named;
  return true;
}

std::string SelectSummary::ResultLine(const std::string& program_name) const {
  const SelectionSummary& s = design.selection;
  char result[256];
  std::snprintf(result, sizeof(result),
                "%s: %zu poses of %lld (%s), log10 det %.4f",
                program_name.c_str(), s.design.size(),
                static_cast<long long>(pool_joints.rows()), s.algorithm.c_str(),
                s.log10_det());
  std::string line = result;
  if (std::isfinite(s.efficiency_lower_bound)) {
    std::snprintf(result, sizeof(result), ", D-efficiency >= %.4f",
                  s.efficiency_lower_bound);
    line += result;
  }
  return line;
}

nlohmann::json SelectionJson(const SelectionSummary& summary,
                             const Eigen::MatrixXd& pool_joints,
                             const std::vector<int64_t>& labels) {
  nlohmann::json j;
  j["algorithm"] = summary.algorithm;
  j["pool_size"] = summary.pool_size;
  j["num_parameters"] = summary.num_parameters;
  std::vector<int64_t> indices;
  nlohmann::json angles = nlohmann::json::array();
  for (int64_t i : summary.design) {
    indices.push_back(labels.empty() ? i : labels[i]);
    const Eigen::VectorXd q = pool_joints.row(i).transpose();
    angles.push_back(std::vector<double>(q.data(), q.data() + q.size()));
  }
  j["pose_indices"] = indices;
  j["joint_angles_rad"] = angles;
  j["log10_det"] = summary.log10_det();
  j["oi"] = OiFromLogDet(summary.log_det, summary.num_parameters);
  std::vector<double> history;
  for (const SelectionStep& s : summary.history) {
    history.push_back(s.log_det / std::log(10.0));
  }
  j["history_log10_det"] = history;
  return j;
}

bool SelectOptions::IsValid(const RobotModel& model, std::string* error) const {
  const bool measurable = pool == SelectPool::kMeasurable;
  const bool drawn = IsDrawn(pool) || measurable;
  const std::string name = SelectPoolToString(pool);
  std::string e;
  if (drawn && !pool_csv.empty()) {
    e = "--pool=" + name + " and --pool_csv: choose one";
  } else if (measurable && cell == nullptr) {
    e = "--pool=measurable needs --cell (the device and the targets to "
        "sample for)";
  } else if (!drawn && pool_size) {
    // A lattice (or a CSV) ignored it: --pool_size=100000000000 exited 0
    // (issue 26).
    e = "--pool_size sizes a --pool=sobol, random or measurable pool; " +
        std::string(pool == SelectPool::kLattice && pool_csv.empty()
                        ? "the lattice has --levels poses per joint"
                        : "--pool_csv has its rows") +
        ": give --pool or drop --pool_size";
  } else if (pool != SelectPool::kPoses && (pool_poses.joints.size() > 0 ||
                                            !pool_poses.pose_indices.empty())) {
    e = "pool_poses give the poses of pool=poses, got pool=" + name;
  } else if (pool == SelectPool::kPoses &&
             pool_poses.joints.cols() != model.num_joints()) {
    e = "pool: expected " + std::to_string(model.num_joints()) +
        " joint values per pose, got " +
        std::to_string(pool_poses.joints.cols());
  } else if (pool == SelectPool::kPoses && !pool_poses.pose_indices.empty() &&
             static_cast<int64_t>(pool_poses.pose_indices.size()) !=
                 pool_poses.joints.rows()) {
    e = "pool_indices: expected " + std::to_string(pool_poses.joints.rows()) +
        " values (one per pool pose), got " +
        std::to_string(pool_poses.pose_indices.size());
  } else if (pool == SelectPool::kPoses &&
             !CheckPoseIndices(pool_poses.pose_indices, /*unique=*/true, &e)) {
    e = "pool_indices: " + e;
  } else if (drawn &&
             !CheckSelectionPoolSize(pool_size.value_or(defaults::kPoolSize),
                                     model, type, &e)) {
    // Refused before the pool is listed (it was a std::bad_alloc).
    e = Flag(*this, "pool_size: ") + e;
  } else if (!measurable && max_draws) {
    e = "--max_draws caps the draws of --pool=measurable, got --pool=" + name;
  } else if (max_draws.value_or(0) < 0) {
    e = "--max_draws must be >= 0, got " + std::to_string(*max_draws);
  }
  if (!e.empty() && error) *error = e;
  return e.empty();
}

bool Select(const RobotModel& input_model, const SelectOptions& options,
            SelectSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  *summary = SelectSummary();
  SelectSummary& out = *summary;
  std::string& report = out.report;
  auto fail = [&](std::string message) {
    out.termination_type = TerminationType::kFailure;
    out.message = std::move(message);
    out.total_seconds = SecondsSince(start);
    return false;
  };
  RobotModel model = input_model;
  const CellSetup no_cell;
  const bool with_cell = options.cell != nullptr;
  const CellSetup& cell = with_cell ? *options.cell : no_cell;
  const SelectDesignOptions& design_options = options.design;
  const bool with_target = design_options.target_rms_m.has_value();
  const int num_poses = design_options.num_poses;
  const uint64_t seed = design_options.seed;
  const int num_threads = design_options.num_threads;
  const double noise_m = design_options.noise_m;
  const SelectPool pool_kind =
      options.pool == SelectPool::kLattice && !options.pool_csv.empty()
          ? SelectPool::kCsv
          : options.pool;
  const bool measurable = pool_kind == SelectPool::kMeasurable;
  const bool sampled = IsDrawn(pool_kind);
  const bool from_lattice = pool_kind == SelectPool::kLattice;
  const std::string pool_name = SelectPoolToString(pool_kind);
  const int64_t pool_size = options.pool_size.value_or(defaults::kPoolSize);
  {
    std::string error;
    if (!options.IsValid(input_model, &error)) return fail(error);
  }

  // The candidate poses.
  Eigen::MatrixXd& pool_joints = out.pool_joints;
  std::vector<int64_t>& labels = out.labels;
  JointLattice lattice;
  MeasurablePoolSummary measurable_summary;
  if (measurable) {
    MeasurablePoolOptions o;
    o.num_poses = pool_size;
    o.max_draws = options.max_draws.value_or(0);
    o.seed = seed;
    o.num_threads = num_threads;
    o.progress = Stage(options, "measurable poses");
    const bool sampled_ok =
        SampleMeasurablePool(*cell.checker, o, &measurable_summary);
    o.progress = nullptr;  // the stage ends here
    if (!sampled_ok) {
      return fail("--pool=measurable: " + measurable_summary.message);
    }
    // Too few poses for the design (or none): one line with the counts.
    const int64_t needed = with_target ? 1 : std::max(1, num_poses);
    if (measurable_summary.joints.rows() < needed) {
      return fail("--pool=measurable: " +
                  measurable_summary.FailureText(*cell.checker) +
                  (measurable_summary.gave_up
                       ? ""
                       : " (raise --max_draws, or fix the cell)"));
    }
    Append(&report, "  %s", measurable_summary.BriefReport().c_str());
    if (!measurable_summary.message.empty()) {
      Append(&report, "  --pool=measurable: note: %s\n",
             measurable_summary.message.c_str());
    }
    pool_joints = measurable_summary.joints;
  } else if (from_lattice) {
    // With a cell the lattice spans the ranges inside the joint margins.
    std::string error;
    if (!MakeLatticePool(model, with_cell ? cell.checker.get() : nullptr,
                         options.levels, options.type, Flag(options, ""),
                         &lattice, &report, &error)) {
      return fail(error);
    }
    out.lattice_notes = lattice.OneTurnNotes(model);
    pool_joints = lattice.AllJointValues();
  } else if (sampled) {
    std::string error;
    if (!SampleJointValues(
            with_cell ? WithinJointMargins(*cell.checker, model) : model,
            pool_kind == SelectPool::kRandom ? JointSampling::kRandom
                                             : JointSampling::kSobol,
            pool_size, seed, &pool_joints, &error)) {
      return fail(Flag(options, "pool=") + pool_name + ": " + error);
    }
  } else if (pool_kind == SelectPool::kPoses) {
    pool_joints = options.pool_poses.joints;
    labels = options.pool_poses.pose_indices;
  } else {
    PoseList list;
    std::string error;
    if (!ReadPosesCsv(options.pool_csv, model, /*reject_duplicates=*/true,
                      &list, &error)) {
      return fail("--pool_csv: " + error);
    }
    pool_joints = std::move(list.joints);
    labels = std::move(list.pose_indices);
  }
  if (!with_target && (num_poses <= 0 || num_poses > pool_joints.rows())) {
    return fail(Flag(options, "num_poses") + " must be in [1, " +
                std::to_string(pool_joints.rows()) + "] (the pool size), got " +
                std::to_string(num_poses));
  }
  // How the pool is stored: single precision where the double blocks would
  // not fit the budget (and the algorithm reads such pools).
  SelectionPoolOptions pool_options;
  pool_options.reads_float =
      ReadsFloatPool(design_options.algorithm, design_options.criterion);
  pool_options.storage = options.storage;
  pool_options.max_double_pool_mib = options.max_double_pool_mib;
  // The parameters the design is for: a named set is reduced to what the
  // pool separates, and the pool is linearised at the generic point of that
  // analysis.
  pool_options.parameter_set = options.parameter_set;
  pool_options.type = options.type;
  pool_options.rotation_weight_m_per_rad = options.rotation_weight_m_per_rad;
  pool_options.auto_fix = options.auto_fix;
  pool_options.num_threads = num_threads;
  // The preprocess: the cell's checks of every pose.
  PoolFilterSummary& feasibility = out.feasibility;
  if (with_cell) {
    pool_options.filter = [&](const Eigen::MatrixXd& joints,
                              std::vector<int64_t>* kept, std::string* note) {
      PoolFilterOptions o;
      o.num_threads = num_threads;
      o.progress = Stage(options, "cell checks");
      return CellPoolFilter(*cell.checker, o, &feasibility)(joints, kept, note);
    };
    // Several targets as the markers: each pose's rows are those seen.
    if (CellTargetsAreMarkers(*cell.checker, model)) {
      pool_options.kept_marker_masks = &feasibility.targets_seen;
    }
  }
  CandidatePool pool;
  SelectionPoolSummary& pool_summary = out.pool;
  pool_options.progress = Stage(options, "Jacobians of the pool poses");
  const bool pool_built = BuildSelectionPool(&model, pool_joints, pool_options,
                                             &pool, &pool_summary);
  pool_options.progress = nullptr;  // the stage ends here
  if (pool_summary.filtered && !pool_summary.kept.empty()) {
    Append(&report, "  %s", feasibility.BriefReport(*cell.checker).c_str());
  }
  if (pool_summary.filtered && pool_summary.kept.empty()) {
    return fail(Flag(options, "cell: ") + pool_summary.message);
  }
  if (pool_summary.reduction_failed) {
    return fail(Flag(options, pool_summary.message));
  }
  if (pool_summary.termination_type == TerminationType::kUserFailure) {
    return fail(pool_summary.message);
  }
  report += HeldFixedLines(pool_options.parameter_set, pool_summary.dropped);
  if (pool_summary.single_precision) {
    Append(&report,
           "  pool stored in single precision: %.4g MiB instead of %.4g MiB "
           "(design log det and certificate computed in double)\n",
           pool_summary.double_mib / 2, pool_summary.double_mib);
  }
  if (!pool_built) {
    const IdentifiabilityReport& r = pool_summary.pool.identifiability;
    if (!r.identifiable() && r.num_free > 0) {
      const std::string what =
          pool_summary.filtered
              ? "the feasible pool (" + pool_summary.filter_note + ")"
              : "the pool";
      if (options.auto_fix || r.num_equations < r.num_free) {
        return fail(what + ": " + r.Message());
      }
      return fail(what + ": " + r.Message() +
                  ". Fix them in the robot file (remove them from 'free') or "
                  "pass " +
                  Spelt(options, "--auto_fix", "auto_fix=True"));
    }
    return fail(pool_summary.message);
  }
  {
    // The parameters the pool cannot identify, held (--auto_fix).
    const std::vector<std::string> fixed = HeldNames(pool_summary.pool.held);
    if (!fixed.empty()) {
      std::string list;
      for (const std::string& f : fixed) list += (list.empty() ? "" : ", ") + f;
      report +=
          options.program_name + ": --auto_fix: the pool cannot identify " +
          std::to_string(fixed.size()) + " of " +
          std::to_string(pool_summary.pool.num_free_before) +
          " free parameters; holding them at their nominal values: " + list +
          "\n";
    }
  }
  const double jacobian_seconds = pool_summary.pool.jacobian_seconds;
  // From here on the pool is the feasible one: its rows, labelled by their
  // place in the pool drawn (or their pose_index).
  const int64_t drawn_pool_size = pool_joints.rows();
  if (pool_summary.filtered && options.rejected_csv) {
    out.rejected_csv =
        RejectedCsvText(*cell.checker, pool_joints, labels, feasibility);
  }
  if (pool_summary.filtered) {
    std::vector<int64_t> kept_labels;
    for (int64_t row : pool_summary.kept) {
      kept_labels.push_back(labels.empty() ? row : labels[row]);
    }
    pool_joints = feasibility.FeasibleJoints(pool_joints);
    labels = std::move(kept_labels);
    if (!with_target && num_poses > pool_joints.rows()) {
      return fail(Flag(options, "num_poses=") + std::to_string(num_poses) +
                  ": the feasible pool has only " + pool_summary.filter_note);
    }
  }
  const std::vector<std::string> auto_fixed = pool_summary.HeldFixed();

  // The design's options.
  SelectDesignOptions design = design_options;
  const bool task = design.task();
  {
    std::string error;
    if (!design.IsValid(&error)) {
      // The options' names are the flags'.
      const std::string task_prefix = "criterion=task_rms: ";
      if (options.option_spelling == OptionSpelling::kKeywords) {
        return fail(error);
      }
      return fail(error.rfind(task_prefix, 0) == 0
                      ? "--" + task_prefix + "--" +
                            error.substr(task_prefix.size())
                      : "--" + error);
    }
  }
  if ((!options.measured_csv.empty() || !options.measured.empty()) && !task) {
    return fail(Spelt(options, "--measured_csv needs --criterion=task_rms",
                      "measured needs criterion='task_rms'") +
                " (the D-criterion algorithms take no prior information)");
  }

  // The task: position rows at the task poses (the pool by default).
  Eigen::MatrixXd W;
  int64_t num_task_poses = pool_joints.rows();
  {
    Eigen::MatrixXd task_joints;
    if (options.task_joints.rows() > 0) {
      task_joints = options.task_joints;
      num_task_poses = task_joints.rows();
    } else if (!options.task_poses_csv.empty()) {
      PoseList list;
      std::string error;
      if (!ReadPosesCsv(options.task_poses_csv, model,
                        /*reject_duplicates=*/false, &list, &error)) {
        return fail("--task_poses_csv: " + error);
      }
      task_joints = std::move(list.joints);
      num_task_poses = task_joints.rows();
    }
    CandidatePool task_pool;
    bool task_is_pool = false;
    std::string error;
    if (!BuildTaskPool(model, pool_joints, task_joints, pool_options,
                       &task_pool, &task_is_pool, &error)) {
      return fail(Spelt(options, "--task_poses_csv: ", "task_poses: ") + error);
    }
    W = TaskMatrix(task_is_pool ? pool : task_pool);
  }
  // The poses already measured, whitened to noise_m.
  RowMatrixXd prior(0, pool.num_parameters());
  int num_measured = 0;
  if (!options.measured_csv.empty() || !options.measured.empty()) {
    std::vector<Measurement> measured = options.measured;
    std::string error;
    if (!options.measured_csv.empty()) {
      std::vector<Measurement> read;
      MeasurementsCsvOptions o;
      o.column_map = options.column_map;
      if (!ReadMeasurementsCsv(options.measured_csv, model, o, &read, nullptr,
                               &error)) {
        return fail("--measured_csv: " + error);
      }
      measured.insert(measured.end(), read.begin(), read.end());
    }
    if (!MeasuredInformationRows(model, model.nominal, measured,
                                 options.rotation_weight_m_per_rad, noise_m,
                                 &prior, &error)) {
      return fail(Spelt(options, "--measured_csv: ", "measured: ") + error);
    }
    num_measured = static_cast<int>(measured.size());
  }
  const bool with_prior = prior.rows() > 0;
  // Several targets as the markers: a pose gives the rows of the targets it
  // sees only, so the pool's block rows overstate what num_poses poses
  // give. The most the best num_poses feasible poses can give, up front
  // as for one target (the exchange algorithms would otherwise return a
  // design of more poses, greedy fail on the first singular step).
  if (pool_options.kept_marker_masks != nullptr && !with_target &&
      model.num_markers() > 0 && num_poses > 0) {
    const int rows_per_target = pool.block_rows() / model.num_markers();
    std::vector<int> rows;
    for (uint32_t mask : feasibility.targets_seen) {
      rows.push_back(rows_per_target * __builtin_popcount(mask));
    }
    std::sort(rows.begin(), rows.end(), std::greater<int>());
    int64_t equations = prior.rows();
    for (size_t k = 0; k < rows.size() && k < static_cast<size_t>(num_poses);
         ++k) {
      equations += rows[k];
    }
    if (equations < pool.num_parameters()) {
      const int most = rows.empty() ? 0 : rows[0] / rows_per_target;
      return fail(std::to_string(num_poses) + " poses give " +
                  std::to_string(equations) + " equations, fewer than the " +
                  std::to_string(pool.num_parameters()) +
                  " parameters: every such design is singular (a feasible "
                  "pose sees at most " +
                  std::to_string(most) + " of the " +
                  std::to_string(model.num_markers()) + " targets" +
                  (with_prior
                       ? "; with " + Spelt(options, "--measured_csv's rows",
                                           "the measured rows")
                       : "") +
                  ")");
    }
  }

  SelectDesignSummary& select = out.design;
  {
    design.approximate_progress = Stage(options, "approximate design, rounds");
    design.restarts_progress =
        Stage(options, std::string(DesignAlgorithmToString(design.algorithm)) +
                           " restarts");
    const bool designed = SelectDesign(pool, W, prior, design, &select);
    design.approximate_progress = nullptr;  // the stages end here
    design.restarts_progress = nullptr;
    if (!designed) {
      // The target's failures name the flag.
      return fail(select.message.rfind("target_rms_m: ", 0) == 0 &&
                          options.option_spelling == OptionSpelling::kFlags
                      ? "--" + select.message
                      : select.message);
    }
  }
  // The D-efficiency lost to the cell: the design's det against that of the
  // same design problem on an unconstrained pool of the same size.
  nlohmann::json cell_efficiency_json;
  std::string cell_efficiency_line;  // printed after the design's report
  const std::string free_pool_name = sampled ? pool_name : "sobol";
  if (with_cell && options.cell_efficiency && !task && !with_target &&
      !with_prior) {
    const JointSampling free_sampling = pool_kind == SelectPool::kRandom
                                            ? JointSampling::kRandom
                                            : JointSampling::kSobol;
    Eigen::MatrixXd free_joints;
    std::string error;
    if (!SampleJointValues(model, free_sampling, pool_joints.rows(), seed,
                           &free_joints, &error)) {
      return fail("--cell_efficiency: the unconstrained pool: " + error);
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
    SelectDesignOptions free_design = design;
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
      return fail("--cell_efficiency: the unconstrained design: " +
                  free_select.message);
    } else {
      const int p = static_cast<int>(pool.num_parameters());
      const double log10_cell = select.selection.log10_det();
      const double log10_free = free_select.selection.log10_det();
      const double efficiency = std::pow(10.0, (log10_cell - log10_free) / p);
      cell_efficiency_json = {{"d_efficiency", efficiency},
                              {"log10_det_cell", log10_cell},
                              {"log10_det_unconstrained", log10_free},
                              {"num_parameters", p},
                              {"unconstrained_pool", free_pool_name},
                              {"unconstrained_pool_size", free_joints.rows()}};
      Append(&cell_efficiency_line,
             "  D-efficiency lost to the cell: %.4f = 10^((%.4f - %.4f) / %d) "
             "against an unconstrained %s pool of %lld poses\n",
             efficiency, log10_cell, log10_free, p, free_pool_name.c_str(),
             static_cast<long long>(free_joints.rows()));
    }
  }
  // The order to run the design in.
  TourSummary tour;
  const bool ordered = options.order_shortest;
  const std::vector<double> velocity_limits =
      ordered ? RobotVelocityLimits(options.robot_path, options.chain, model)
              : std::vector<double>();
  if (ordered) {
    const std::vector<int64_t> chosen = select.selection.design;
    Eigen::MatrixXd design_joints(chosen.size(), pool_joints.cols());
    for (size_t k = 0; k < chosen.size(); ++k) {
      design_joints.row(k) = pool_joints.row(chosen[k]);
    }
    TourOptions o;
    o.velocity_limits = velocity_limits;
    o.resolution_rad = options.order_resolution_deg * M_PI / 180.0;
    o.resolution_m = options.order_resolution_deg * 1e-3;
    o.check_moves = with_cell;
    if (!OrderTour(with_cell ? cell.checker.get() : nullptr, design_joints, o,
                   &tour)) {
      return fail(Spelt(options, "--order=shortest: ", "order='shortest': ") +
                  tour.message);
    }
    for (size_t k = 0; k < chosen.size(); ++k) {
      select.selection.design[k] = chosen[tour.order[k]];
    }
  }

  // The report.
  const SelectionSummary& s = select.selection;
  const TargetSizeSummary& target = select.target;
  const ApproximateDesignSummary& approx = select.approx;
  const TaskApproximateSummary& task_approx = select.task_approx;
  report += select.BriefReport();
  if (select.with_approx && pool.single_precision()) {
    report +=
        "  (the approximate design's bound is over the stored float blocks; "
        "the design's log det and certificate are over the double ones)\n";
  }
  Append(&report,
         "  predicted task RMS %.6g m over %lld task poses (sigma %g m",
         select.predicted_task_rms_m, static_cast<long long>(num_task_poses),
         noise_m);
  if (with_prior) Append(&report, ", %d measured poses counted", num_measured);
  report += ")\n";
  if (task && with_prior && design.certificate) {
    report += "  no certificate: its bounds assume no measured poses\n";
  }
  if (with_target) {
    Append(&report, "  target %g m: %s\n  %-10s %s\n", *design.target_rms_m,
           target.message.c_str(), "num_poses", "predicted_task_rms_m");
    for (size_t k = 0; k < target.sizes.size(); ++k) {
      Append(&report, "  %-10d %.6g\n", target.sizes[k],
             target.rms_by_size_m[k]);
    }
    out.curve_csv = "num_poses,predicted_task_rms_m\n";
    for (size_t k = 0; k < target.sizes.size(); ++k) {
      out.curve_csv += std::to_string(target.sizes[k]) + "," +
                       Number(target.rms_by_size_m[k], 17) + "\n";
    }
  }
  Append(&report, "  Jacobians of %lld poses: %.3f s\n",
         static_cast<long long>(pool.size()), jacobian_seconds);
  report += cell_efficiency_line;
  const nlohmann::json moves_checked =
      options.option_spelling == OptionSpelling::kFlags
          ? MovesCheckedJson(with_cell, cell)
          : MovesCheckedJson(with_cell, cell, "no cell=");
  const std::string velocity_note =
      ordered ? AssumedVelocityNote(model, velocity_limits) : std::string();
  if (ordered) {
    report +=
        "  " + tour.BriefReport(
                   moves_checked["moves_checked"].get<bool>()
                       ? std::string()
                       : moves_checked["moves_not_checked"].get<std::string>());
    if (!velocity_note.empty()) {
      report += "  --order=shortest: note: " + velocity_note + "\n";
    }
    for (size_t b = 0; b < tour.blocked_moves.size(); ++b) {
      Append(&report,
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
  Append(&report, "  %-6s %-8s %s\n", "#", "index",
         from_lattice    ? "levels (joint 1..n)"
         : any_prismatic ? "joints (deg; prismatic mm)"
                         : "joints (deg)");
  for (size_t k = 0; k < s.design.size(); ++k) {
    const int64_t i = s.design[k];
    Append(&report, "  %-6zu %-8lld", k,
           static_cast<long long>(labels.empty() ? i : labels[i]));
    if (from_lattice) {
      for (int l : lattice.Levels(labels.empty() ? i : labels[i])) {
        Append(&report, " %d", l);
      }
    } else {
      for (int c = 0; c < pool_joints.cols(); ++c) {
        const bool prismatic =
            model.links[c].joint_type == JointType::kPrismatic;
        Append(&report, " %.3f",
               pool_joints(i, c) * (prismatic ? 1000.0 : 180.0 / M_PI));
      }
    }
    report += "\n";
  }

  // The poses to run, labelled.
  out.chosen.joints.resize(s.design.size(), model.num_joints());
  for (size_t k = 0; k < s.design.size(); ++k) {
    const int64_t i = s.design[k];
    out.chosen.joints.row(k) = pool_joints.row(i);
    out.chosen.pose_indices.push_back(labels.empty() ? i : labels[i]);
  }
  out.poses_csv = PosesCsvText(model, out.chosen);
  if (with_cell && !cell.cell.targets.empty()) {
    // Which targets to measure at each pose: those the cell sees.
    std::vector<uint32_t> seen;
    for (int64_t i : s.design) seen.push_back(feasibility.targets_seen[i]);
    out.poses_csv = PosesCsvWithTargets(out.poses_csv, cell.cell, seen);
  }

  // The JSON report.
  nlohmann::json& j = out.json;
  j = SelectionJson(s, pool_joints, labels);
  if (with_cell) {
    // The preprocess: what the cell kept and why the rest went.
    j["cell"] = options.cell_path;
    j["drawn_pool_size"] = drawn_pool_size;
    if (!cell_efficiency_json.is_null()) {
      j["cell_d_efficiency"] = cell_efficiency_json;
    }
    j.update(CellPoolJson(cell.cell, feasibility));
    if (!cell.cell.targets.empty()) {
      nlohmann::json seen = nlohmann::json::array();
      for (int64_t i : s.design) {
        seen.push_back(TargetsSeenJson(cell.cell, feasibility.targets_seen[i]));
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
    j["order"] = "shortest";
    j["tour"] = TourJson(tour, options.order_resolution_deg,
                         out.chosen.pose_indices, moves_checked, velocity_note);
  }
  j["criterion"] = task ? "task_rms" : "d";
  j["num_poses"] = s.design.size();
  j["noise_m"] = noise_m;
  j["predicted_task_rms_m"] = select.predicted_task_rms_m;
  j["num_task_poses"] = num_task_poses;
  j["task_poses_csv"] = options.task_poses_csv;
  j["measured_csv"] = options.measured_csv;
  j["num_measured"] = num_measured;
  if (with_target) {
    j["target_rms_m"] = *design.target_rms_m;
    j["best_reachable_rms_m"] = target.best_reachable_rms_m;
    nlohmann::json curve = nlohmann::json::array();
    for (size_t k = 0; k < target.sizes.size(); ++k) {
      curve.push_back({target.sizes[k], target.rms_by_size_m[k]});
    }
    j["predicted_task_rms_by_size_m"] = curve;
  }
  j["robot"] = model.name;
  j["measurement"] = MeasurementTypeName(options.type);
  j["free_parameters"] = model.FreeParameterNames();
  j["auto_fixed"] = auto_fixed;
  j["seed"] = seed;
  j["pool"] = pool_name;
  j["pool_storage"] = pool.single_precision() ? "float" : "double";
  j["pool_storage_mib"] = pool.storage_bytes() / (1024.0 * 1024.0);
  if (from_lattice) {
    j["levels"] = options.levels;
  } else if (pool_kind == SelectPool::kCsv) {
    j["pool_csv"] = options.pool_csv;
  }
  out.total_seconds = SecondsSince(start);
  // Wall-clock times: the only fields that vary between runs.
  j["timing"] = {
      {"jacobian_seconds", jacobian_seconds},
      {"selection_seconds", s.seconds},
      {"approximate_seconds", task ? task_approx.seconds : approx.seconds},
      {"total_seconds", out.total_seconds}};
  if (design.certificate && !task) {
    j["efficiency_lower_bound"] = s.efficiency_lower_bound;
    j["log10_det_upper_bound"] = s.log_det_upper_bound / std::log(10.0);
  }
  if (design.certificate && task && !with_prior) {
    // Task efficiency: RMS^2 of the best design of this size over this
    // design's, bounded below.
    j["efficiency_lower_bound"] = s.efficiency_lower_bound;
    j["task_rms_lower_bound_m"] =
        PredictedTaskRms(s.task_criterion_lower_bound, noise_m);
  }
  if (select.with_task_approx) {
    j["approximate_task"] = {
        {"support", task_approx.support},
        {"weights", task_approx.weights},
        {"predicted_task_rms_m",
         PredictedTaskRms(task_approx.criterion, noise_m)},
        {"efficiency_lower_bound", task_approx.efficiency_lower_bound},
        {"converged",
         task_approx.termination_type == TerminationType::kConvergence}};
  }
  if (select.with_approx) {
    j["approximate"] = {
        {"support", approx.support},
        {"weights", approx.weights},
        {"log10_det", approx.log_det / std::log(10.0)},
        {"max_variance", approx.max_variance},
        {"log10_det_upper_bound", approx.log_det_upper_bound / std::log(10.0)},
        {"tolerance", design.approx_tolerance},
        {"converged",
         approx.termination_type == TerminationType::kConvergence}};
  }
  out.termination_type = select.termination_type;
  out.message = select.message;
  return true;
}

}  // namespace activecal
