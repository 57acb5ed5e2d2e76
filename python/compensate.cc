// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: compensate; with cell= a configuration the
// cell refuses is a collision (cell_planning.h), as activecal_compensate
// --cell.

#include "activecal/calibration/compensate.h"

#include <sstream>

#include "activecal/calibration/cell_planning.h"
#include "activecal/io/csv_files.h"
#include "activecal/kinematics/inverse_kinematics.h"
#include "common.h"

namespace activecal {
namespace python {

// ----------------------------------------------------------- compensate

namespace {

struct CompensationResult {
  CompensationSummary summary;
  RobotPtr robot;
  std::vector<int64_t> pose_indices;
  Eigen::MatrixXd starts;  // the program, or the targets' starts
};

// Joint rows given to compensate: finite, within the ranges widened by the
// tolerance for measured joints (a NaN row is bad input, not a target
// that did not converge).
void CheckRows(const RobotModel& model, const Eigen::MatrixXd& rows,
               const std::string& what) {
  for (int r = 0; r < rows.rows(); ++r) {
    std::string error;
    if (!model.CheckJointValues(rows.row(r).transpose(), &error,
                                kMeasuredJointToleranceRad,
                                kMeasuredJointToleranceM)) {
      Fail(what + " row " + std::to_string(r) + ": " + error);
    }
  }
}

// Rows of numbers given to compensate: every value finite (a NaN rotation
// vector was read as the identity and its target reported converged).
void CheckFinite(const Eigen::MatrixXd& rows, const std::string& what) {
  for (int r = 0; r < rows.rows(); ++r) {
    for (int c = 0; c < rows.cols(); ++c) {
      if (!std::isfinite(rows(r, c))) {
        std::ostringstream value;
        value << rows(r, c);
        Fail(what + " row " + std::to_string(r) + ": value " +
             std::to_string(c) + " is not finite (" + value.str() + ")");
      }
    }
  }
}

std::shared_ptr<CompensationResult> CompensatePy(
    const RobotPtr& robot, const py::object& program, const py::object& nominal,
    const py::object& targets, const py::object& rotations,
    const py::object& starts, const py::object& pose_indices,
    const std::string& match, int marker, double position_tolerance_m,
    double rotation_tolerance_rad, double rotation_weight_m, int max_iterations,
    double singular_threshold, int num_threads, const py::kwargs& kwargs) {
  NoUnknownOptions("compensate", kwargs, {"cell"});
  const RobotModel& model = robot->model();
  std::vector<std::string> cell_notes;
  const std::unique_ptr<CellSetup> cell = CellArg(*robot, kwargs, &cell_notes);
  if (program.is_none() == targets.is_none()) {
    Fail(
        "give exactly one of program (joint targets, with nominal) and "
        "targets (Cartesian points in the device frame)");
  }
  CompensateOptions options;
  InverseKinematicsOptions& ik = options.compensation.ik;
  if (!ParseIkMatch(match, &ik.match)) {
    Fail("match must be position or pose, got '" + match + "'");
  }
  ik.position_tolerance_m = position_tolerance_m;
  ik.rotation_tolerance_rad = rotation_tolerance_rad;
  ik.rotation_weight_m = rotation_weight_m;
  ik.max_iterations = max_iterations;
  ik.singular_threshold = singular_threshold;
  options.compensation.num_threads = num_threads;
  if (marker < 0 || marker >= model.num_markers()) {
    Fail("marker must be in [0, " + std::to_string(model.num_markers() - 1) +
         "], got " + std::to_string(marker));
  }
  ik.marker = marker;
  options.marker.clear();  // ik.marker as given
  options.in_memory = true;
  std::string error;
  if (!options.IsValid(&error)) Fail(error);
  // The cell's check as given: no collision geometry required.
  if (cell) options.compensation.check = CellCompensationCheck(*cell->checker);
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
    options.joint_program =
        MatrixArg(program, "program", model.num_joints(), false);
    n = options.joint_program.rows();
    CheckRows(taught.model(), options.joint_program, "program");
    options.nominal_model = &taught.model();
  } else {
    TargetList& list = options.targets;
    list.points = MatrixArg(targets, "targets", 3, false);
    CheckFinite(list.points, "targets");
    n = list.points.rows();
    if (!rotations.is_none()) {
      list.rotation_vectors = MatrixArg(rotations, "rotations", 3, false);
      CheckFinite(list.rotation_vectors, "rotations");
      if (list.rotation_vectors.rows() != n) {
        Fail("rotations: expected " + std::to_string(n) +
             " rows (one per target), got " +
             std::to_string(list.rotation_vectors.rows()));
      }
    } else if (ik.match == IkMatch::kPose) {
      Fail("match='pose' needs the target orientations: rotations=");
    }
    if (!starts.is_none()) {
      list.start_joints =
          MatrixArg(starts, "starts", model.num_joints(), false);
      CheckRows(model, list.start_joints, "starts");
      if (list.start_joints.rows() != n) {
        Fail("starts: expected " + std::to_string(n) +
             " rows (one per target), got " +
             std::to_string(list.start_joints.rows()));
      }
    }
  }
  // The model as given: the module's Robot has no learned correction.
  RobotDescription description;
  description.model = model;
  CompensateSummary summary;
  {
    py::gil_scoped_release release;
    Compensate(description, options, &summary);
  }
  if (summary.termination_type == TerminationType::kUserFailure) {
    Fail(summary.message);
  }
  result->summary = std::move(summary.compensation);
  result->starts = std::move(summary.starts);
  if (pose_indices.is_none()) {
    for (int64_t i = 0; i < n; ++i) result->pose_indices.push_back(i);
  } else {
    result->pose_indices = IntegerVector(pose_indices, "pose_indices");
    if (static_cast<int64_t>(result->pose_indices.size()) != n) {
      Fail("pose_indices: expected " + std::to_string(n) + " values, got " +
           std::to_string(result->pose_indices.size()));
    }
    std::string error;
    if (!CheckPoseIndices(result->pose_indices, /*unique=*/false, &error)) {
      Fail(error);
    }
  }
  return result;
}

// Per target, a number of its result.
Eigen::VectorXd PerTarget(const CompensationResult& c,
                          double InverseKinematicsResult::*field) {
  Eigen::VectorXd e(c.summary.results.size());
  for (size_t i = 0; i < c.summary.results.size(); ++i) {
    e[i] = c.summary.results[i].*field;
  }
  return e;
}

}  // namespace

void BindCompensate(py::module_& m) {
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
            return Each(c.summary.results,
                        [](const InverseKinematicsResult& r) {
                          return std::string(IkStatusName(r.status));
                        });
          },
          "Per target: converged, singular, limit, unreachable, invalid, "
          "iteration_cap, collision (cell=)")
      .def_property_readonly(
          "messages",
          [](const CompensationResult& c) {
            return Each(
                c.summary.results,
                [](const InverseKinematicsResult& r) { return r.message; });
          })
      .def_property_readonly(
          "position_error_m",
          [](const CompensationResult& c) {
            return PerTarget(c, &InverseKinematicsResult::position_error_m);
          })
      .def_property_readonly(
          "rotation_error_rad",
          [](const CompensationResult& c) {
            return PerTarget(c, &InverseKinematicsResult::rotation_error_rad);
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
}

}  // namespace python
}  // namespace activecal
