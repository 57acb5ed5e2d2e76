// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Shared by the files of the Python module `activecal` (module.cc binds
// what they define): conversions between numpy and Eigen, errors, the
// GIL-aware progress bridge, the result classes, and the declarations of
// each file's functions.
//
// Every function composes the library's free functions the way the
// programs under apps/ do, with the same defaults, so that a call gives
// the same numbers as the program for the same seed and options. Errors:
// the library's one-line messages, as ValueError (bad input) or
// RuntimeError (a solver that did not converge). The GIL is released
// around the long work (pool Jacobians, designs, identification); progress
// callbacks take it back while they run.

#ifndef ACTIVECAL_PYTHON_COMMON_H_
#define ACTIVECAL_PYTHON_COMMON_H_

#include <glog/logging.h>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/calibration/cell_planning.h"
#include "activecal/calibration/pool_builder.h"
#include "activecal/calibration/select_design.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/cell/tour.h"
#include "activecal/core/joint_sampling.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/lattice.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/estimate_warnings.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/model_selection.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/estimation/registration.h"
#include "activecal/estimation/registration_fit.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/targets_csv.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/kinematics/compensation.h"
#include "activecal/kinematics/inverse_kinematics.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/random_designs.h"
#include "activecal/selection/target_size.h"
#include "activecal/selection/task_approximate.h"
#include "activecal/selection/task_criterion.h"
#include "activecal/selection/task_exchange.h"

namespace py = pybind11;

namespace activecal {
namespace python {

// ---------------------------------------------------------------- helpers

[[noreturn]] inline void Fail(const std::string& message) {
  throw py::value_error(message);
}

inline std::string Shape(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    s += (d ? ", " : "") + std::to_string(a.shape(d));
  }
  return s + (a.ndim() == 1 ? ",)" : ")");
}

inline std::string Repr(const py::handle& obj) { return py::repr(obj); }

// `obj` as an array of doubles (any real numeric dtype, any sequence), or a
// ValueError naming `what`. Complex arrays are refused (numpy would drop
// the imaginary part with only a warning).
inline py::array_t<double, py::array::c_style> DoubleArray(
    const py::handle& obj, const std::string& what) {
  const py::array raw = py::array::ensure(obj);
  if (raw && raw.dtype().kind() == 'c') {
    Fail(what + ": expected real numbers, got dtype " +
         std::string(py::str(raw.dtype())));
  }
  auto a =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
          raw ? py::handle(raw) : obj);
  if (!a) Fail(what + ": expected an array of numbers");
  return a;
}

// `obj` as integers (markers, indices): a 1-D array of any integer dtype
// or a sequence of ints ([] is empty). Floats, bools, strings: a
// ValueError naming `what` and the dtype.
inline std::vector<int64_t> IntegerVector(const py::handle& obj,
                                          const std::string& what) {
  const py::array a = py::array::ensure(obj);
  if (!a) Fail(what + ": expected an array of integers");
  if (a.ndim() != 1) {
    Fail(what + ": expected a 1-D array of integers, got shape " + Shape(a));
  }
  if (a.size() == 0) return {};  // numpy makes [] float64
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u') {
    Fail(what + ": expected integers, got dtype " +
         std::string(py::str(a.dtype())));
  }
  const auto v =
      py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(
          a);
  if (!v) Fail(what + ": expected an array of integers");
  return std::vector<int64_t>(v.data(), v.data() + v.size());
}

// A path argument: str, bytes or os.PathLike (pathlib.Path), as os.fsdecode
// takes them; anything else is its TypeError.
inline std::string PathArg(const py::handle& obj) {
  return py::str(py::module_::import("os").attr("fsdecode")(obj));
}

// A (rows x cols) matrix from a 2-D array; a 1-D array of `cols` values is
// one row when allow_1d (*was_1d says so).
inline Eigen::MatrixXd MatrixArg(const py::handle& obj, const std::string& what,
                                 int cols, bool allow_1d,
                                 bool* was_1d = nullptr) {
  const auto a = DoubleArray(obj, what);
  if (was_1d) *was_1d = a.ndim() == 1;
  const std::string want =
      "an array of shape (n, " + std::to_string(cols) + ")" +
      (allow_1d ? " or (" + std::to_string(cols) + ",)" : "");
  if (a.ndim() == 1 && allow_1d) {
    if (a.shape(0) != cols) {
      Fail(what + ": expected " + std::to_string(cols) + " values, got " +
           std::to_string(a.shape(0)));
    }
    Eigen::MatrixXd m(1, cols);
    for (int c = 0; c < cols; ++c) m(0, c) = a.at(c);
    return m;
  }
  if (a.ndim() != 2 || a.shape(1) != cols) {
    Fail(what + ": expected " + want + ", got shape " + Shape(a));
  }
  const py::ssize_t rows = a.shape(0);
  // One copy, into the column-major matrix the library takes.
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                 Eigen::RowMajor>>
      view(a.data(), rows, cols);
  return Eigen::MatrixXd(view);
}

inline Eigen::VectorXd VectorArg(const py::handle& obj, const std::string& what,
                                 int size) {
  const auto a = DoubleArray(obj, what);
  if (a.ndim() != 1 || (size >= 0 && a.shape(0) != size)) {
    Fail(what + ": expected an array of shape (" + std::to_string(size) +
         ",), got shape " + Shape(a));
  }
  Eigen::VectorXd v(a.shape(0));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) v[i] = a.at(i);
  return v;
}

inline std::string Join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

// Refuses keyword arguments a function does not know (a misspelt option
// would otherwise be silently ignored).
inline void NoUnknownOptions(const char* function, const py::kwargs& kwargs,
                             const std::vector<std::string>& known = {}) {
  for (const auto& item : kwargs) {
    const std::string name = py::str(item.first);
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    Fail(std::string(function) + ": unknown option '" + name + "'" +
         (known.empty() ? "" : " (options: " + Join(known) + ")"));
  }
}

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

// --------------------------------------------------------------- classes

struct Robot {
  RobotDescription description;
  std::string path;  // "" for the built-in PUMA 560
  bool urdf = false;
  UrdfChainOptions chain;    // URDF: the chain's ends given to load_robot
  bool with_frames = false;  // load_robot's frames= gave the markers
  const RobotModel& model() const { return description.model; }
};
using RobotPtr = std::shared_ptr<Robot>;

// design.cc: the cell of the kwarg cell= (a path; None or absent: null),
// set up by the library (SetUpCell) on the robot as loaded; with
// targets_as_markers the cell's targets become the markers of *described
// (a copy of the robot's description; may be null when not wanted), as the
// programs do without --frames. The notes of the setup appended to *notes.
// A ValueError "cell: <file>:<line>:<col>: <field>: ..." for a bad cell
// file.
std::unique_ptr<CellSetup> CellArg(const Robot& robot, const py::kwargs& kwargs,
                                   std::vector<std::string>* notes,
                                   bool targets_as_markers = false,
                                   RobotDescription* described = nullptr);

inline Eigen::VectorXd ParametersArg(const Robot& robot,
                                     const py::object& obj) {
  if (obj.is_none()) return robot.model().nominal;
  Eigen::VectorXd p =
      VectorArg(obj, "parameters", robot.model().num_parameters());
  std::string error;
  if (!robot.model().CheckParameters(p, &error)) Fail("parameters: " + error);
  return p;
}

inline void CheckQ(const RobotModel& model, const Eigen::VectorXd& q, int row,
                   bool batch) {
  // Inside every range and finite: valid without building a message.
  bool inside = q.size() == model.num_joints();
  for (int j = 0; inside && j < q.size(); ++j) {
    const Link& link = model.links[j];
    inside =
        std::isfinite(q[j]) && q[j] >= link.joint_min && q[j] <= link.joint_max;
  }
  if (inside) return;
  std::string error;
  if (!model.CheckJointValues(q, &error, kMeasuredJointToleranceRad,
                              kMeasuredJointToleranceM)) {
    Fail(batch ? "q row " + std::to_string(row) + ": " + error : "q: " + error);
  }
}

// The model's parameter set by name (None: full for a URDF robot, file
// otherwise, as the programs).
inline ParameterSet ParameterSetArg(const Robot& robot, const py::object& obj) {
  ParameterSet set = robot.urdf ? ParameterSet::kFull : ParameterSet::kFile;
  if (obj.is_none()) return set;
  const std::string name = py::str(obj);
  if (!StringToParameterSet(name, &set)) {
    Fail("parameter_set must be registration, offsets, full or file, got '" +
         name + "'");
  }
  return set;
}

inline MeasurementType MeasurementTypeArg(const std::string& name,
                                          bool distance_ok,
                                          const std::string& what) {
  MeasurementType type;
  if (!ParseMeasurementType(name, &type) ||
      (!distance_ok && type == MeasurementType::kDistance)) {
    Fail(what + " must be position" +
         std::string(distance_ok ? ", pose or distance" : " or pose") +
         ", got '" + name + "'");
  }
  return type;
}

struct Measurements {
  std::vector<Measurement> items;
  std::vector<std::string> warnings;  // from the CSV reader
  std::vector<std::string> notes;
  int num_joints = 0;  // the joints' columns when there are no rows
};

// The markers of `items` against the robot, 0-based as the API counts
// them (the library's messages count from 1, as the CSV files do).
inline void CheckMarkers(const RobotModel& model,
                         const std::vector<Measurement>& items,
                         const std::string& what) {
  const int k = model.num_markers();
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i].marker < 0 || items[i].marker >= k) {
      Fail(what + " row " + std::to_string(i) + ": marker " +
           std::to_string(items[i].marker) +
           " is not a marker of the robot (it has " + std::to_string(k) +
           ", numbered from 0: " +
           (k == 1 ? std::string("0") : "0 to " + std::to_string(k - 1)) + ")");
    }
  }
}

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

struct EstimateResult {
  RobotPtr robot;  // the robot identified (its file's units)
  CalibrationSummary calibration;
  // The rows identified from and validated on, then the selection's
  // validation rows: write_urdf checks the written URDF against them.
  std::vector<Measurement> measurements;
  // activecal_identify's notes (the orientation hint, the rotation_weight
  // note), one line each.
  std::vector<std::string> notes;

  const IdentificationSummary& fit() const {
    return calibration.identification;
  }
  const RobotModel& model() const { return calibration.model; }
};

// A column of the measurements as an array; rows without it are NaN.
template <typename Get>
Eigen::MatrixXd Column(const Measurements& m, int cols, Get get) {
  Eigen::MatrixXd out(m.items.size(), cols);
  for (size_t i = 0; i < m.items.size(); ++i) {
    const Eigen::RowVectorXd row = get(m.items[i]);
    // Rows of another robot's joint count (Measurements joined with +):
    // NaN, not an out-of-bounds write.
    if (row.size() == cols) {
      out.row(i) = row;
    } else {
      out.row(i).setConstant(NAN);
    }
  }
  return out;
}

// identify's option `name` taken out of kwargs: `value` when absent or
// None, else the value converted to T or a ValueError naming what T takes.
template <typename T>
T Option(py::kwargs& kwargs, const char* name, T value) {
  if (kwargs.contains(name)) {
    const py::object given = kwargs[name];
    if (!given.is_none()) {
      try {
        value = py::cast<T>(given);
      } catch (const py::cast_error&) {
        const char* want =
            std::is_same<T, std::string>::value ? "a string"
            : std::is_same<T, bool>::value      ? "True or False"
            : std::is_integral<T>::value && std::is_unsigned<T>::value
                ? "a non-negative integer"
            : std::is_integral<T>::value ? "an integer"
                                         : "a number";
        Fail(std::string("identify: option ") + name + ": expected " + want +
             ", got " + Repr(given));
      }
    }
    PyDict_DelItemString(kwargs.ptr(), name);
  }
  return value;
}

struct CompensationResult {
  CompensationSummary summary;
  RobotPtr robot;
  std::vector<int64_t> pose_indices;
  Eigen::MatrixXd starts;  // the program, or the targets' starts
};

// robot.cc: Robot: load_robot, puma560, forward, frame, jacobian,
// with_parameter_set, save.
RobotPtr LoadRobotPy(const py::object& path, const py::object& base_link,
                     const py::object& tip_link, const py::object& frames);

RobotPtr Puma560();

py::array_t<bool> FreeFlags(const RobotModel& model);

py::array_t<double> Forward(const Robot& robot, const py::object& q_obj,
                            const py::object& parameters, int marker);

Eigen::Matrix4d Frame(const Robot& robot, const py::object& q_obj,
                      const py::object& parameters, int marker);

py::array_t<double> JacobianPy(const Robot& robot, const py::object& q_obj,
                               const py::object& parameters, int marker,
                               const std::string& type_name,
                               double rotation_weight);

RobotPtr WithParameterSet(const Robot& robot, const std::string& name,
                          const std::string& measurement);

// Robot.perturbed: PerturbParameters (core/simulation.h).
Eigen::VectorXd PerturbedPy(const Robot& robot, double perturb_m,
                            double perturb_rad, uint64_t seed,
                            const py::object& parameters);
void SaveRobot(const Robot& robot, const py::object& path,
               const py::object& parameters);

// Pickling: a Robot as its robot file text (radians, true values) with its
// path and kind; Measurements as arrays.
py::tuple RobotState(const Robot& robot);
RobotPtr RobotFromState(const py::tuple& state);
py::tuple MeasurementsState(const Measurements& m);
Measurements MeasurementsFromState(const py::tuple& state);

// measurements_files.cc: Files (measurements, poses, targets CSV),
// Measurements, simulate.
void WriteText(const std::string& path, const std::string& text);

Measurements ReadMeasurementsPy(const Robot& robot, const py::object& path,
                                bool strict_limits, bool columns_strict,
                                const py::object& column_map);

void WriteMeasurementsPy(const Robot& robot, const py::object& path,
                         const Measurements& m, bool millimetres,
                         bool joint_degrees, bool joint_names,
                         const std::string& orientation);

py::tuple ReadPosesPy(const Robot& robot, const py::object& path,
                      bool reject_duplicates);

py::tuple ReadTargetsPy(const Robot& robot, const py::object& path);

void WritePosesPy(const Robot& robot, const py::object& path,
                  const py::object& joints, const py::object& indices);

Measurements MakeMeasurements(
    const std::string& type_name, const py::object& joints_obj,
    const py::object& positions, const py::object& rotations,
    const py::object& joints2, const py::object& distances,
    const py::object& markers, const py::object& sigma_m,
    const py::object& sigma_rad);

const Measurements& MeasurementsArg(const py::object& obj,
                                    const std::string& what);

int NumJoints(const Measurements& m);

Measurements Subset(const Measurements& m, const py::object& key);

Measurements SimulatePy(const Robot& robot, const py::object& joint_angles,
                        double noise_m, uint64_t seed,
                        const std::string& type_name, double rotation_noise_rad,
                        const py::object& parameters, const py::kwargs& kwargs);

// design.cc: select: the pool, the task and the design, by the library
// (selection_pool.h, select_design.h).
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
    const py::kwargs& kwargs);

py::array_t<double> HistoryLog10(const SelectionSummary& s);

// identify.cc: identify and evaluate.
std::shared_ptr<EstimateResult> IdentifyPy(const RobotPtr& robot_ptr,
                                           const Measurements& measurements,
                                           py::kwargs kwargs);

std::string EstimateFileText(const EstimateResult& e);
// The learned residual's summary as a dict (None when it was off).
py::object LearnedResidualPy(const EstimateResult& e);

RobotPtr CalibratedRobot(const EstimateResult& e);

py::dict Stats(const ErrorStatistics& s);

py::dict EvaluatePy(const Robot& robot, const Measurements& measurements,
                    const py::object& parameters);
// The ISO 9283 figures of a cycles file (activecal_evaluate --iso9283):
// the JSON's "iso9283" object as a dict.
py::object Iso9283Py(const Robot& robot, const std::string& path,
                     const py::object& parameters);

// compensate.cc: compensate.
std::shared_ptr<CompensationResult> CompensatePy(
    const RobotPtr& robot, const py::object& program, const py::object& nominal,
    const py::object& targets, const py::object& rotations,
    const py::object& starts, const py::object& pose_indices,
    const std::string& match, int marker, double position_tolerance_m,
    double rotation_tolerance_rad, double rotation_weight_m, int max_iterations,
    double singular_threshold, int num_threads, const py::kwargs& kwargs);

// The module's classes and functions, one area a file (module.cc calls
// them in this order: a class is bound before the functions that return it).
void BindRobot(py::module_& m);         // robot.cc: Robot, load_robot, puma560
void BindMeasurements(py::module_& m);  // measurements_files.cc: Measurements,
                                        // the CSV readers/writers, simulate
void BindDesign(py::module_& m);        // design.cc: Design, select
void BindIdentify(py::module_& m);      // identify.cc: Estimate, identify,
                                        // evaluate, iso9283
void BindCompensate(py::module_& m);  // compensate.cc: Compensation, compensate
// export.cc: Estimate.write_urdf, write_frames, write_ros_frames and
// read_ros_frames, added to the module's classes.
void BindExport(py::module_& m);
void BindReport(py::module_& m);  // report.cc: Estimate.write_report

}  // namespace python
}  // namespace activecal

#endif  // ACTIVECAL_PYTHON_COMMON_H_
