// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: select, by the library's Select
// (select_workflow.h, what activecal_select calls); with cell= the pool is
// the feasible one, as activecal_select --cell.

#include <optional>
#include <sstream>

#include "activecal/calibration/defaults.h"
#include "activecal/calibration/select_workflow.h"
#include "activecal/core/free_set.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/task_criterion.h"
#include "common.h"

namespace activecal {
namespace python {

std::unique_ptr<CellSetup> CellArg(const Robot& robot, const py::kwargs& kwargs,
                                   std::vector<std::string>* notes,
                                   bool targets_as_markers,
                                   RobotDescription* described) {
  if (!kwargs.contains("cell") || kwargs["cell"].is_none()) return nullptr;
  CellSetupOptions options;
  options.cell_path = PathArg(kwargs["cell"]);
  options.robot_path = robot.path;
  options.chain = robot.chain;
  options.targets_as_markers = targets_as_markers;
  auto setup = std::make_unique<CellSetup>();
  RobotDescription description = robot.description;
  std::string error;
  if (!SetUpCell(options, &description, setup.get(), &error)) {
    Fail("cell: " + error);
  }
  if (described != nullptr) *described = std::move(description);
  for (const std::string& note : setup->notes) {
    notes->push_back("cell: note: " + note);
  }
  return setup;
}

// --------------------------------------------------------------- select

namespace {

// Progress callbacks from C++ (any worker thread) into a Python callable
// progress(stage, done, total). The GIL is taken for each call; an
// exception raised by the callable is kept, later calls are skipped, and
// it is raised again once the C++ work is over (the library's work cannot
// be cancelled, so it runs to its end).
class Progress {
 public:
  explicit Progress(py::object callable) : callable_(std::move(callable)) {
    if (!callable_.is_none() && !PyCallable_Check(callable_.ptr())) {
      Fail("progress: expected a callable progress(stage, done, total)");
    }
  }
  ProgressCallback Callback(const std::string& stage) {
    if (callable_.is_none()) return {};
    return [this, stage](int64_t done, int64_t total) {
      py::gil_scoped_acquire gil;
      if (error_) return;
      try {
        callable_(stage, done, total);
      } catch (py::error_already_set& e) {
        error_.emplace(std::move(e));
      }
    };
  }
  // With the GIL held: raises what the callable raised, if anything.
  void RaiseIfFailed() {
    if (error_) {
      py::error_already_set e = std::move(*error_);
      error_.reset();
      throw e;
    }
  }

 private:
  py::object callable_;
  std::optional<py::error_already_set> error_;
};

struct DesignResult {
  SelectionSummary summary;
  Eigen::MatrixXd joint_angles;
  std::vector<int64_t> pose_indices;
  std::vector<std::string> free_parameters;
  std::vector<std::string> auto_fixed;
  std::vector<std::string> notes;
  std::string criterion;
  double predicted_task_rms_m = 0;
  double noise_m = 0;
  int64_t num_task_poses = 0;
  bool certificate = false;
  bool with_approx = false;
  ApproximateDesignSummary approx;
  bool with_task_approx = false;
  TaskApproximateSummary task_approx;
  bool with_target = false;
  TargetSizeSummary target;
  int num_measured = 0;
  bool single_precision = false;  // the pool's storage
  // With cell=: feasible_poses, rejected, targets_seen (as
  // activecal_select --cell's JSON); with order="shortest": tour. Null
  // members are None.
  nlohmann::json cell_info = nlohmann::json::object();
};

// The library's stages (Select's progress) as the module names them
// ("jacobians", "approximate", "restarts"); its other stages unreported.
StageProgress StagesOf(Progress* bridge) {
  return [bridge](const std::string& stage) -> ProgressCallback {
    if (stage == "Jacobians of the pool poses") {
      return bridge->Callback("jacobians");
    }
    if (stage == "approximate design, rounds") {
      return bridge->Callback("approximate");
    }
    const std::string restarts = " restarts";
    if (stage.size() > restarts.size() &&
        stage.compare(stage.size() - restarts.size(), restarts.size(),
                      restarts) == 0) {
      return bridge->Callback("restarts");
    }
    return {};
  };
}

// select: the keywords as the library's SelectOptions, one Select (the
// work of activecal_select), its summary as a Design.
std::shared_ptr<DesignResult> SelectPy(
    const Robot& robot, std::string algorithm, int num_poses, uint64_t seed,
    int levels, const py::object& pool_obj, const std::string& criterion,
    int64_t pool_size, const py::object& pool_indices,
    const std::string& measurement, double rotation_weight,
    const py::object& parameter_set, bool auto_fix, int restarts,
    int initial_poses, int random_designs, bool certificate,
    double approx_tolerance, int64_t polish_pool_size,
    const std::string& pool_storage, int64_t max_double_pool_mib,
    double noise_m, const py::object& task_poses, const py::object& measured,
    const py::object& target_rms_m, int num_threads, const py::object& progress,
    const py::kwargs& kwargs) {
  NoUnknownOptions("select", kwargs, {"cell", "order"});
  Progress bridge(progress);
  auto result = std::make_shared<DesignResult>();
  // The cell (kwarg cell=path): its checks on this robot; its targets are
  // the markers unless load_robot's frames= gave them, as activecal_select
  // --cell without --frames.
  RobotDescription described;
  const std::unique_ptr<CellSetup> cell =
      CellArg(robot, kwargs, &result->notes, !robot.with_frames, &described);
  const RobotModel& model = cell ? described.model : robot.model();
  // order= (kwarg): "none" (default) or "shortest" (a short tour, as
  // activecal_select --order=shortest; with a cell every move checked).
  std::string order = "none";
  if (kwargs.contains("order") && !kwargs["order"].is_none()) {
    order = py::str(kwargs["order"]);
  }
  if (order != "none" && order != "shortest") {
    Fail("order must be 'none' or 'shortest', got '" + order + "'");
  }
  SelectOptions options;
  options.option_spelling = OptionSpelling::kKeywords;
  options.type = MeasurementTypeArg(measurement, false, "measurement");
  SelectDesignOptions& design = options.design;
  {
    std::string error;
    if (!ParseDesignAlgorithm(algorithm, &design.algorithm, &error) ||
        !ParseDesignCriterion(criterion, &design.criterion, &error)) {
      Fail(error);
    }
  }
  // The candidate poses: a lattice, drawn, or given (labelled by
  // pool_indices).
  if (!pool_obj.is_none() && !py::isinstance<py::str>(pool_obj)) {
    options.pool = SelectPool::kPoses;
    options.pool_poses.joints =
        MatrixArg(pool_obj, "pool", model.num_joints(), false);
    if (!pool_indices.is_none()) {
      options.pool_poses.pose_indices =
          IntegerVector(pool_indices, "pool_indices");
      // The library takes no labels as none given: an empty list is a
      // list of the wrong length here.
      if (options.pool_poses.pose_indices.empty() &&
          options.pool_poses.joints.rows() > 0) {
        Fail("pool_indices: expected " +
             std::to_string(options.pool_poses.joints.rows()) +
             " values (one per pool pose), got 0");
      }
    }
  } else {
    const std::string kind =
        pool_obj.is_none() ? "lattice" : std::string(py::str(pool_obj));
    if (!StringToSelectPool(kind, &options.pool) ||
        options.pool == SelectPool::kMeasurable) {
      Fail(
          "pool must be 'lattice', 'sobol', 'random' or an array of joint "
          "values, got '" +
          kind + "'");
    }
    if (!pool_indices.is_none()) {
      Fail("pool_indices label a pool given as an array; pool is '" + kind +
           "'");
    }
    if (options.pool != SelectPool::kLattice) options.pool_size = pool_size;
  }
  options.levels = levels;
  if (!target_rms_m.is_none()) {
    double target_rms = 0.0;
    try {
      target_rms = py::cast<double>(target_rms_m);
    } catch (const py::cast_error&) {
      Fail("target_rms_m: expected a number (m), got " + Repr(target_rms_m));
    }
    if (!(target_rms > 0) || !std::isfinite(target_rms)) {
      Fail("target_rms_m must be > 0 (m)");
    }
    design.target_rms_m = target_rms;
  }
  if (!measured.is_none()) {
    options.measured = MeasurementsArg(measured, "measured").items;
    CheckMarkers(model, options.measured, "measured");
  }
  design.num_poses = num_poses;
  design.restarts = restarts;
  design.seed = seed;
  design.num_threads = num_threads;
  design.certificate = certificate;
  design.approx_tolerance = approx_tolerance;
  design.polish_pool_size = polish_pool_size;
  design.initial_poses = initial_poses;
  design.random_designs = random_designs;
  design.noise_m = noise_m;
  {
    std::string error;
    if (!design.IsValid(&error)) Fail(error);  // before the pool's work
  }
  if (!task_poses.is_none()) {
    options.task_joints =
        MatrixArg(task_poses, "task_poses", model.num_joints(), false);
  }
  options.parameter_set = ParameterSetArg(robot, parameter_set);
  options.rotation_weight_m_per_rad = rotation_weight;
  options.auto_fix = auto_fix;
  if (!PoolStorageFromString(pool_storage, &options.storage)) {
    Fail("pool_storage must be 'auto', 'double' or 'float', got '" +
         pool_storage + "'");
  }
  options.max_double_pool_mib = max_double_pool_mib;
  options.cell = cell.get();
  options.cell_efficiency = false;
  options.order_shortest = order == "shortest";
  options.robot_path = robot.path;
  options.chain = robot.chain;
  options.progress = StagesOf(&bridge);

  SelectSummary summary;
  {
    py::gil_scoped_release release;
    Select(model, options, &summary);
  }
  bridge.RaiseIfFailed();
  if (!summary.IsSolutionUsable()) Fail(summary.message);

  // The notes: the lattice's, the parameters held and why, the cell's
  // counts.
  for (const std::string& note : summary.lattice_notes) {
    result->notes.push_back(note);
  }
  for (const HeldParameter& d : summary.pool.dropped) {
    result->notes.push_back(
        "parameter_set=" +
        std::string(ParameterSetToString(options.parameter_set)) + ": " +
        d.name + " held fixed: " + d.reason);
  }
  if (summary.pool.filtered) {
    std::string line = summary.feasibility.BriefReport(*cell->checker);
    if (!line.empty() && line.back() == '\n') line.pop_back();
    result->notes.push_back(line);
  }
  for (const std::string& f : HeldNames(summary.pool.pool.held)) {
    result->notes.push_back("auto_fix: " + f + " held fixed");
  }
  const nlohmann::json& j = summary.json;
  SelectDesignSummary& select = summary.design;
  result->summary = select.selection;
  result->predicted_task_rms_m = select.predicted_task_rms_m;
  result->with_approx = select.with_approx;
  result->approx = std::move(select.approx);
  result->with_task_approx = select.with_task_approx;
  result->task_approx = std::move(select.task_approx);
  result->target = std::move(select.target);
  result->single_precision = summary.pool.single_precision;
  result->auto_fixed = summary.pool.HeldFixed();
  result->num_task_poses = j["num_task_poses"].get<int64_t>();
  result->criterion = j["criterion"].get<std::string>();
  result->with_target = design.target_rms_m.has_value();
  result->num_measured = j["num_measured"].get<int>();
  result->noise_m = noise_m;
  result->certificate = certificate;
  result->free_parameters =
      j["free_parameters"].get<std::vector<std::string>>();
  result->joint_angles = summary.chosen.joints;
  result->pose_indices = summary.chosen.pose_indices;
  // As activecal_select's JSON: the tour, the cell's counts and the
  // targets each chosen pose sees.
  for (const char* key :
       {"tour", "feasible_poses", "rejected", "targets_seen"}) {
    if (j.contains(key)) result->cell_info[key] = j[key];
  }
  if (cell) {
    // pool_rows: rows of the pool given, not of the feasible one.
    for (int64_t& i : result->summary.design) {
      i = summary.feasibility.feasible[i];
    }
  }
  return result;
}

py::array_t<double> HistoryLog10(const SelectionSummary& s) {
  py::array_t<double> h(s.history.size());
  auto v = h.mutable_unchecked<1>();
  for (size_t k = 0; k < s.history.size(); ++k) {
    v(k) = s.history[k].log_det / std::log(10.0);
  }
  return h;
}

// A Design's property: the selection's `field` (a copy).
template <typename T>
auto Selected(T SelectionSummary::*field) {
  return [field](const DesignResult& d) -> T { return d.summary.*field; };
}

// DesignResult::cell_info[key] as Python (through json.loads: exact for
// the JSON's numbers and nesting); None when absent.
py::object CellInfo(const DesignResult& d, const char* key) {
  if (!d.cell_info.contains(key)) return py::none();
  return py::module_::import("json").attr("loads")(d.cell_info[key].dump());
}

}  // namespace

void BindDesign(py::module_& m) {
  py::class_<DesignResult, std::shared_ptr<DesignResult>>(
      m, "Design", "A selected set of calibration poses (select).")
      .def_property_readonly(
          "joint_angles", [](const DesignResult& d) { return d.joint_angles; },
          "(num_poses, num_joints): the chosen poses (rad, m)")
      .def_property_readonly(
          "pose_indices",
          [](const DesignResult& d) {
            return py::array(py::cast(d.pose_indices));
          },
          "The chosen poses' labels: lattice pose indices, or pool_indices")
      .def_property_readonly(
          "pool_rows",
          [](const DesignResult& d) {
            return py::array(py::cast(d.summary.design));
          },
          "The chosen poses' rows in the pool")
      .def_property_readonly(
          "feasible_poses",
          [](const DesignResult& d) { return CellInfo(d, "feasible_poses"); },
          "With cell=: the poses of the pool the cell allows (an int, as "
          "activecal_select --cell's JSON); None without a cell")
      .def_property_readonly(
          "rejected",
          [](const DesignResult& d) { return CellInfo(d, "rejected"); },
          "With cell=: the poses rejected per reason, a dict as the CLI's "
          "JSON ('obstacle' a dict per obstacle); None without a cell")
      .def_property_readonly(
          "targets_seen",
          [](const DesignResult& d) { return CellInfo(d, "targets_seen"); },
          "With cell=: per chosen pose, the names of the cell's targets it "
          "sees (the markers measured there); None without targets")
      .def_property_readonly(
          "tour", [](const DesignResult& d) { return CellInfo(d, "tour"); },
          "With order='shortest': the tour (motion_time_before_s, "
          "motion_time_after_s, velocities, blocked_moves (a count), "
          "blocked (a list), ... as the CLI's JSON); None otherwise")
      .def_property_readonly(
          "log10_det",
          [](const DesignResult& d) { return d.summary.log10_det(); })
      .def_property_readonly("oi",
                             [](const DesignResult& d) {
                               return OiFromLogDet(d.summary.log_det,
                                                   d.summary.num_parameters);
                             })
      .def_property_readonly(
          "efficiency_lower_bound",
          [](const DesignResult& d) {
            return d.summary.efficiency_lower_bound;
          },
          "Certified lower bound on the D-efficiency (task criterion: the "
          "task efficiency); NaN without certificate")
      .def_property_readonly("log10_det_upper_bound",
                             [](const DesignResult& d) {
                               return d.summary.log_det_upper_bound /
                                      std::log(10.0);
                             })
      .def_property_readonly(
          "history",
          [](const DesignResult& d) { return HistoryLog10(d.summary); },
          "log10 det after each step of the best restart")
      .def_property_readonly(
          "history_steps",
          [](const DesignResult& d) {
            return Each(d.summary.history,
                        [](const SelectionStep& x) { return x.name(); });
          })
      .def_property_readonly("algorithm",
                             Selected(&SelectionSummary::algorithm))
      .def_readonly("criterion", &DesignResult::criterion)
      .def_property_readonly("num_parameters",
                             Selected(&SelectionSummary::num_parameters))
      .def_property_readonly("pool_size",
                             Selected(&SelectionSummary::pool_size))
      .def_property_readonly(
          "pool_storage",
          [](const DesignResult& d) {
            return std::string(d.single_precision ? "float" : "double");
          },
          "How the pool's blocks were stored: 'double' or 'float' "
          "(pool_storage='auto' past max_double_pool_mib)")
      .def_readonly("free_parameters", &DesignResult::free_parameters)
      .def_readonly("auto_fixed", &DesignResult::auto_fixed)
      .def_readonly("notes", &DesignResult::notes)
      .def_readonly("predicted_task_rms_m", &DesignResult::predicted_task_rms_m,
                    "Predicted RMS position error over the task poses with "
                    "noise sigma noise_m")
      .def_readonly("num_task_poses", &DesignResult::num_task_poses)
      .def_readonly("num_measured", &DesignResult::num_measured,
                    "Measurements counted as already made (measured=)")
      .def_property_readonly(
          "target",
          [](const DesignResult& d) -> py::object {
            if (!d.with_target) return py::none();
            py::dict t;
            t["message"] = d.target.message;
            t["num_poses"] = d.target.num_poses;
            t["predicted_task_rms_m"] = d.target.predicted_task_rms_m;
            t["best_reachable_rms_m"] = d.target.best_reachable_rms_m;
            t["sizes"] = py::array(py::cast(d.target.sizes));
            t["rms_by_size_m"] = py::array(py::cast(d.target.rms_by_size_m));
            return t;
          },
          "With target_rms_m: the size found and the curve size -> "
          "predicted task RMS, or None")
      .def_property_readonly(
          "termination_type",
          [](const DesignResult& d) {
            return TerminationTypeToString(d.summary.termination_type);
          })
      .def_property_readonly(
          "message", [](const DesignResult& d) { return d.summary.message; })
      .def_property_readonly(
          "seconds", [](const DesignResult& d) { return d.summary.seconds; })
      .def_property_readonly(
          "approximate",
          [](const DesignResult& d) -> py::object {
            if (d.with_approx) {
              py::dict a;
              a["support"] = py::array(py::cast(d.approx.support));
              a["weights"] = py::array(py::cast(d.approx.weights));
              a["log10_det"] = d.approx.log_det / std::log(10.0);
              a["log10_det_upper_bound"] =
                  d.approx.log_det_upper_bound / std::log(10.0);
              a["converged"] =
                  d.approx.termination_type == TerminationType::kConvergence;
              return a;
            }
            if (d.with_task_approx) {
              py::dict a;
              a["support"] = py::array(py::cast(d.task_approx.support));
              a["weights"] = py::array(py::cast(d.task_approx.weights));
              a["predicted_task_rms_m"] =
                  PredictedTaskRms(d.task_approx.criterion, d.noise_m);
              a["efficiency_lower_bound"] =
                  d.task_approx.efficiency_lower_bound;
              a["converged"] = d.task_approx.termination_type ==
                               TerminationType::kConvergence;
              return a;
            }
            return py::none();
          },
          "The approximate (continuous-weight) design, or None")
      .def("report",
           [](const DesignResult& d) {
             std::string r = d.summary.BriefReport();
             if (d.with_approx) r += d.approx.BriefReport();
             if (d.with_task_approx) r += d.task_approx.BriefReport();
             return r;
           })
      .def("__repr__", [](const DesignResult& d) {
        std::ostringstream s;
        s << "<activecal.Design " << d.summary.algorithm << ": "
          << d.summary.design.size() << " poses, log10 det "
          << d.summary.log10_det() << ">";
        return s.str();
      });

  m.def("select", &SelectPy, py::arg("robot"),
        py::arg("algorithm") = defaults::kSelectAlgorithm,
        py::arg("num_poses") = defaults::kNumPoses,
        py::arg("seed") = defaults::kSeed,
        py::arg("levels") = defaults::kLevels, py::arg("pool") = py::none(),
        py::arg("criterion") = defaults::kSelectCriterion,
        py::arg("pool_size") = defaults::kPoolSize,
        py::arg("pool_indices") = py::none(),
        py::arg("measurement") = "position",
        py::arg("rotation_weight") = defaults::kRotationWeightMPerRad,
        py::arg("parameter_set") = py::none(), py::arg("auto_fix") = false,
        py::arg("restarts") = 0,
        py::arg("initial_poses") = defaults::kInitialPoses,
        py::arg("random_designs") = defaults::kRandomDesigns,
        py::arg("certificate") = true,
        py::arg("approx_tolerance") = defaults::kApproxTolerance,
        py::arg("polish_pool_size") = defaults::kPolishPoolSize,
        py::arg("pool_storage") = "auto",
        py::arg("max_double_pool_mib") = defaults::kMaxDoublePoolMib,
        py::arg("noise_m") = defaults::kDesignNoiseM,
        py::arg("task_poses") = py::none(), py::arg("measured") = py::none(),
        py::arg("target_rms_m") = py::none(), py::arg("num_threads") = 0,
        py::arg("progress") = py::none(),
        "Selects calibration poses, as activecal_select with the same "
        "options (the same design for the same seed). pool: None or "
        "'lattice' (levels per joint), 'sobol' or 'random' (pool_size "
        "poses), or an array (n, num_joints) of candidate poses. "
        "algorithm: fedorov, eae, detmax, greedy, random, approx. "
        "criterion: d (det), svd (eae), task_rms (task_poses: where the "
        "robot will work, default the pool; measured: Measurements already "
        "made, counted; target_rms_m: the fewest poses meeting it). "
        "cell: a cell file (docs/formats.md): the pool keeps the poses the "
        "cell can run, as activecal_select --cell (its targets the markers "
        "unless load_robot's frames= gave them; the counts in notes and in "
        "feasible_poses, rejected, targets_seen). order: 'none' or "
        "'shortest' (the design as a short tour, as --order=shortest; the "
        "Design's tour). "
        "progress: a callable "
        "progress(stage, done, total). The GIL is released while it runs.");
}

}  // namespace python
}  // namespace activecal
