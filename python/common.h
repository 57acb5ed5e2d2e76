// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Shared by the files of the Python module `activecal` (module.cc binds
// what they define): conversions between numpy and Eigen, errors, the
// arguments several files take (a Robot, a cell, Measurements), the
// Estimate, and each file's Bind function.
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

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_robot.h"

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

// What `get` gives for each of `items`, in order (a property's list).
template <typename Items, typename Get>
auto Each(const Items& items, Get get) {
  std::vector<std::decay_t<decltype(get(*std::begin(items)))>> out;
  for (const auto& item : items) out.push_back(get(item));
  return out;
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

// measurements_files.cc: `text` written to `path`, or a ValueError naming
// it; a Measurements argument, or a ValueError naming `what`.
void WriteText(const std::string& path, const std::string& text);
const Measurements& MeasurementsArg(const py::object& obj,
                                    const std::string& what);

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
