// The Python module `activecal`: thin pybind11 bindings over the library,
// numpy in and out (docs/python.md).
//
// Every function composes the library's free functions the way the
// programs under apps/ do, with the same defaults, so that a call gives
// the same numbers as the program for the same seed and options. Errors:
// the library's one-line messages, as ValueError (bad input) or
// RuntimeError (a solver that did not converge). The GIL is released
// around the long work (pool Jacobians, designs, identification); progress
// callbacks take it back while they run.

#include <glog/logging.h>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "activecal/core/csv_files.h"
#include "activecal/core/evaluation.h"
#include "activecal/core/joint_sampling.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/lattice.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/registration.h"
#include "activecal/core/robot_file.h"
#include "activecal/core/robot_loader.h"
#include "activecal/core/simulation.h"
#include "activecal/core/targets_csv.h"
#include "activecal/residuals/compensation.h"
#include "activecal/residuals/estimate_warnings.h"
#include "activecal/residuals/identification.h"
#include "activecal/residuals/inverse_kinematics.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/residuals/model_selection.h"
#include "activecal/residuals/parameter_reduction.h"
#include "activecal/residuals/pool_builder.h"
#include "activecal/residuals/registration_fit.h"
#include "activecal/residuals/selection_pool.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/random_designs.h"
#include "activecal/selection/select_design.h"
#include "activecal/selection/target_size.h"
#include "activecal/selection/task_approximate.h"
#include "activecal/selection/task_criterion.h"
#include "activecal/selection/task_exchange.h"

namespace py = pybind11;

namespace activecal {
namespace python {
namespace {

// ---------------------------------------------------------------- helpers

[[noreturn]] void Fail(const std::string& message) {
  throw py::value_error(message);
}

std::string Shape(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    s += (d ? ", " : "") + std::to_string(a.shape(d));
  }
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// `obj` as an array of doubles (any numeric dtype, any sequence), or a
// ValueError naming `what`.
py::array_t<double, py::array::c_style> DoubleArray(const py::handle& obj,
                                                    const std::string& what) {
  auto a =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
          obj);
  if (!a) Fail(what + ": expected an array of numbers");
  return a;
}

// A (rows x cols) matrix from a 2-D array; a 1-D array of `cols` values is
// one row when allow_1d (*was_1d says so).
Eigen::MatrixXd MatrixArg(const py::handle& obj, const std::string& what,
                          int cols, bool allow_1d, bool* was_1d = nullptr) {
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

Eigen::VectorXd VectorArg(const py::handle& obj, const std::string& what,
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

std::string Join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

// Refuses keyword arguments a function does not know (a misspelt option
// would otherwise be silently ignored).
void NoUnknownOptions(const char* function, const py::kwargs& kwargs,
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
  const RobotModel& model() const { return description.model; }
};
using RobotPtr = std::shared_ptr<Robot>;

Eigen::VectorXd ParametersArg(const Robot& robot, const py::object& obj) {
  if (obj.is_none()) return robot.model().nominal;
  Eigen::VectorXd p =
      VectorArg(obj, "parameters", robot.model().num_parameters());
  std::string error;
  if (!robot.model().CheckParameters(p, &error)) Fail("parameters: " + error);
  return p;
}

void CheckQ(const RobotModel& model, const Eigen::VectorXd& q, int row,
            bool batch) {
  std::string error;
  if (!model.CheckJointValues(q, &error, kMeasuredJointToleranceRad,
                              kMeasuredJointToleranceM)) {
    Fail(batch ? "q row " + std::to_string(row) + ": " + error : "q: " + error);
  }
}

// The model's parameter set by name (None: full for a URDF robot, file
// otherwise, as the programs).
ParameterSet ParameterSetArg(const Robot& robot, const py::object& obj) {
  ParameterSet set = robot.urdf ? ParameterSet::kFull : ParameterSet::kFile;
  if (obj.is_none()) return set;
  const std::string name = py::str(obj);
  if (!ParseParameterSet(name, &set)) {
    Fail("parameter_set must be registration, offsets, full or file, got '" +
         name + "'");
  }
  return set;
}

MeasurementType MeasurementTypeArg(const std::string& name, bool distance_ok,
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
};

struct EstimateResult {
  RobotPtr robot;    // the robot identified (its file's units)
  RobotModel model;  // the model fitted (free flags as reduced)
  IdentificationSummary summary;
  std::vector<std::string> held_fixed;  // reduced, auto-fixed, dropped
  std::vector<std::string> warnings;
  bool registered_base = false;
  bool have_baseline = false;
  double registration_only_rms_m = 0;
  std::string parameter_set;
  ModelSelectionSummary selection;
  std::string model_selection;
};

// ------------------------------------------------------------- load_robot

RobotPtr LoadRobotPy(const std::string& path, const py::object& base_link,
                     const py::object& tip_link, const py::object& frames) {
  RobotLoadOptions options;
  if (!base_link.is_none()) options.chain.base_link = py::str(base_link);
  if (!tip_link.is_none()) options.chain.tip_link = py::str(tip_link);
  if (!frames.is_none()) options.frames_path = py::str(frames);
  auto robot = std::make_shared<Robot>();
  std::string error;
  if (!LoadRobot(path, options, &robot->description, &error)) Fail(error);
  robot->path = path;
  robot->urdf = IsUrdfPath(path);
  return robot;
}

RobotPtr Puma560() {
  auto robot = std::make_shared<Robot>();
  robot->description.model = Puma560PaperModel();
  robot->description.true_parameters = Puma560TrueParameters();
  return robot;
}

py::array_t<bool> FreeFlags(const RobotModel& model) {
  py::array_t<bool> flags(model.num_parameters());
  auto f = flags.mutable_unchecked<1>();
  for (int i = 0; i < model.num_parameters(); ++i) f(i) = model.IsFree(i);
  return flags;
}

// forward(q): the measured point (m) at joint readings q, (3,) or (n, 3).
py::array_t<double> Forward(const Robot& robot, const py::object& q_obj,
                            const py::object& parameters, int marker) {
  const RobotModel& model = robot.model();
  if (marker < 0 || marker >= model.num_markers()) {
    Fail("marker must be in [0, " + std::to_string(model.num_markers() - 1) +
         "], got " + std::to_string(marker));
  }
  bool one = false;
  const Eigen::MatrixXd q =
      MatrixArg(q_obj, "q", model.num_joints(), true, &one);
  const Eigen::VectorXd p = ParametersArg(robot, parameters);
  for (int r = 0; r < q.rows(); ++r) CheckQ(model, q.row(r), r, !one);
  py::array_t<double> out =
      one ? py::array_t<double>(3)
          : py::array_t<double>({static_cast<py::ssize_t>(q.rows()),
                                 static_cast<py::ssize_t>(3)});
  double* o = out.mutable_data();
  {
    // `out` is not shared yet: filled without the GIL.
    py::gil_scoped_release release;
    for (int r = 0; r < q.rows(); ++r) {
      const Eigen::Vector3d x =
          MeasuredPoint(model, p, q.row(r).transpose(), marker);
      for (int k = 0; k < 3; ++k) o[3 * r + k] = x[k];
    }
  }
  return out;
}

// frame(q): the 4 x 4 transform of the measured target frame.
Eigen::Matrix4d Frame(const Robot& robot, const py::object& q_obj,
                      const py::object& parameters, int marker) {
  const RobotModel& model = robot.model();
  if (marker < 0 || marker >= model.num_markers()) {
    Fail("marker must be in [0, " + std::to_string(model.num_markers() - 1) +
         "], got " + std::to_string(marker));
  }
  const Eigen::VectorXd q =
      MatrixArg(q_obj, "q", model.num_joints(), true).row(0).transpose();
  if (DoubleArray(q_obj, "q").ndim() != 1) {
    Fail("q: frame takes one pose, an array of shape (" +
         std::to_string(model.num_joints()) + ",)");
  }
  CheckQ(model, q, 0, false);
  const Eigen::VectorXd p = ParametersArg(robot, parameters);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  TargetFrame(model, p, q, &R, &t, marker);
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = R;
  T.topRightCorner<3, 1>() = t;
  return T;
}

// jacobian(q): d(measurement)/d(free parameters), (rows, num_free) or
// (n, rows, num_free); rows 3 (position) or 6 (pose).
py::array_t<double> JacobianPy(const Robot& robot, const py::object& q_obj,
                               const py::object& parameters, int marker,
                               const std::string& type_name,
                               double rotation_weight) {
  const RobotModel& model = robot.model();
  const MeasurementType type = MeasurementTypeArg(type_name, false, "type");
  if (marker < 0 || marker >= model.num_markers()) {
    Fail("marker must be in [0, " + std::to_string(model.num_markers() - 1) +
         "], got " + std::to_string(marker));
  }
  bool one = false;
  const Eigen::MatrixXd q =
      MatrixArg(q_obj, "q", model.num_joints(), true, &one);
  const Eigen::VectorXd p = ParametersArg(robot, parameters);
  for (int r = 0; r < q.rows(); ++r) CheckQ(model, q.row(r), r, !one);
  const int rows = MeasurementDimension(type);
  const int cols = model.num_free();
  std::vector<py::ssize_t> shape;
  if (!one) shape.push_back(q.rows());
  shape.push_back(rows);
  shape.push_back(cols);
  py::array_t<double> out(shape);
  double* o = out.mutable_data();
  std::string error;
  {
    // `out` is not shared yet: filled without the GIL.
    py::gil_scoped_release release;
    for (int r = 0; r < q.rows() && error.empty(); ++r) {
      Measurement m;
      m.type = type;
      m.marker = marker;
      m.joints = q.row(r).transpose();
      Eigen::MatrixXd J;
      if (!MeasurementJacobian(model, p, m, rotation_weight, &J, &error)) {
        break;
      }
      for (int i = 0; i < rows; ++i) {
        for (int c = 0; c < cols; ++c) o[(r * rows + i) * cols + c] = J(i, c);
      }
    }
  }
  if (!error.empty()) Fail(error);
  return out;
}

RobotPtr WithParameterSet(const Robot& robot, const std::string& name,
                          const std::string& measurement) {
  ParameterSet set;
  if (!ParseParameterSet(name, &set)) {
    Fail("parameter_set must be registration, offsets, full or file, got '" +
         name + "'");
  }
  const MeasurementType type =
      MeasurementTypeArg(measurement, true, "measurement");
  auto out = std::make_shared<Robot>(robot);
  if (set != ParameterSet::kFile) {
    ApplyParameterSet(set, type == MeasurementType::kPose,
                      &out->description.model);
  }
  return out;
}

void SaveRobot(const Robot& robot, const std::string& path,
               const py::object& parameters) {
  RobotFileOptions options;
  options.angle_unit = robot.description.angle_unit;
  options.true_parameters = robot.description.true_parameters;
  const std::string text =
      RobotFileText(robot.model(), ParametersArg(robot, parameters), options);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out || !(out << text) || !out.flush()) {
    Fail("cannot write '" + path + "'");
  }
}

// ------------------------------------------------------------ files

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.flush();
  if (!out) Fail("cannot write '" + path + "'");
}

Measurements ReadMeasurementsPy(const Robot& robot, const std::string& path,
                                bool strict_limits, bool columns_strict) {
  MeasurementsCsvOptions options;
  options.strict_limits = strict_limits;
  options.columns_strict = columns_strict;
  Measurements m;
  MeasurementsCsvReport report;
  std::string error;
  if (!ReadMeasurementsCsv(path, robot.model(), options, &m.items, &report,
                           &error)) {
    Fail(error);
  }
  m.warnings = report.warnings;
  m.notes = report.notes;
  return m;
}

void WriteMeasurementsPy(const Robot& robot, const std::string& path,
                         const Measurements& m, bool millimetres,
                         bool joint_degrees, bool joint_names,
                         const std::string& orientation) {
  MeasurementsCsvFormat format;
  format.millimetres = millimetres;
  format.joint_degrees = joint_degrees;
  format.joint_names = joint_names;
  if (orientation == "rotation_vector") {
    format.orientation = OrientationFormat::kRotationVector;
  } else if (orientation == "quaternion") {
    format.orientation = OrientationFormat::kQuaternion;
  } else if (orientation == "rpy_rad") {
    format.orientation = OrientationFormat::kRpyRad;
  } else if (orientation == "rpy_deg") {
    format.orientation = OrientationFormat::kRpyDeg;
  } else {
    Fail(
        "orientation must be rotation_vector, quaternion, rpy_rad or "
        "rpy_deg, got '" +
        orientation + "'");
  }
  for (size_t i = 0; i < m.items.size(); ++i) {
    std::string error;
    if (!CheckMeasurement(robot.model(), m.items[i], &error)) {
      Fail("measurement " + std::to_string(i) + ": " + error);
    }
  }
  WriteText(path, MeasurementsCsvText(robot.model(), m.items, format));
}

py::tuple ReadPosesPy(const Robot& robot, const std::string& path,
                      bool reject_duplicates) {
  PoseList list;
  std::string error;
  if (!ReadPosesCsv(path, robot.model(), reject_duplicates, &list, &error)) {
    Fail(error);
  }
  return py::make_tuple(list.joints, py::array(py::cast(list.pose_indices)));
}

// A Cartesian targets CSV (targets_csv.h): points, rotation vectors and
// start joints when the file has them (else None), pose indices.
py::tuple ReadTargetsPy(const Robot& robot, const std::string& path) {
  TargetList list;
  std::string error;
  if (!ReadTargetsCsv(path, robot.model(), &list, &error)) Fail(error);
  auto or_none = [](const Eigen::MatrixXd& m) -> py::object {
    if (m.rows() == 0) return py::none();
    return py::cast(m);
  };
  return py::make_tuple(list.points, or_none(list.rotation_vectors),
                        or_none(list.start_joints),
                        py::array(py::cast(list.pose_indices)));
}

void WritePosesPy(const Robot& robot, const std::string& path,
                  const py::object& joints, const py::object& indices) {
  const RobotModel& model = robot.model();
  PoseList list;
  list.joints = MatrixArg(joints, "joint_angles", model.num_joints(), false);
  if (indices.is_none()) {
    for (int64_t i = 0; i < list.joints.rows(); ++i) {
      list.pose_indices.push_back(i);
    }
  } else {
    list.pose_indices = py::cast<std::vector<int64_t>>(indices);
    if (static_cast<int64_t>(list.pose_indices.size()) != list.joints.rows()) {
      Fail("pose_indices: expected " + std::to_string(list.joints.rows()) +
           " values (one per pose), got " +
           std::to_string(list.pose_indices.size()));
    }
  }
  for (int r = 0; r < list.joints.rows(); ++r) {
    std::string error;
    if (!model.CheckJointValues(list.joints.row(r).transpose(), &error)) {
      Fail("joint_angles row " + std::to_string(r) + ": " + error);
    }
  }
  WriteText(path, PosesCsvText(model, list));
}

// --------------------------------------------------------- measurements

Measurements MakeMeasurements(
    const std::string& type_name, const py::object& joints_obj,
    const py::object& positions, const py::object& rotations,
    const py::object& joints2, const py::object& distances,
    const py::object& markers, const py::object& sigma_m,
    const py::object& sigma_rad) {
  const MeasurementType type = MeasurementTypeArg(type_name, true, "type");
  const auto ja = DoubleArray(joints_obj, "joints");
  if (ja.ndim() != 2) {
    Fail("joints: expected an array of shape (n, num_joints), got shape " +
         Shape(ja));
  }
  const int n = static_cast<int>(ja.shape(0));
  const int nj = static_cast<int>(ja.shape(1));
  const Eigen::MatrixXd J = MatrixArg(joints_obj, "joints", nj, false);
  auto need = [&](const py::object& o, const char* name) {
    if (o.is_none()) {
      Fail(std::string("type=") + type_name + " needs " + name);
    }
  };
  Eigen::MatrixXd P, Rv, J2, S;
  Eigen::VectorXd D, SR;
  if (type != MeasurementType::kDistance) {
    need(positions, "positions");
    P = MatrixArg(positions, "positions", 3, false);
    if (P.rows() != n)
      Fail("positions: expected " + std::to_string(n) +
           " rows (one per measurement), got " + std::to_string(P.rows()));
  }
  if (type == MeasurementType::kPose) {
    need(rotations, "rotations");
    Rv = MatrixArg(rotations, "rotations", 3, false);
    if (Rv.rows() != n)
      Fail("rotations: expected " + std::to_string(n) + " rows, got " +
           std::to_string(Rv.rows()));
  }
  if (type == MeasurementType::kDistance) {
    need(joints2, "joints2");
    need(distances, "distances");
    J2 = MatrixArg(joints2, "joints2", nj, false);
    if (J2.rows() != n)
      Fail("joints2: expected " + std::to_string(n) + " rows, got " +
           std::to_string(J2.rows()));
    D = VectorArg(distances, "distances", n);
  }
  if (!sigma_m.is_none()) {
    S = MatrixArg(sigma_m, "sigma_m", 3, false);
    if (S.rows() != n)
      Fail("sigma_m: expected " + std::to_string(n) + " rows, got " +
           std::to_string(S.rows()));
  }
  if (!sigma_rad.is_none()) SR = VectorArg(sigma_rad, "sigma_rad", n);
  std::vector<int> mk;
  if (!markers.is_none()) {
    mk = py::cast<std::vector<int>>(markers);
    if (static_cast<int>(mk.size()) != n) {
      Fail("markers: expected " + std::to_string(n) + " values, got " +
           std::to_string(mk.size()));
    }
  }
  Measurements out;
  out.items.resize(n);
  for (int i = 0; i < n; ++i) {
    Measurement& m = out.items[i];
    m.type = type;
    m.joints = J.row(i).transpose();
    if (P.size()) m.position = P.row(i).transpose();
    if (Rv.size()) m.rotation = Rv.row(i).transpose();
    if (J2.size()) m.joints2 = J2.row(i).transpose();
    if (D.size()) m.distance = D[i];
    if (S.size()) m.sigma_m = S.row(i).transpose();
    if (SR.size()) m.sigma_rad = SR[i];
    if (!mk.empty()) m.marker = mk[i];
  }
  return out;
}

const Measurements& MeasurementsArg(const py::object& obj,
                                    const std::string& what) {
  if (!py::isinstance<Measurements>(obj)) {
    Fail(what + ": expected activecal.Measurements, got " +
         std::string(py::str(py::type::of(obj).attr("__name__"))));
  }
  return py::cast<const Measurements&>(obj);
}

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

int NumJoints(const Measurements& m) {
  return m.items.empty() ? 0 : static_cast<int>(m.items[0].joints.size());
}

Measurements Subset(const Measurements& m, const py::object& key) {
  const int64_t n = static_cast<int64_t>(m.items.size());
  std::vector<int64_t> index;
  if (py::isinstance<py::slice>(key)) {
    py::ssize_t start, stop, step, length;
    if (!py::cast<py::slice>(key).compute(n, &start, &stop, &step, &length)) {
      throw py::error_already_set();
    }
    for (py::ssize_t k = 0; k < length; ++k) index.push_back(start + k * step);
  } else {
    py::array a = py::array::ensure(key);
    if (!a) Fail("measurements index: expected an int, a slice or an array");
    if (a.dtype().kind() == 'b') {
      auto b = py::array_t<bool>::ensure(a);
      if (b.ndim() != 1 || b.shape(0) != n) {
        Fail("measurements index: a boolean mask needs shape (" +
             std::to_string(n) + ",), got shape " + Shape(a));
      }
      for (int64_t i = 0; i < n; ++i) {
        if (b.at(i)) index.push_back(i);
      }
    } else if (a.dtype().kind() == 'i' || a.dtype().kind() == 'u') {
      auto v = py::array_t<int64_t, py::array::forcecast>::ensure(a);
      if (v.ndim() > 1) Fail("measurements index: expected a 1-D array");
      for (py::ssize_t k = 0; k < v.size(); ++k) {
        int64_t i = v.data()[k];
        if (i < 0) i += n;
        if (i < 0 || i >= n) {
          throw py::index_error(
              "measurement index " + std::to_string(v.data()[k]) +
              " out of range for " + std::to_string(n) + " measurements");
        }
        index.push_back(i);
      }
    } else {
      Fail("measurements index: expected an int, a slice or an array");
    }
  }
  Measurements out;
  for (int64_t i : index) out.items.push_back(m.items[i]);
  return out;
}

// ------------------------------------------------------------- simulate

Measurements SimulatePy(const Robot& robot, const py::object& joint_angles,
                        double noise_m, uint64_t seed,
                        const std::string& type_name, double rotation_noise_rad,
                        const py::object& parameters,
                        const py::kwargs& kwargs) {
  NoUnknownOptions("simulate", kwargs);
  const RobotModel& model = robot.model();
  const MeasurementType type = MeasurementTypeArg(type_name, true, "type");
  Eigen::VectorXd truth;
  if (parameters.is_none()) {
    if (robot.description.true_parameters.size() != model.num_parameters()) {
      Fail("robot '" + robot.path +
           "' has no true values to simulate from: add 'true:' entries to "
           "its blocks (docs/formats.md) or pass parameters=");
    }
    truth = robot.description.true_parameters;
  } else {
    truth = ParametersArg(robot, parameters);
  }
  const Eigen::MatrixXd joints =
      MatrixArg(joint_angles, "joint_angles", model.num_joints(), false);
  // The plan as activecal_simulate makes it from a poses file.
  std::vector<Measurement> plan;
  const int n = static_cast<int>(joints.rows());
  if (type == MeasurementType::kDistance) {
    if (n < 2) {
      Fail("type=distance needs at least 2 poses, got " + std::to_string(n));
    }
    for (int i = 0; i + 1 < n; ++i) {
      if (joints.row(i) == joints.row(i + 1)) {
        Fail("type=distance: poses " + std::to_string(i) + " and " +
             std::to_string(i + 1) +
             " (rows of joint_angles) are identical: a distance between "
             "them measures nothing; remove one");
      }
      Measurement m;
      m.type = type;
      m.joints = joints.row(i).transpose();
      m.joints2 = joints.row(i + 1).transpose();
      plan.push_back(m);
    }
  } else {
    plan = MeasurementPlan(joints, type);
  }
  SimulationNoise noise;
  noise.position_m = noise_m;
  noise.rotation_rad = rotation_noise_rad;
  Measurements out;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = SimulateMeasurements(model, truth, plan, noise, seed, &out.items,
                              &error);
  }
  if (!ok) Fail(error);
  return out;
}

// --------------------------------------------------------------- select

std::shared_ptr<DesignResult> SelectPy(
    const Robot& robot, std::string algorithm, int num_poses, uint64_t seed,
    int levels, const py::object& pool_obj, const std::string& criterion,
    int64_t pool_size, const py::object& pool_indices,
    const std::string& measurement, double rotation_weight,
    const py::object& parameter_set, bool auto_fix, int restarts,
    int initial_poses, int random_designs, bool certificate,
    double approx_tolerance, int64_t polish_pool_size, double noise_m,
    const py::object& task_poses, const py::object& measured,
    const py::object& target_rms_m, int num_threads, const py::object& progress,
    const py::kwargs& kwargs) {
  NoUnknownOptions("select", kwargs);
  Progress bridge(progress);
  auto result = std::make_shared<DesignResult>();
  RobotModel model = robot.model();
  const MeasurementType type =
      MeasurementTypeArg(measurement, false, "measurement");

  // The candidate poses: a lattice, sampled, or given.
  Eigen::MatrixXd pool_joints;
  std::vector<int64_t> labels;
  std::string pool_kind = "lattice";
  if (!pool_obj.is_none() && py::isinstance<py::str>(pool_obj)) {
    pool_kind = py::str(pool_obj);
  } else if (!pool_obj.is_none()) {
    pool_kind = "array";
  }
  if (pool_kind == "lattice") {
    JointLattice lattice;
    std::string error;
    if (!JointLattice::Create(model, levels, &lattice, &error)) {
      Fail("levels=" + std::to_string(levels) + ": " + error);
    }
    for (int j = 0; j < model.num_joints(); ++j) {
      if (lattice.one_turn(j)) {
        result->notes.push_back(
            "joint " + std::to_string(j + 1) + " (" + model.block_name(j + 1) +
            ") spans a full turn: its " + std::to_string(levels) +
            " levels cover one turn (both ends would repeat a pose)");
      }
    }
    pool_joints = lattice.AllJointValues();
  } else if (pool_kind == "array") {
    pool_joints = MatrixArg(pool_obj, "pool", model.num_joints(), false);
    if (!pool_indices.is_none()) {
      labels = py::cast<std::vector<int64_t>>(pool_indices);
      if (static_cast<int64_t>(labels.size()) != pool_joints.rows()) {
        Fail("pool_indices: expected " + std::to_string(pool_joints.rows()) +
             " values (one per pool pose), got " +
             std::to_string(labels.size()));
      }
    }
  } else {
    JointSampling sampling;
    if (!JointSamplingFromString(pool_kind, &sampling)) {
      Fail(
          "pool must be 'lattice', 'sobol', 'random' or an array of joint "
          "values, got '" +
          pool_kind + "'");
    }
    std::string error;
    if (!SampleJointValues(model, sampling, pool_size, seed, &pool_joints,
                           &error)) {
      Fail("pool=" + pool_kind + ": " + error);
    }
  }
  if (!pool_indices.is_none() && pool_kind != "array") {
    Fail("pool_indices label a pool given as an array; pool is '" + pool_kind +
         "'");
  }
  const bool with_target = !target_rms_m.is_none();
  const double target_rms = with_target ? py::cast<double>(target_rms_m) : 0.0;
  if (with_target && (!(target_rms > 0) || !std::isfinite(target_rms))) {
    Fail("target_rms_m must be > 0 (m)");
  }
  std::vector<Measurement> measured_items;
  if (!measured.is_none()) {
    measured_items = MeasurementsArg(measured, "measured").items;
  }
  if (!with_target && (num_poses <= 0 || num_poses > pool_joints.rows())) {
    Fail("num_poses must be in [1, " + std::to_string(pool_joints.rows()) +
         "] (the pool size), got " + std::to_string(num_poses));
  }
  SelectDesignOptions options;
  options.algorithm = algorithm;
  options.criterion = criterion;
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
      for (const DroppedParameter& d : pool_summary.dropped) {
        result->notes.push_back(
            "parameter_set=" +
            std::string(ParameterSetName(pool_options.parameter_set)) + ": " +
            d.name + " held fixed: " + d.reason);
      }
      if (!pool_built) {
        const IdentifiabilityReport& report = pool_summary.pool.identifiability;
        if (!pool_summary.reduction_failed && !report.identifiable() &&
            report.num_free > 0) {
          failure = "the pool: " + report.Message();
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
      result->auto_fixed = pool_summary.HeldFixed();
      for (const std::string& f : pool_summary.pool.fixed_names) {
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
  return result;
}

// ------------------------------------------------------------- identify

template <typename T>
T Option(py::kwargs& kwargs, const char* name, T value) {
  if (kwargs.contains(name)) {
    try {
      value = py::cast<T>(kwargs[name]);
    } catch (const py::cast_error&) {
      Fail(std::string("identify: option ") + name + ": expected a " +
           (std::is_same<T, std::string>::value ? "string"
            : std::is_same<T, bool>::value      ? "bool"
                                                : "number") +
           ", got " + std::string(py::str(kwargs[name])));
    }
    PyDict_DelItemString(kwargs.ptr(), name);
  }
  return value;
}

std::shared_ptr<EstimateResult> IdentifyPy(const RobotPtr& robot_ptr,
                                           const Measurements& measurements,
                                           py::kwargs kwargs) {
  const Robot& robot = *robot_ptr;
  // A copy: the options are taken out as read, what is left is unknown.
  kwargs = py::reinterpret_steal<py::kwargs>(PyDict_Copy(kwargs.ptr()));
  const std::string parameter_set_name =
      Option<std::string>(kwargs, "parameter_set", "");
  const bool register_base = Option(kwargs, "register_base", true);
  const bool auto_fix = Option(kwargs, "auto_fix", false);
  const std::string model_selection =
      Option<std::string>(kwargs, "model_selection", "cv");
  const int folds = Option(kwargs, "folds", 5);
  const std::string ranking =
      Option<std::string>(kwargs, "selection_ranking", "significance");
  const std::string robust_loss =
      Option<std::string>(kwargs, "robust_loss", "none");
  const double robust_scale_m = Option(kwargs, "robust_scale_m", 0.0);
  const double outlier_threshold = Option(kwargs, "outlier_threshold", 4.0);
  const double rotation_weight = Option(kwargs, "rotation_weight", 1.0);
  const double default_sigma_m = Option(kwargs, "default_sigma_m", 0.0);
  const double default_sigma_rad = Option(kwargs, "default_sigma_rad", 0.0);
  const double prior_std_m = Option(kwargs, "prior_std_m", 0.0);
  const double prior_std_rad = Option(kwargs, "prior_std_rad", 0.0);
  const uint64_t seed = Option<uint64_t>(kwargs, "seed", 1);
  const int num_threads = Option(kwargs, "num_threads", 0);
  py::object validation_obj = py::none();
  if (kwargs.contains("validation")) {
    validation_obj = kwargs["validation"];
    PyDict_DelItemString(kwargs.ptr(), "validation");
  }
  NoUnknownOptions(
      "identify", kwargs,
      {"parameter_set", "register_base", "auto_fix", "model_selection", "folds",
       "selection_ranking", "validation", "robust_loss", "robust_scale_m",
       "outlier_threshold", "rotation_weight", "default_sigma_m",
       "default_sigma_rad", "prior_std_m", "prior_std_rad", "seed",
       "num_threads"});
  std::vector<Measurement> selection_validation;
  if (!validation_obj.is_none()) {
    selection_validation = MeasurementsArg(validation_obj, "validation").items;
  }

  auto result = std::make_shared<EstimateResult>();
  result->robot = robot_ptr;
  RobotModel model = robot.model();
  const std::vector<Measurement>& training = measurements.items;
  if (training.empty()) Fail("identify: no measurements");

  IdentificationOptions options;
  if (!ParseRobustLoss(robust_loss, &options.robust_loss)) {
    Fail("robust_loss must be none, huber or cauchy, got '" + robust_loss +
         "'");
  }
  options.robust_scale_m = robust_scale_m;
  options.outlier_threshold = outlier_threshold;
  options.rotation_weight_m_per_rad = rotation_weight;
  options.default_sigma_m = default_sigma_m;
  options.default_sigma_rad = default_sigma_rad;
  ModelSelectionOptions selection_options;
  if (!ParseModelSelectionMethod(model_selection, &selection_options.method)) {
    Fail("model_selection must be none, validation or cv, got '" +
         model_selection + "'");
  }
  if (selection_options.method == ModelSelectionMethod::kValidation &&
      selection_validation.empty()) {
    Fail("model_selection='validation' needs validation=<Measurements>");
  }
  if (!(prior_std_m >= 0 && std::isfinite(prior_std_m) && prior_std_rad >= 0 &&
        std::isfinite(prior_std_rad))) {
    Fail("prior_std_m and prior_std_rad must be finite and >= 0");
  }
  const bool map_fit = prior_std_m > 0 || prior_std_rad > 0;
  if (map_fit && selection_options.method != ModelSelectionMethod::kNone) {
    Fail(
        "prior_std_m/prior_std_rad (a MAP fit) and model_selection are two "
        "answers to the same question: choose one (model_selection='none')");
  }
  {
    std::string error;
    if (!options.IsValid(&error)) Fail(error);
  }
  if (!ParseParameterRanking(ranking, &selection_options.ranking)) {
    Fail("selection_ranking must be significance or jacobian, got '" + ranking +
         "'");
  }
  const ParameterSet set =
      ParameterSetArg(robot, parameter_set_name.empty()
                                 ? py::object(py::none())
                                 : py::object(py::str(parameter_set_name)));
  result->parameter_set = ParameterSetName(set);
  result->model_selection = model_selection;

  std::string failure;
  bool solver_failure = false;
  {
    py::gil_scoped_release release;
    [&] {
      Eigen::VectorXd initial = model.nominal;
      if (register_base && model.base.convention == LinkConvention::kFrame) {
        RegistrationSummary registration;
        result->registered_base =
            RegisterBaseFrame(model, training, &initial, &registration);
        if (!result->registered_base) {
          failure = registration.message +
                    " (or give the base in a frames file and pass "
                    "register_base=False)";
          return;
        }
      }
      std::vector<DroppedParameter> dropped;
      Eigen::MatrixXd J;
      std::string error;
      const bool reduce = set != ParameterSet::kFile;
      if (!ApplyAndReduceParameterSet(set, training, rotation_weight, &model,
                                      &initial, &dropped, &error)) {
        failure = "parameter_set=" + std::string(ParameterSetName(set)) + ": " +
                  error;
        return;
      }
      if (!StackedJacobian(model, initial, training, rotation_weight, &J,
                           &error)) {
        failure = "measurements: " + error;
        return;
      }
      const std::string what =
          "the " + std::to_string(training.size()) + " measurements";
      IdentifiabilityReport report;
      std::vector<int> fixed_columns;
      if (reduce) {
        for (const DroppedParameter& d : dropped) {
          result->held_fixed.push_back(d.name);
        }
        report = AnalyzeIdentifiability(model, J, options.rank_tolerance);
        if (!report.identifiable()) {
          failure = what + ": " + report.Message();
          return;
        }
      } else if (auto_fix) {
        if (!FixUnidentifiableParameters(&model, J, options.rank_tolerance,
                                         &report, &fixed_columns,
                                         &result->held_fixed)) {
          failure = what + ": " + report.Message();
          return;
        }
      } else {
        report = AnalyzeIdentifiability(model, J, options.rank_tolerance);
        if (!report.identifiable()) {
          failure = what + ": " + report.Message();
          if (report.num_equations >= report.num_free) {
            failure +=
                ". Fix them in the robot file (remove them from 'free') or "
                "pass auto_fix=True";
          }
          return;
        }
      }
      selection_options.num_folds = folds;
      selection_options.num_threads = num_threads;
      selection_options.seed = Random::StreamSeed(seed, 3);
      selection_options.identification = options;
      ModelSelectionSummary& selection = result->selection;
      SelectModel(&model, initial, training, selection_validation,
                  selection_options, &selection);
      if (selection.termination_type != TerminationType::kConvergence) {
        failure = (selection_validation.empty() ? "model_selection: "
                                                : "validation: ") +
                  selection.message;
        return;
      }
      if (selection_options.method != ModelSelectionMethod::kNone) {
        for (const std::string& name : selection.dropped) {
          result->held_fixed.push_back(name);
        }
      }
      IdentificationSummary& summary = result->summary;
      if (map_fit) {
        IdentificationSummary plain;
        Identify(model, training, initial, options, &plain);
        if (plain.termination_type != TerminationType::kConvergence) {
          failure = "identification failed: " + plain.message;
          solver_failure =
              plain.termination_type != TerminationType::kUserFailure;
          return;
        }
        options.prior_std_m = prior_std_m;
        options.prior_std_rad = prior_std_rad;
        options.prior_reference_sigma_m = plain.weighted ? 0.0 : plain.sigma_m;
      }
      Identify(model, training, initial, options, &summary);
      if (summary.termination_type != TerminationType::kConvergence) {
        failure = "identification failed: " + summary.message;
        solver_failure =
            summary.termination_type != TerminationType::kUserFailure;
        return;
      }
      RegistrationFitSummary baseline;
      IdentificationOptions baseline_options = options;
      baseline_options.prior_std_m = baseline_options.prior_std_rad = 0.0;
      FitRegistration(robot.model(), robot.model().nominal, training,
                      baseline_options, &baseline);
      result->have_baseline =
          baseline.termination_type == TerminationType::kConvergence;
      result->registration_only_rms_m = baseline.rms_m;
      result->warnings =
          EstimateWarnings(model, summary, EstimateWarningOptions());
    }();
  }
  if (!failure.empty()) {
    if (solver_failure) throw std::runtime_error(failure);
    Fail(failure);
  }
  result->model = model;
  return result;
}

std::string EstimateFileText(const EstimateResult& e) {
  RobotFileOptions options;
  options.angle_unit = e.robot->description.angle_unit;
  options.comment = "Calibrated by activecal (Python) from " +
                    std::to_string(e.summary.num_measurements) +
                    " measurements, RMS residual " +
                    std::to_string(e.summary.rms_m) + " m";
  return RobotFileText(e.model, e.summary.parameters, options);
}

RobotPtr CalibratedRobot(const EstimateResult& e) {
  auto robot = std::make_shared<Robot>(*e.robot);
  robot->description.model = e.model;
  robot->description.model.nominal = e.summary.parameters;
  return robot;
}

// ------------------------------------------------------------- evaluate

py::dict Stats(const ErrorStatistics& s) {
  py::dict d;
  d["count"] = s.count;
  d["rms"] = s.rms;
  d["mean"] = s.mean;
  d["p95"] = s.p95;
  d["max"] = s.max;
  return d;
}

py::dict EvaluatePy(const Robot& robot, const Measurements& measurements,
                    const py::object& parameters) {
  const Eigen::VectorXd p = ParametersArg(robot, parameters);
  EvaluationSummary s;
  {
    py::gil_scoped_release release;
    EvaluateModel(robot.model(), p, measurements.items, &s);
  }
  if (!s.success) Fail(s.message);
  py::dict d;
  d["num_measurements"] = s.num_measurements;
  d["position"] = Stats(s.position);
  d["rotation"] = Stats(s.rotation);
  d["distance"] = Stats(s.distance);
  d["rmse_xyz_m"] = Eigen::Vector3d(s.rmse_xyz_m);
  d["mean_xyz_m"] = Eigen::Vector3d(s.mean_xyz_m);
  Eigen::MatrixXd pe(s.position_errors.size(), 3);
  for (size_t i = 0; i < s.position_errors.size(); ++i) {
    pe.row(i) = s.position_errors[i].transpose();
  }
  d["position_errors_m"] = pe;
  d["rotation_errors_rad"] = py::array(py::cast(s.rotation_errors_rad));
  d["distance_errors_m"] = py::array(py::cast(s.distance_errors_m));
  d["report"] = s.BriefReport();
  return d;
}

// ----------------------------------------------------------- compensate

struct CompensationResult {
  CompensationSummary summary;
  RobotPtr robot;
  std::vector<int64_t> pose_indices;
  Eigen::MatrixXd starts;  // the program, or the targets' starts
};

std::shared_ptr<CompensationResult> CompensatePy(
    const RobotPtr& robot, const py::object& program, const py::object& nominal,
    const py::object& targets, const py::object& rotations,
    const py::object& starts, const py::object& pose_indices,
    const std::string& match, int marker, double position_tolerance_m,
    double rotation_tolerance_rad, double rotation_weight_m, int max_iterations,
    double singular_threshold, int num_threads, const py::kwargs& kwargs) {
  NoUnknownOptions("compensate", kwargs);
  const RobotModel& model = robot->model();
  if (program.is_none() == targets.is_none()) {
    Fail(
        "give exactly one of program (joint targets, with nominal) and "
        "targets (Cartesian points in the device frame)");
  }
  CompensationOptions options;
  if (!ParseIkMatch(match, &options.ik.match)) {
    Fail("match must be position or pose, got '" + match + "'");
  }
  options.ik.position_tolerance_m = position_tolerance_m;
  options.ik.rotation_tolerance_rad = rotation_tolerance_rad;
  options.ik.rotation_weight_m = rotation_weight_m;
  options.ik.max_iterations = max_iterations;
  options.ik.singular_threshold = singular_threshold;
  options.num_threads = num_threads;
  if (marker < 0 || marker >= model.num_markers()) {
    Fail("marker must be in [0, " + std::to_string(model.num_markers() - 1) +
         "], got " + std::to_string(marker));
  }
  options.ik.marker = marker;
  std::string error;
  if (!options.ik.IsValid(&error)) Fail(error);
  auto result = std::make_shared<CompensationResult>();
  result->robot = robot;
  int64_t n = 0;
  if (!program.is_none()) {
    if (nominal.is_none()) {
      Fail("program needs nominal: the Robot the program was taught with");
    }
    const Robot& taught = py::cast<const Robot&>(nominal);
    if (!CheckSameChain(model, taught.model(), &error)) {
      Fail("robot and nominal: " + error);
    }
    result->starts = MatrixArg(program, "program", model.num_joints(), false);
    n = result->starts.rows();
    py::gil_scoped_release release;
    CompensateProgram(model, model.nominal, taught.model(),
                      taught.model().nominal, result->starts, options,
                      &result->summary);
  } else {
    TargetList list;
    list.points = MatrixArg(targets, "targets", 3, false);
    n = list.points.rows();
    if (!rotations.is_none()) {
      list.rotation_vectors = MatrixArg(rotations, "rotations", 3, false);
      if (list.rotation_vectors.rows() != n) {
        Fail("rotations: expected " + std::to_string(n) +
             " rows (one per target), got " +
             std::to_string(list.rotation_vectors.rows()));
      }
    } else if (options.ik.match == IkMatch::kPose) {
      Fail("match='pose' needs the target orientations: rotations=");
    }
    if (!starts.is_none()) {
      list.start_joints =
          MatrixArg(starts, "starts", model.num_joints(), false);
      if (list.start_joints.rows() != n) {
        Fail("starts: expected " + std::to_string(n) +
             " rows (one per target), got " +
             std::to_string(list.start_joints.rows()));
      }
    }
    result->starts = list.start_joints;
    const std::vector<IkTarget> ik_targets = IkTargetsFromList(list);
    py::gil_scoped_release release;
    CompensateTargets(model, model.nominal, ik_targets, list.start_joints,
                      Eigen::VectorXd(), options, &result->summary);
  }
  if (result->summary.termination_type == TerminationType::kUserFailure) {
    Fail(result->summary.message);
  }
  if (pose_indices.is_none()) {
    for (int64_t i = 0; i < n; ++i) result->pose_indices.push_back(i);
  } else {
    result->pose_indices = py::cast<std::vector<int64_t>>(pose_indices);
    if (static_cast<int64_t>(result->pose_indices.size()) != n) {
      Fail("pose_indices: expected " + std::to_string(n) + " values, got " +
           std::to_string(result->pose_indices.size()));
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

}  // namespace
}  // namespace python
}  // namespace activecal

using namespace activecal;
using namespace activecal::python;

PYBIND11_MODULE(activecal, m) {
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
           "offsets, full; file: unchanged), as ApplyParameterSet; select "
           "and identify further reduce it to what the data separate.")
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
      .def("__len__", [](const Measurements& m) { return m.items.size(); })
      .def("__getitem__", &Subset)
      .def("__add__",
           [](const Measurements& a, const Measurements& b) {
             Measurements out = a;
             out.items.insert(out.items.end(), b.items.begin(), b.items.end());
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
        py::arg("columns_strict") = false,
        "Reads a measurements CSV (docs/formats.md).");
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
        py::arg("noise_m") = 0.001, py::arg("seed") = 1,
        py::arg("type") = "position", py::arg("rotation_noise_rad") = 0.001,
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

  m.def("select", &SelectPy, py::arg("robot"), py::arg("algorithm") = "fedorov",
        py::arg("num_poses") = 30, py::arg("seed") = 1, py::arg("levels") = 5,
        py::arg("pool") = py::none(), py::arg("criterion") = "d",
        py::arg("pool_size") = 100000, py::arg("pool_indices") = py::none(),
        py::arg("measurement") = "position", py::arg("rotation_weight") = 1.0,
        py::arg("parameter_set") = py::none(), py::arg("auto_fix") = false,
        py::arg("restarts") = 0, py::arg("initial_poses") = 12,
        py::arg("random_designs") = 5000, py::arg("certificate") = true,
        py::arg("approx_tolerance") = 2e-3, py::arg("polish_pool_size") = 20000,
        py::arg("noise_m") = 1e-4, py::arg("task_poses") = py::none(),
        py::arg("measured") = py::none(), py::arg("target_rms_m") = py::none(),
        py::arg("num_threads") = 0, py::arg("progress") = py::none(),
        "Selects calibration poses, as activecal_select with the same "
        "options (the same design for the same seed). pool: None or "
        "'lattice' (levels per joint), 'sobol' or 'random' (pool_size "
        "poses), or an array (n, num_joints) of candidate poses. "
        "algorithm: fedorov, eae, detmax, greedy, random, approx. "
        "criterion: d (det), svd (eae), task_rms (task_poses: where the "
        "robot will work, default the pool; measured: Measurements already "
        "made, counted; target_rms_m: the fewest poses meeting it). "
        "progress: a callable "
        "progress(stage, done, total). The GIL is released while it runs.");

  // ---- Estimate
  py::class_<EstimateResult, std::shared_ptr<EstimateResult>>(
      m, "Estimate", "An identification result (identify).")
      .def_property_readonly(
          "parameter_names",
          [](const EstimateResult& e) { return e.summary.names; },
          "The identified (free) parameters, in order")
      .def_property_readonly(
          "estimates",
          [](const EstimateResult& e) { return e.summary.estimates; })
      .def_property_readonly(
          "std",
          [](const EstimateResult& e) { return e.summary.standard_deviations; },
          "Standard deviations of the estimates")
      .def_property_readonly(
          "covariance",
          [](const EstimateResult& e) { return e.summary.covariance; })
      .def_property_readonly(
          "correlation",
          [](const EstimateResult& e) { return e.summary.correlation; })
      .def_property_readonly(
          "nominal",
          [](const EstimateResult& e) {
            return ExtractFree(e.model, e.robot->model().nominal);
          },
          "The nominal values of the identified parameters")
      .def_property_readonly(
          "parameters",
          [](const EstimateResult& e) { return e.summary.parameters; },
          "The full parameter vector identified")
      .def_property_readonly(
          "rms_before_m",
          [](const EstimateResult& e) { return e.summary.initial_rms_m; },
          "RMS residual norm at the start (nominal, base registered)")
      .def_property_readonly(
          "rms_after_m",
          [](const EstimateResult& e) { return e.summary.rms_m; })
      .def_property_readonly(
          "registration_only_rms_m",
          [](const EstimateResult& e) -> py::object {
            if (!e.have_baseline) return py::none();
            return py::float_(e.registration_only_rms_m);
          },
          "RMS residual with only the base and markers fitted, or None")
      .def_property_readonly(
          "sigma_m", [](const EstimateResult& e) { return e.summary.sigma_m; })
      .def_property_readonly(
          "iterations",
          [](const EstimateResult& e) { return e.summary.iterations; })
      .def_property_readonly(
          "residual_norms",
          [](const EstimateResult& e) { return e.summary.residual_norms; })
      .def_property_readonly("outliers",
                             [](const EstimateResult& e) {
                               return py::array(py::cast(e.summary.outliers));
                             })
      .def_property_readonly(
          "termination_type",
          [](const EstimateResult& e) {
            return TerminationTypeToString(e.summary.termination_type);
          })
      .def_readonly("held_fixed", &EstimateResult::held_fixed,
                    "Parameters held at nominal: the parameter set's "
                    "reduction, auto_fix, model selection")
      .def_readonly("warnings", &EstimateResult::warnings)
      .def_readonly("registered_base", &EstimateResult::registered_base)
      .def_readonly("parameter_set", &EstimateResult::parameter_set)
      .def_property_readonly(
          "model_selection_curve",
          [](const EstimateResult& e) {
            py::list curve;
            for (const ModelSelectionPoint& p : e.selection.curve) {
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
      .def_property_readonly(
          "robot", &CalibratedRobot,
          "The calibrated Robot: identified values as nominal")
      .def(
          "save",
          [](const EstimateResult& e, const std::string& path) {
            WriteText(path, EstimateFileText(e));
          },
          py::arg("path"),
          "Writes the calibrated robot YAML (as activecal_identify "
          "--model_out); load_robot(path) reads it back.")
      .def("report",
           [](const EstimateResult& e) { return e.summary.BriefReport(); })
      .def("__repr__", [](const EstimateResult& e) {
        std::ostringstream s;
        s << "<activecal.Estimate: " << e.summary.num_free
          << " parameters, RMS " << e.summary.initial_rms_m << " -> "
          << e.summary.rms_m << " m>";
        return s.str();
      });

  m.def("identify", &IdentifyPy, py::arg("robot"), py::arg("measurements"),
        "identify(robot, measurements, **options) -> Estimate, as "
        "activecal_identify with the same options: parameter_set, "
        "register_base, auto_fix, model_selection ('cv', 'validation', "
        "'none'), folds, selection_ranking, validation (Measurements), "
        "robust_loss, robust_scale_m, outlier_threshold, rotation_weight, "
        "default_sigma_m, default_sigma_rad, prior_std_m, prior_std_rad, "
        "seed, num_threads. The GIL is released while it runs.");
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
          "Per target: converged, singular, limit, unreachable, invalid")
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
          [](const CompensationResult& c, const std::string& path) {
            WriteText(path, CompensatedPosesCsvText(c.robot->model(),
                                                    c.pose_indices, c.summary));
          },
          py::arg("path"),
          "Writes the compensated program as activecal_compensate --out "
          "does (poses CSV with status and position_error_m).")
      .def("report",
           [](const CompensationResult& c) { return c.summary.BriefReport(); });

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
        "starts (n, num_joints)). Targets that do not converge keep their "
        "status (all_converged False); bad input is a ValueError. The GIL "
        "is released while it runs.");

  m.def("evaluate", &EvaluatePy, py::arg("robot"), py::arg("measurements"),
        py::arg("parameters") = py::none(),
        "The errors of a model (robot's nominal, or `parameters`) on "
        "measurements, no fitting: a dict of statistics (m, rad).");
}
