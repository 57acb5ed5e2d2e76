// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: Robot: load_robot, puma560, forward, frame,
// jacobian, with_parameter_set, perturbed, save.

#include <fstream>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/simulation.h"
#include "activecal/io/robot_loader.h"
#include "activecal/residuals/jacobians.h"
#include "common.h"

namespace activecal {
namespace python {

namespace {

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

// ------------------------------------------------------------- load_robot

RobotPtr LoadRobotPy(const py::object& path_obj, const py::object& base_link,
                     const py::object& tip_link, const py::object& frames) {
  const std::string path = PathArg(path_obj);
  RobotLoadOptions options;
  if (!base_link.is_none()) options.chain.base_link = py::str(base_link);
  if (!tip_link.is_none()) options.chain.tip_link = py::str(tip_link);
  if (!frames.is_none()) options.frames_path = PathArg(frames);
  auto robot = std::make_shared<Robot>();
  std::string error;
  if (!LoadRobot(path, options, &robot->description, &error)) Fail(error);
  robot->path = path;
  robot->urdf = IsUrdfPath(path);
  robot->chain = options.chain;
  robot->with_frames = !frames.is_none();
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

// The arguments forward and jacobian share: the marker, the joint
// readings q (one pose or n, checked against the ranges) and the
// parameters.
static void PointArgs(const Robot& robot, const py::object& q_obj,
                      const py::object& parameters, int marker,
                      Eigen::MatrixXd* q, Eigen::VectorXd* p, bool* one) {
  const RobotModel& model = robot.model();
  if (marker < 0 || marker >= model.num_markers()) {
    Fail("marker must be in [0, " + std::to_string(model.num_markers() - 1) +
         "], got " + std::to_string(marker));
  }
  *q = MatrixArg(q_obj, "q", model.num_joints(), true, one);
  *p = ParametersArg(robot, parameters);
  for (int r = 0; r < q->rows(); ++r) CheckQ(model, q->row(r), r, !*one);
}

// forward(q): the measured point (m) at joint readings q, (3,) or (n, 3).
py::array_t<double> Forward(const Robot& robot, const py::object& q_obj,
                            const py::object& parameters, int marker) {
  const RobotModel& model = robot.model();
  bool one = false;
  Eigen::MatrixXd q;
  Eigen::VectorXd p;
  PointArgs(robot, q_obj, parameters, marker, &q, &p, &one);
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
  bool one = false;
  Eigen::MatrixXd q;
  Eigen::VectorXd p;
  PointArgs(robot, q_obj, parameters, marker, &q, &p, &one);
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
    // `out` is not shared yet: filled without the GIL. The pool path: the
    // analytic point kernel for position rows (the program's), the
    // auto-diff residual for pose rows; one thread (the caller may run
    // several).
    py::gil_scoped_release release;
    PoolJacobianOptions options;
    options.num_threads = 1;
    options.type = type;
    options.rotation_weight_m_per_rad = rotation_weight;
    options.marker = marker;
    options.joint_tolerance_rad = kMeasuredJointToleranceRad;
    options.joint_tolerance_m = kMeasuredJointToleranceM;
    if (PoolJacobians(model, p, q, options, o, &error)) {
      error.clear();
    } else if (error.empty()) {
      error = "Jacobian evaluation failed";
    }
  }
  if (!error.empty()) Fail(error);
  return out;
}

RobotPtr WithParameterSet(const Robot& robot, const std::string& name,
                          const std::string& measurement) {
  ParameterSet set;
  if (!StringToParameterSet(name, &set)) {
    Fail("parameter_set must be registration, offsets, full or file, got '" +
         name + "'");
  }
  const MeasurementType type =
      MeasurementTypeArg(measurement, true, "measurement");
  auto out = std::make_shared<Robot>(robot);
  if (set != ParameterSet::kFile) {
    RobotModel& model = out->description.model;
    model = WithFreeSet(
        model, ParameterSetFreeSet(model, set, type == MeasurementType::kPose));
  }
  return out;
}

Eigen::VectorXd PerturbedPy(const Robot& robot, double perturb_m,
                            double perturb_rad, uint64_t seed,
                            const py::object& parameters) {
  Eigen::VectorXd out;
  std::string error;
  if (!PerturbParameters(robot.model(), ParametersArg(robot, parameters),
                         perturb_m, perturb_rad, seed, &out, &error)) {
    Fail(error);
  }
  return out;
}

void SaveRobot(const Robot& robot, const py::object& path_obj,
               const py::object& parameters) {
  const std::string path = PathArg(path_obj);
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

// The file text in radians (the file's unit would round angles through
// degrees), the unit kept beside it.
py::tuple RobotState(const Robot& robot) {
  RobotFileOptions options;
  options.true_parameters = robot.description.true_parameters;
  const std::string text =
      RobotFileText(robot.model(), robot.model().nominal, options);
  return py::make_tuple(1, py::bytes(text), robot.path, robot.urdf,
                        robot.description.angle_unit == AngleUnit::kDegree,
                        robot.description.true_parameters.size() > 0,
                        robot.chain.base_link, robot.chain.tip_link);
}

RobotPtr RobotFromState(const py::tuple& state) {
  // 6 entries: written before the chain's ends were kept.
  if ((state.size() != 6 && state.size() != 8) ||
      py::cast<int>(state[0]) != 1) {
    Fail("Robot: unknown pickle state");
  }
  auto robot = std::make_shared<Robot>();
  std::string error;
  if (!ParseRobotDescription(py::cast<std::string>(state[1]), "<pickle>",
                             &robot->description, &error)) {
    Fail("Robot: " + error);
  }
  robot->path = py::cast<std::string>(state[2]);
  robot->urdf = py::cast<bool>(state[3]);
  robot->description.angle_unit =
      py::cast<bool>(state[4]) ? AngleUnit::kDegree : AngleUnit::kRadian;
  if (!py::cast<bool>(state[5])) robot->description.true_parameters.resize(0);
  if (state.size() == 8) {
    robot->chain.base_link = py::cast<std::string>(state[6]);
    robot->chain.tip_link = py::cast<std::string>(state[7]);
  }
  return robot;
}

}  // namespace

void BindRobot(py::module_& m) {
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
}

}  // namespace python
}  // namespace activecal
