// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: select: the pool, the task and the design, by
// the library (selection_pool.h, select_design.h); with cell= the pool is
// the feasible one (cell_planning.h), as activecal_select --cell.

#include "activecal/calibration/defaults.h"
#include "activecal/calibration/select_workflow.h"
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
  RobotModel model = cell ? described.model : robot.model();
  // order= (kwarg): "none" (default) or "shortest" (a short tour, as
  // activecal_select --order=shortest; with a cell every move checked).
  std::string order = "none";
  if (kwargs.contains("order") && !kwargs["order"].is_none()) {
    order = py::str(kwargs["order"]);
  }
  if (order != "none" && order != "shortest") {
    Fail("order must be 'none' or 'shortest', got '" + order + "'");
  }
  const MeasurementType type =
      MeasurementTypeArg(measurement, false, "measurement");
  DesignAlgorithm design_algorithm;
  DesignCriterion design_criterion;
  {
    std::string error;
    if (!ParseDesignAlgorithm(algorithm, &design_algorithm, &error) ||
        !ParseDesignCriterion(criterion, &design_criterion, &error)) {
      Fail(error);
    }
  }

  // The candidate poses: a lattice, sampled, or given.
  Eigen::MatrixXd pool_joints;
  std::vector<int64_t> labels;
  std::string pool_kind = "lattice";
  if (!pool_obj.is_none() && py::isinstance<py::str>(pool_obj)) {
    pool_kind = py::str(pool_obj);
  } else if (!pool_obj.is_none()) {
    pool_kind = "array";
  }
  // With a cell the lattice and the draws span the ranges inside the joint
  // margins, as activecal_select --cell.
  const RobotModel pool_model =
      cell ? WithinJointMargins(*cell->checker, model) : model;
  // The drawn pools and the lattice, as activecal_select's --pool (not
  // measurable: the module has no such pool).
  SelectPool drawn = SelectPool::kLattice;
  const bool given = pool_kind == "array";
  if (!given && (!StringToSelectPool(pool_kind, &drawn) ||
                 drawn == SelectPool::kMeasurable)) {
    Fail(
        "pool must be 'lattice', 'sobol', 'random' or an array of joint "
        "values, got '" +
        pool_kind + "'");
  }
  if (given) {
    pool_joints = MatrixArg(pool_obj, "pool", model.num_joints(), false);
    if (!pool_indices.is_none()) {
      labels = IntegerVector(pool_indices, "pool_indices");
      if (static_cast<int64_t>(labels.size()) != pool_joints.rows()) {
        Fail("pool_indices: expected " + std::to_string(pool_joints.rows()) +
             " values (one per pool pose), got " +
             std::to_string(labels.size()));
      }
      std::string error;
      if (!CheckPoseIndices(labels, /*unique=*/true, &error)) {
        Fail("pool_indices: " + error);
      }
    }
  } else if (drawn == SelectPool::kLattice) {
    JointLattice lattice;
    std::string error;
    if (!JointLattice::Create(pool_model, levels, &lattice, &error)) {
      Fail("levels=" + std::to_string(levels) + ": " + error);
    }
    if (!CheckSelectionPoolSize(lattice.size(), model, type, &error)) {
      Fail("levels=" + std::to_string(levels) + ": " + error);
    }
    for (const std::string& note : lattice.OneTurnNotes(model)) {
      result->notes.push_back(note);
    }
    pool_joints = lattice.AllJointValues();
  } else {
    const JointSampling sampling = drawn == SelectPool::kRandom
                                       ? JointSampling::kRandom
                                       : JointSampling::kSobol;
    // A pool too large for memory is refused up front (the alternative is
    // std::bad_alloc midway), by the library's check, as activecal_select.
    std::string error;
    if (!CheckSelectionPoolSize(pool_size, model, type, &error)) {
      Fail("pool_size: " + error);
    }
    if (!SampleJointValues(pool_model, sampling, pool_size, seed, &pool_joints,
                           &error)) {
      Fail("pool=" + pool_kind + ": " + error);
    }
  }
  if (!pool_indices.is_none() && pool_kind != "array") {
    Fail("pool_indices label a pool given as an array; pool is '" + pool_kind +
         "'");
  }
  const bool with_target = !target_rms_m.is_none();
  double target_rms = 0.0;
  if (with_target) {
    try {
      target_rms = py::cast<double>(target_rms_m);
    } catch (const py::cast_error&) {
      Fail("target_rms_m: expected a number (m), got " + Repr(target_rms_m));
    }
  }
  if (with_target && (!(target_rms > 0) || !std::isfinite(target_rms))) {
    Fail("target_rms_m must be > 0 (m)");
  }
  std::vector<Measurement> measured_items;
  if (!measured.is_none()) {
    measured_items = MeasurementsArg(measured, "measured").items;
    CheckMarkers(model, measured_items, "measured");
  }
  if (!with_target && (num_poses <= 0 || num_poses > pool_joints.rows())) {
    Fail("num_poses must be in [1, " + std::to_string(pool_joints.rows()) +
         "] (the pool size), got " + std::to_string(num_poses));
  }
  SelectDesignOptions options;
  options.algorithm = design_algorithm;
  options.criterion = design_criterion;
  options.num_poses = num_poses;
  options.restarts = restarts;
  options.seed = seed;
  options.num_threads = num_threads;
  options.certificate = certificate;
  options.approx_tolerance = approx_tolerance;
  options.polish_pool_size = polish_pool_size;
  options.initial_poses = initial_poses;
  options.random_designs = random_designs;
  options.noise_m = noise_m;
  if (with_target) options.target_rms_m = target_rms;
  {
    std::string error;
    if (!options.IsValid(&error)) Fail(error);
  }
  const bool task = options.task();
  if (!measured_items.empty() && !task) {
    Fail(
        "measured needs criterion='task_rms' (the D-criterion algorithms "
        "take no prior information)");
  }
  Eigen::MatrixXd task_joints;
  if (!task_poses.is_none()) {
    task_joints =
        MatrixArg(task_poses, "task_poses", model.num_joints(), false);
  }
  SelectionPoolOptions pool_options;
  pool_options.parameter_set = ParameterSetArg(robot, parameter_set);
  pool_options.type = type;
  pool_options.rotation_weight_m_per_rad = rotation_weight;
  pool_options.num_threads = num_threads;
  pool_options.auto_fix = auto_fix;
  // Single precision past the budget, as activecal_select --pool_storage.
  pool_options.reads_float = ReadsFloatPool(design_algorithm, design_criterion);
  if (!PoolStorageFromString(pool_storage, &pool_options.storage)) {
    Fail("pool_storage must be 'auto', 'double' or 'float', got '" +
         pool_storage + "'");
  }
  pool_options.max_double_pool_mib = max_double_pool_mib;
  {
    std::string error;
    if (!pool_options.IsValid(&error)) Fail(error);
  }
  PoolFilterSummary feasibility;
  if (cell) {
    PoolFilterOptions o;
    o.num_threads = num_threads;
    SetCellPoolFilter(*cell->checker, model, o, &feasibility, &pool_options);
  }
  pool_options.progress = bridge.Callback("jacobians");
  options.approximate_progress = bridge.Callback("approximate");
  options.restarts_progress = bridge.Callback("restarts");

  std::string failure;  // set inside the GIL-free block
  {
    py::gil_scoped_release release;
    [&] {
      // The parameters, the pool, the task and the design, as
      // activecal_select.
      CandidatePool pool;
      SelectionPoolSummary pool_summary;
      const bool pool_built = BuildSelectionPool(
          &model, pool_joints, pool_options, &pool, &pool_summary);
      result->single_precision = pool_summary.single_precision;
      if (pool_summary.filtered && pool_summary.kept.empty()) {
        failure = "cell: " + pool_summary.message;
        return;
      }
      for (const HeldParameter& d : pool_summary.dropped) {
        result->notes.push_back(
            "parameter_set=" +
            std::string(ParameterSetToString(pool_options.parameter_set)) +
            ": " + d.name + " held fixed: " + d.reason);
      }
      if (!pool_built) {
        const IdentifiabilityReport& report = pool_summary.pool.identifiability;
        if (!pool_summary.reduction_failed && !report.identifiable() &&
            report.num_free > 0) {
          failure =
              (pool_summary.filtered
                   ? "the feasible pool (" + pool_summary.filter_note + "): "
                   : "the pool: ") +
              report.Message();
          if (!auto_fix && report.num_equations >= report.num_free) {
            failure +=
                ". Fix them in the robot file (remove them from 'free') or "
                "pass auto_fix=True";
          }
        } else {
          failure = pool_summary.message;
        }
        return;
      }
      if (pool_summary.filtered) {
        // From here on the pool is the feasible one, its rows labelled by
        // their place in the pool given (or their pool_indices).
        std::string line = feasibility.BriefReport(*cell->checker);
        if (!line.empty() && line.back() == '\n') line.pop_back();
        result->notes.push_back(line);
        std::vector<int64_t> kept_labels;
        for (int64_t row : pool_summary.kept) {
          kept_labels.push_back(labels.empty() ? row : labels[row]);
        }
        pool_joints = feasibility.FeasibleJoints(pool_joints);
        labels = std::move(kept_labels);
        if (!with_target && num_poses > pool_joints.rows()) {
          failure = "num_poses=" + std::to_string(num_poses) +
                    ": the feasible pool has only " + pool_summary.filter_note;
          return;
        }
      }
      result->auto_fixed = pool_summary.HeldFixed();
      for (const std::string& f : HeldNames(pool_summary.pool.held)) {
        result->notes.push_back("auto_fix: " + f + " held fixed");
      }
      result->num_task_poses =
          task_joints.rows() ? task_joints.rows() : pool_joints.rows();
      CandidatePool task_pool;
      bool task_is_pool = false;
      std::string error;
      if (!BuildTaskPool(model, pool_joints, task_joints, pool_options,
                         &task_pool, &task_is_pool, &error)) {
        failure = "task_poses: " + error;
        return;
      }
      const Eigen::MatrixXd W = TaskMatrix(task_is_pool ? pool : task_pool);
      // The poses already measured, whitened to noise_m.
      RowMatrixXd prior(0, pool.num_parameters());
      if (!measured_items.empty() &&
          !MeasuredInformationRows(model, model.nominal, measured_items,
                                   rotation_weight, noise_m, &prior, &error)) {
        failure = "measured: " + error;
        return;
      }
      SelectDesignSummary select;
      if (!SelectDesign(pool, W, prior, options, &select)) {
        failure = select.message;
        return;
      }
      result->summary = select.selection;
      result->predicted_task_rms_m = select.predicted_task_rms_m;
      result->with_approx = select.with_approx;
      result->approx = std::move(select.approx);
      result->with_task_approx = select.with_task_approx;
      result->task_approx = std::move(select.task_approx);
      result->target = std::move(select.target);
    }();
  }
  bridge.RaiseIfFailed();
  if (!failure.empty()) Fail(failure);

  SelectionSummary& summary = result->summary;
  result->criterion = task ? "task_rms" : "d";
  result->with_target = with_target;
  result->num_measured = static_cast<int>(measured_items.size());
  result->noise_m = noise_m;
  result->certificate = certificate;
  result->free_parameters = model.FreeParameterNames();
  result->joint_angles.resize(summary.design.size(), model.num_joints());
  for (size_t k = 0; k < summary.design.size(); ++k) {
    const int64_t i = summary.design[k];
    result->joint_angles.row(k) = pool_joints.row(i);
    result->pose_indices.push_back(labels.empty() ? i : labels[i]);
  }
  if (order == "shortest") {
    // The design as a short tour, as activecal_select --order=shortest
    // (1 deg steps).
    TourOptions o;
    o.velocity_limits = RobotVelocityLimits(robot.path, robot.chain, model);
    o.resolution_rad = M_PI / 180.0;
    o.resolution_m = 1e-3;
    o.check_moves = cell != nullptr;
    TourSummary tour;
    if (!OrderTour(cell ? cell->checker.get() : nullptr, result->joint_angles,
                   o, &tour)) {
      Fail("order='shortest': " + tour.message);
    }
    const std::vector<int64_t> design = summary.design;
    const Eigen::MatrixXd joints = result->joint_angles;
    const std::vector<int64_t> labels_before = result->pose_indices;
    for (size_t k = 0; k < design.size(); ++k) {
      summary.design[k] = design[tour.order[k]];
      result->joint_angles.row(k) = joints.row(tour.order[k]);
      result->pose_indices[k] = labels_before[tour.order[k]];
    }
    result->cell_info["tour"] =
        TourJson(tour, 1.0, result->pose_indices,
                 cell ? MovesCheckedJson(true, *cell)
                      : MovesCheckedJson(false, CellSetup(), "no cell="),
                 AssumedVelocityNote(model, o.velocity_limits));
  }
  if (cell) {
    // As activecal_select --cell's JSON.
    result->cell_info.update(CellPoolJson(cell->cell, feasibility));
    if (!cell->cell.targets.empty()) {
      nlohmann::json seen = nlohmann::json::array();
      for (int64_t i : summary.design) {
        seen.push_back(
            TargetsSeenJson(cell->cell, feasibility.targets_seen[i]));
      }
      result->cell_info["targets_seen"] = seen;
    }
    // pool_rows: rows of the pool given, not of the feasible one.
    for (int64_t& i : summary.design) i = feasibility.feasible[i];
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

namespace {

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
            std::vector<std::string> s;
            for (const SelectionStep& x : d.summary.history) {
              s.push_back(x.name());
            }
            return s;
          })
      .def_property_readonly(
          "algorithm",
          [](const DesignResult& d) { return d.summary.algorithm; })
      .def_readonly("criterion", &DesignResult::criterion)
      .def_property_readonly(
          "num_parameters",
          [](const DesignResult& d) { return d.summary.num_parameters; })
      .def_property_readonly(
          "pool_size",
          [](const DesignResult& d) { return d.summary.pool_size; })
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
