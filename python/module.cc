// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: thin pybind11 bindings over the library,
// numpy in and out (docs/python.md). This file binds the functions and
// classes the other files of python/ define (common.h).

#include "activecal/calibration/defaults.h"
#include "common.h"

using namespace activecal;
using namespace activecal::python;

namespace {

// DesignResult::cell_info[key] as Python (through json.loads: exact for
// the JSON's numbers and nesting); None when absent.
py::object CellInfo(const DesignResult& d, const char* key) {
  if (!d.cell_info.contains(key)) return py::none();
  return py::module_::import("json").attr("loads")(d.cell_info[key].dump());
}

}  // namespace

PYBIND11_MODULE(_activecal, m) {
  m.doc() =
      "activecal: robot kinematic calibration (C++ core, pybind11 "
      "bindings). Units are SI (m, rad); errors are ValueError (bad input) "
      "or RuntimeError (a solver failed), with the library's one-line "
      "messages. See docs/python.md.";
  m.attr("__version__") = "0.1.0";
  // As the programs: glog silent below FATAL (no Ceres LOG(ERROR) lines
  // beside the exception that says what went wrong).
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = google::GLOG_FATAL;

  // ---- Robot
  py::class_<Robot, std::shared_ptr<Robot>>(
      m, "Robot",
      "A robot model (load_robot, puma560). Immutable, so one Robot may be "
      "used from several threads.")
      .def_property_readonly("name",
                             [](const Robot& r) { return r.model().name; })
      .def_property_readonly("path", [](const Robot& r) { return r.path; })
      .def_property_readonly("is_urdf", [](const Robot& r) { return r.urdf; })
      .def_property_readonly(
          "num_joints", [](const Robot& r) { return r.model().num_joints(); })
      .def_property_readonly("joint_names",
                             [](const Robot& r) {
                               std::vector<std::string> names;
                               for (int j = 0; j < r.model().num_joints();
                                    ++j) {
                                 names.push_back(r.model().block_name(j + 1));
                               }
                               return names;
                             })
      .def_property_readonly(
          "joint_limits",
          [](const Robot& r) {
            Eigen::MatrixXd l(r.model().num_joints(), 2);
            for (int j = 0; j < r.model().num_joints(); ++j) {
              l(j, 0) = r.model().links[j].joint_min;
              l(j, 1) = r.model().links[j].joint_max;
            }
            return l;
          },
          "(num_joints, 2): min and max of each joint (rad, or m for a "
          "prismatic joint)")
      .def_property_readonly(
          "num_parameters",
          [](const Robot& r) { return r.model().num_parameters(); })
      .def_property_readonly(
          "num_free", [](const Robot& r) { return r.model().num_free(); })
      .def_property_readonly(
          "parameter_names",
          [](const Robot& r) { return r.model().ParameterNames(); },
          "Names of every parameter, in the full vector's order "
          "(\"L2.beta\", \"elbow_joint.offset\")")
      .def_property_readonly(
          "free_parameter_names",
          [](const Robot& r) { return r.model().FreeParameterNames(); })
      .def_property_readonly("parameter_units",
                             [](const Robot& r) {
                               std::vector<std::string> units;
                               for (int i = 0; i < r.model().num_parameters();
                                    ++i) {
                                 units.push_back(r.model().ParameterUnit(i));
                               }
                               return units;
                             })
      .def_property_readonly(
          "nominal",
          [](const Robot& r) { return Eigen::VectorXd(r.model().nominal); },
          "The nominal values of every parameter (SI), a copy")
      .def_property_readonly(
          "free", [](const Robot& r) { return FreeFlags(r.model()); },
          "Boolean array: which parameters are free (identified)")
      .def_property_readonly(
          "true_parameters",
          [](const Robot& r) -> py::object {
            if (r.description.true_parameters.size() == 0) return py::none();
            return py::cast(Eigen::VectorXd(r.description.true_parameters));
          },
          "The file's true values (for simulation), or None")
      .def("forward", &Forward, py::arg("q"),
           py::arg("parameters") = py::none(), py::arg("marker") = 0,
           "The measured point (m) at joint readings q: shape (3,) for one "
           "pose (num_joints,), (n, 3) for n poses (n, num_joints). "
           "parameters: a full parameter vector (default: nominal).")
      .def("frame", &Frame, py::arg("q"), py::arg("parameters") = py::none(),
           py::arg("marker") = 0,
           "The 4 x 4 transform of the measured target frame at q (one "
           "pose) in the device's frame.")
      .def("jacobian", &JacobianPy, py::arg("q"),
           py::arg("parameters") = py::none(), py::arg("marker") = 0,
           py::arg("type") = "position", py::arg("rotation_weight") = 1.0,
           "d(measured point)/d(free parameters): (3, num_free) for one "
           "pose, (n, 3, num_free) for n; type='pose' gives 6 rows "
           "(orientation rows times rotation_weight, m/rad).")
      .def("with_parameter_set", &WithParameterSet, py::arg("name"),
           py::arg("measurement") = "position",
           "A copy whose free parameters are the named set (registration, "
           "offsets, full; file: unchanged), as ParameterSetFreeSet; select "
           "and identify further reduce it to what the data separate.")
      .def("perturbed", &PerturbedPy, py::arg("perturb_m"),
           py::arg("perturb_rad"), py::arg("seed") = 1,
           py::arg("parameters") = py::none(),
           "The parameters of a simulated robot: `parameters` (default: "
           "nominal) with every free parameter moved by N(0, perturb_m^2) "
           "(lengths, m) or N(0, perturb_rad^2) (angles, rad), seeded: the "
           "values activecal_simulate --perturb_m --perturb_rad --seed "
           "simulates from (PerturbParameters).")
      .def(py::pickle(&RobotState, &RobotFromState))
      .def("__copy__", [](const RobotPtr& r) { return r; })
      .def(
          "__deepcopy__", [](const RobotPtr& r, py::object) { return r; },
          py::arg("memo"))
      .def("save", &SaveRobot, py::arg("path"),
           py::arg("parameters") = py::none(),
           "Writes the robot YAML file with `parameters` (default: nominal) "
           "as its nominal values.")
      .def("__repr__", [](const Robot& r) {
        return "<activecal.Robot '" + r.model().name +
               "': " + std::to_string(r.model().num_joints()) + " joints, " +
               std::to_string(r.model().num_free()) + " of " +
               std::to_string(r.model().num_parameters()) + " parameters free>";
      });

  m.def("load_robot", &LoadRobotPy, py::arg("path"),
        py::arg("base_link") = py::none(), py::arg("tip_link") = py::none(),
        py::arg("frames") = py::none(),
        "Loads a robot: an activecal robot YAML file or a URDF (.urdf) chain "
        "from base_link to tip_link; frames: a metrology frames file. "
        "ValueError with file:line: field: what on errors.");
  m.def("puma560", &Puma560,
        "The built-in PUMA 560 of Sun & Hollerbach (the same as "
        "data/puma560.yaml), with its true values.");

  // ---- Measurements
  py::class_<Measurements, std::shared_ptr<Measurements>>(
      m, "Measurements",
      "What a device reported: position, 6D pose or distance rows. Arrays "
      "are in SI units; rows without a field hold NaN.")
      .def(py::init(&MakeMeasurements), py::arg("type"), py::arg("joints"),
           py::arg("positions") = py::none(), py::arg("rotations") = py::none(),
           py::arg("joints2") = py::none(), py::arg("distances") = py::none(),
           py::arg("markers") = py::none(), py::arg("sigma_m") = py::none(),
           py::arg("sigma_rad") = py::none(),
           "Measurements of one type from arrays: joints (n, num_joints); "
           "positions (n, 3) m; rotations (n, 3) rotation vectors (rad, "
           "pose); joints2 (n, num_joints) and distances (n,) m (distance); "
           "markers (n,) 0-based; sigma_m (n, 3); sigma_rad (n,).")
      .def(py::pickle(&MeasurementsState, &MeasurementsFromState))
      .def("__len__", [](const Measurements& m) { return m.items.size(); })
      .def("__getitem__", &Subset)
      .def("__add__",
           [](const Measurements& a, const Measurements& b) {
             Measurements out = a;
             out.items.insert(out.items.end(), b.items.begin(), b.items.end());
             out.warnings.insert(out.warnings.end(), b.warnings.begin(),
                                 b.warnings.end());
             out.notes.insert(out.notes.end(), b.notes.begin(), b.notes.end());
             out.num_joints = NumJoints(a) ? NumJoints(a) : NumJoints(b);
             return out;
           })
      .def_property_readonly("types",
                             [](const Measurements& m) {
                               std::vector<std::string> t;
                               for (const Measurement& x : m.items) {
                                 t.push_back(MeasurementTypeName(x.type));
                               }
                               return t;
                             })
      .def_property_readonly("joints",
                             [](const Measurements& m) {
                               return Column(m, NumJoints(m),
                                             [](const Measurement& x) {
                                               return x.joints.transpose();
                                             });
                             })
      .def_property_readonly(
          "joints2",
          [](const Measurements& m) {
            const int n = NumJoints(m);
            return Column(m, n, [n](const Measurement& x) {
              return x.joints2.size() == n
                         ? Eigen::RowVectorXd(x.joints2.transpose())
                         : Eigen::RowVectorXd::Constant(n, NAN);
            });
          })
      .def_property_readonly(
          "positions",
          [](const Measurements& m) {
            return Column(m, 3, [](const Measurement& x) {
              return x.type == MeasurementType::kDistance
                         ? Eigen::RowVector3d::Constant(NAN)
                         : Eigen::RowVector3d(x.position.transpose());
            });
          })
      .def_property_readonly(
          "rotations",
          [](const Measurements& m) {
            return Column(m, 3, [](const Measurement& x) {
              return x.type == MeasurementType::kPose
                         ? Eigen::RowVector3d(x.rotation.transpose())
                         : Eigen::RowVector3d::Constant(NAN);
            });
          })
      .def_property_readonly("distances",
                             [](const Measurements& m) {
                               Eigen::VectorXd d(m.items.size());
                               for (size_t i = 0; i < m.items.size(); ++i) {
                                 d[i] = m.items[i].type ==
                                                MeasurementType::kDistance
                                            ? m.items[i].distance
                                            : NAN;
                               }
                               return d;
                             })
      .def_property_readonly("markers",
                             [](const Measurements& m) {
                               std::vector<int> k;
                               for (const Measurement& x : m.items) {
                                 k.push_back(x.marker);
                               }
                               return py::array(py::cast(k));
                             })
      .def_property_readonly(
          "sigma_m",
          [](const Measurements& m) {
            return Column(m, 3, [](const Measurement& x) {
              return Eigen::RowVector3d(x.sigma_m.transpose());
            });
          })
      .def_property_readonly("sigma_rad",
                             [](const Measurements& m) {
                               Eigen::VectorXd s(m.items.size());
                               for (size_t i = 0; i < m.items.size(); ++i) {
                                 s[i] = m.items[i].sigma_rad;
                               }
                               return s;
                             })
      .def_readonly("warnings", &Measurements::warnings,
                    "The CSV reader's warnings (joint readings just beyond "
                    "the limits)")
      .def_readonly("notes", &Measurements::notes,
                    "The CSV reader's notes (ignored columns, markers not "
                    "seen)")
      .def("__repr__", [](const Measurements& m) {
        return "<activecal.Measurements: " + std::to_string(m.items.size()) +
               " rows>";
      });

  m.def("read_measurements", &ReadMeasurementsPy, py::arg("robot"),
        py::arg("path"), py::arg("strict_limits") = false,
        py::arg("columns_strict") = false, py::arg("column_map") = py::none(),
        "Reads a measurements CSV (docs/formats.md); column_map: the path "
        "of a YAML column map to read a device's export as it comes.");
  m.def("write_measurements", &WriteMeasurementsPy, py::arg("robot"),
        py::arg("path"), py::arg("measurements"),
        py::arg("millimetres") = false, py::arg("joint_degrees") = false,
        py::arg("joint_names") = false,
        py::arg("orientation") = "rotation_vector",
        "Writes a measurements CSV; the default (SI) reads back bit for "
        "bit.");
  m.def("read_poses", &ReadPosesPy, py::arg("robot"), py::arg("path"),
        py::arg("reject_duplicates") = false,
        "Reads a poses CSV: (joint_angles (n, num_joints) rad/m, "
        "pose_indices (n,)).");
  m.def("write_poses", &WritePosesPy, py::arg("robot"), py::arg("path"),
        py::arg("joint_angles"), py::arg("pose_indices") = py::none(),
        "Writes a poses CSV (pose_index, joints in rad and deg) to run on "
        "the robot.");

  m.def("read_targets", &ReadTargetsPy, py::arg("robot"), py::arg("path"),
        "Reads a Cartesian targets CSV (docs/formats.md): (points (n, 3) m, "
        "rotation vectors (n, 3) rad or None, start joints (n, num_joints) "
        "or None, pose_indices (n,)), for compensate(targets=...).");
  m.def("simulate", &SimulatePy, py::arg("robot"), py::arg("joint_angles"),
        py::arg("noise_m") = defaults::kSimulationNoiseM,
        py::arg("seed") = defaults::kSeed, py::arg("type") = "position",
        py::arg("rotation_noise_rad") = defaults::kSimulationRotationNoiseRad,
        py::arg("parameters") = py::none(),
        "The measurements a device would report at the poses (rows of "
        "joint_angles), from the robot's true values (or `parameters`) with "
        "Gaussian noise, as activecal_simulate; type='distance' measures "
        "consecutive poses.");

  // ---- Design
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

  // ---- Estimate
  py::class_<EstimateResult, std::shared_ptr<EstimateResult>>(
      m, "Estimate", "An identification result (identify).")
      .def_property_readonly(
          "parameter_names",
          [](const EstimateResult& e) { return e.fit().names; },
          "The identified (free) parameters, in order")
      .def_property_readonly(
          "estimates",
          [](const EstimateResult& e) { return e.fit().estimates; })
      .def_property_readonly(
          "std",
          [](const EstimateResult& e) { return e.fit().standard_deviations; },
          "Standard deviations of the estimates")
      .def_property_readonly(
          "covariance",
          [](const EstimateResult& e) { return e.fit().covariance; })
      .def_property_readonly(
          "correlation",
          [](const EstimateResult& e) { return e.fit().correlation; })
      .def_property_readonly(
          "nominal",
          [](const EstimateResult& e) {
            return ExtractFree(e.model(), e.robot->model().nominal);
          },
          "The nominal values of the identified parameters")
      .def_property_readonly(
          "parameters",
          [](const EstimateResult& e) { return e.fit().parameters; },
          "The full parameter vector identified")
      .def_property_readonly(
          "rms_before_m",
          [](const EstimateResult& e) { return e.fit().initial_rms_m; },
          "RMS residual norm at the start (nominal, base registered)")
      .def_property_readonly(
          "rms_after_m", [](const EstimateResult& e) { return e.fit().rms_m; })
      .def_property_readonly(
          "registration_only_rms_m",
          [](const EstimateResult& e) -> py::object {
            if (!e.calibration.have_baseline) return py::none();
            return py::float_(e.calibration.baseline.rms_m);
          },
          "RMS residual with only the base and markers fitted, or None")
      .def_property_readonly(
          "sigma_m", [](const EstimateResult& e) { return e.fit().sigma_m; })
      .def_property_readonly(
          "iterations",
          [](const EstimateResult& e) { return e.fit().iterations; })
      .def_property_readonly(
          "residual_norms",
          [](const EstimateResult& e) { return e.fit().residual_norms; })
      .def_property_readonly("outliers",
                             [](const EstimateResult& e) {
                               return py::array(py::cast(e.fit().outliers));
                             })
      .def_property_readonly(
          "termination_type",
          [](const EstimateResult& e) {
            return TerminationTypeToString(e.fit().termination_type);
          })
      .def_property_readonly(
          "held_fixed",
          [](const EstimateResult& e) { return HeldNames(e.calibration.held); },
          "Parameters held at nominal: the parameter set's reduction, "
          "auto_fix, model selection")
      .def_property_readonly(
          "warnings",
          [](const EstimateResult& e) { return e.calibration.warnings; })
      .def_property_readonly(
          "registered_base",
          [](const EstimateResult& e) { return e.calibration.registered_base; })
      .def_property_readonly(
          "parameter_set",
          [](const EstimateResult& e) {
            return ParameterSetToString(e.calibration.options.parameter_set);
          })
      .def_property_readonly(
          "model_selection_curve",
          [](const EstimateResult& e) {
            py::list curve;
            for (const ModelSelectionPoint& p : e.calibration.selection.curve) {
              py::dict d;
              d["num_kept"] = p.num_kept;
              d["added"] = p.added;
              d["ok"] = p.ok;
              d["training_rms_m"] = p.training_rms_m;
              d["held_out_rms_m"] = p.held_out_rms_m;
              curve.append(d);
            }
            return curve;
          })
      .def_property_readonly("learned_residual", &LearnedResidualPy,
                             "learned_residual='on'/'auto': the correction's "
                             "fit and decision (a dict), else None")
      .def_readonly("notes", &EstimateResult::notes,
                    "activecal_identify's notes: the orientation hint, the "
                    "rotation_weight note (when not given)")
      .def_property_readonly(
          "robot", &CalibratedRobot,
          "The calibrated Robot: identified values as nominal")
      .def(
          "save",
          [](const EstimateResult& e, const py::object& path) {
            WriteText(PathArg(path), EstimateFileText(e));
          },
          py::arg("path"),
          "Writes the calibrated robot YAML (as activecal_identify "
          "--model_out); load_robot(path) reads it back.")
      .def("report",
           [](const EstimateResult& e) { return e.fit().BriefReport(); })
      .def("__repr__", [](const EstimateResult& e) {
        std::ostringstream s;
        s << "<activecal.Estimate: " << e.fit().num_free << " parameters, RMS "
          << e.fit().initial_rms_m << " -> " << e.fit().rms_m << " m>";
        return s.str();
      });

  m.def("identify", &IdentifyPy, py::arg("robot"), py::arg("measurements"),
        "identify(robot, measurements, **options) -> Estimate, as "
        "activecal_identify with the same options: parameter_set, "
        "register_base, auto_fix, model_selection ('auto': 'none' for the "
        "robot file's free set, 'cv' for a named set; 'cv', 'validation', "
        "'none'), folds, selection_ranking, selection_rule ('1se_most', "
        "'min', '1se', 'ftest'), validation (Measurements), "
        "validation_fraction (held out at random, seeded), "
        "robust_loss, robust_scale_m, outlier_probability, rotation_weight, "
        "default_sigma_m, default_sigma_rad, prior_std_m, prior_std_rad, "
        "seed, num_threads, learned_residual ('off', 'on', 'auto'), "
        "learned_features, learned_standard_errors. The GIL is released "
        "while it runs.");
  // ---- Compensation
  py::class_<CompensationResult, std::shared_ptr<CompensationResult>>(
      m, "Compensation", "A compensated program (compensate).")
      .def_property_readonly(
          "joint_angles",
          [](const CompensationResult& c) {
            Eigen::MatrixXd q(c.summary.results.size(),
                              c.robot->model().num_joints());
            for (size_t i = 0; i < c.summary.results.size(); ++i) {
              const Eigen::VectorXd& j = c.summary.results[i].joints;
              if (j.size() == q.cols()) {
                q.row(i) = j.transpose();
              } else {
                q.row(i).setConstant(NAN);
              }
            }
            return q;
          },
          "(n, num_joints): the joints to send the calibrated robot to")
      .def_property_readonly(
          "status",
          [](const CompensationResult& c) {
            std::vector<std::string> s;
            for (const InverseKinematicsResult& r : c.summary.results) {
              s.push_back(IkStatusName(r.status));
            }
            return s;
          },
          "Per target: converged, singular, limit, unreachable, invalid, "
          "iteration_cap, collision (cell=)")
      .def_property_readonly("messages",
                             [](const CompensationResult& c) {
                               std::vector<std::string> s;
                               for (const auto& r : c.summary.results) {
                                 s.push_back(r.message);
                               }
                               return s;
                             })
      .def_property_readonly("position_error_m",
                             [](const CompensationResult& c) {
                               Eigen::VectorXd e(c.summary.results.size());
                               for (size_t i = 0; i < c.summary.results.size();
                                    ++i) {
                                 e[i] = c.summary.results[i].position_error_m;
                               }
                               return e;
                             })
      .def_property_readonly("rotation_error_rad",
                             [](const CompensationResult& c) {
                               Eigen::VectorXd e(c.summary.results.size());
                               for (size_t i = 0; i < c.summary.results.size();
                                    ++i) {
                                 e[i] = c.summary.results[i].rotation_error_rad;
                               }
                               return e;
                             })
      .def_property_readonly(
          "target_points",
          [](const CompensationResult& c) {
            Eigen::MatrixXd p(c.summary.targets.size(), 3);
            for (size_t i = 0; i < c.summary.targets.size(); ++i) {
              p.row(i) = c.summary.targets[i].point.transpose();
            }
            return p;
          },
          "(n, 3): what each target means in the device frame (m)")
      .def_property_readonly("pose_indices",
                             [](const CompensationResult& c) {
                               return py::array(py::cast(c.pose_indices));
                             })
      .def_property_readonly(
          "all_converged",
          [](const CompensationResult& c) { return c.summary.AllConverged(); })
      .def_property_readonly("max_position_error_m",
                             [](const CompensationResult& c) {
                               return c.summary.max_position_error_m;
                             })
      .def_property_readonly("max_joint_change",
                             [](const CompensationResult& c) {
                               return c.summary.max_joint_change;
                             })
      .def_property_readonly("rms_joint_change",
                             [](const CompensationResult& c) {
                               return c.summary.rms_joint_change;
                             })
      .def_property_readonly(
          "termination_type",
          [](const CompensationResult& c) {
            return TerminationTypeToString(c.summary.termination_type);
          })
      .def_property_readonly(
          "message",
          [](const CompensationResult& c) { return c.summary.message; })
      .def(
          "save",
          [](const CompensationResult& c, const py::object& path) {
            WriteText(PathArg(path),
                      CompensatedPosesCsvText(c.robot->model(), c.pose_indices,
                                              c.summary));
          },
          py::arg("path"),
          "Writes the compensated program as activecal_compensate --out "
          "does (poses CSV with status and position_error_m).")
      .def("report",
           [](const CompensationResult& c) { return c.summary.BriefReport(); })
      .def("__repr__", [](const CompensationResult& c) {
        int converged = 0;
        for (const InverseKinematicsResult& r : c.summary.results) {
          converged += r.status == IkStatus::kConverged;
        }
        std::ostringstream s;
        s << "<activecal.Compensation: " << c.summary.results.size()
          << " targets, " << converged << " converged, max position error "
          << c.summary.max_position_error_m << " m>";
        return s.str();
      });

  m.def("compensate", &CompensatePy, py::arg("robot"),
        py::arg("program") = py::none(), py::arg("nominal") = py::none(),
        py::arg("targets") = py::none(), py::arg("rotations") = py::none(),
        py::arg("starts") = py::none(), py::arg("pose_indices") = py::none(),
        py::arg("match") = "position", py::arg("marker") = 0,
        py::arg("position_tolerance_m") = 1e-9,
        py::arg("rotation_tolerance_rad") = 1e-9,
        py::arg("rotation_weight_m") = 1.0, py::arg("max_iterations") = 100,
        py::arg("singular_threshold") = 1e-6, py::arg("num_threads") = 0,
        "Compensates a program with the calibrated robot, as "
        "activecal_compensate: program (n, num_joints) taught with the "
        "Robot `nominal` -> the joints at which the calibrated robot "
        "reaches what each pose meant; or targets (n, 3) points in the "
        "device frame (rotations (n, 3) rotation vectors for match='pose'; "
        "starts (n, num_joints)). cell: a cell file: a configuration that "
        "collides or leaves a joint margin is status 'collision'. Targets "
        "that do not converge keep their "
        "status (all_converged False); bad input is a ValueError. The GIL "
        "is released while it runs.");

  m.def("evaluate", &EvaluatePy, py::arg("robot"), py::arg("measurements"),
        py::arg("parameters") = py::none(),
        "The errors of a model (robot's nominal, or `parameters`) on "
        "measurements, no fitting: a dict of statistics (m, rad).");
  m.def("iso9283", &Iso9283Py, py::arg("robot"), py::arg("path"),
        py::arg("parameters") = py::none(),
        "ISO 9283 pose accuracy and repeatability of the cycles in the "
        "measurements CSV `path` (pose label and commanded_* columns, "
        "docs/iso9283.md), in the base frame of the model (robot's nominal, "
        "or `parameters`): the dict activecal_evaluate --iso9283 writes "
        "under 'iso9283' in --json_out, the same numbers (poses[i].without "
        "/ .with: ap_p_m, rp_l_m, ap_abc_rad, ...). Bad input is a "
        "ValueError naming file, line and field.");

  BindExport(m);
  BindReport(m);
}
