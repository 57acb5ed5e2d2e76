// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: Files (measurements, poses, targets CSV),
// Measurements, simulate.

#include <fstream>
#include <sstream>
#include <utility>

#include "activecal/calibration/defaults.h"
#include "activecal/core/simulation.h"
#include "activecal/io/column_map.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/targets_csv.h"
#include "common.h"

namespace activecal {
namespace python {

// ------------------------------------------------------------ files

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.flush();
  if (!out) Fail("cannot write '" + path + "'");
}

namespace {

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

Measurements ReadMeasurementsPy(const Robot& robot, const py::object& path_obj,
                                bool strict_limits, bool columns_strict,
                                const py::object& column_map) {
  const std::string path = PathArg(path_obj);
  MeasurementsCsvOptions options;
  options.strict_limits = strict_limits;
  options.columns_strict = columns_strict;
  if (!column_map.is_none()) {
    ColumnMap map;
    std::string error;
    if (!ReadColumnMap(PathArg(column_map), &map, &error)) Fail(error);
    options.column_map = map;
  }
  Measurements m;
  MeasurementsCsvReport report;
  std::string error;
  if (!ReadMeasurementsCsv(path, robot.model(), options, &m.items, &report,
                           &error)) {
    Fail(error);
  }
  m.warnings = report.warnings;
  m.notes = report.notes;
  m.num_joints = robot.model().num_joints();
  return m;
}

// write_measurements' orientation= as the writer's format.
OrientationFormat OrientationArg(const std::string& name) {
  constexpr std::pair<const char*, OrientationFormat> kFormats[] = {
      {"rotation_vector", OrientationFormat::kRotationVector},
      {"quaternion", OrientationFormat::kQuaternion},
      {"rpy_rad", OrientationFormat::kRpyRad},
      {"rpy_deg", OrientationFormat::kRpyDeg}};
  for (const auto& [text, format] : kFormats) {
    if (name == text) return format;
  }
  Fail(
      "orientation must be rotation_vector, quaternion, rpy_rad or "
      "rpy_deg, got '" +
      name + "'");
}

void WriteMeasurementsPy(const Robot& robot, const py::object& path_obj,
                         const Measurements& m, bool millimetres,
                         bool joint_degrees, bool joint_names,
                         const std::string& orientation) {
  const std::string path = PathArg(path_obj);
  const MeasurementsCsvFormat format{millimetres, joint_degrees, joint_names,
                                     OrientationArg(orientation)};
  CheckMarkers(robot.model(), m.items, "measurements");
  for (size_t i = 0; i < m.items.size(); ++i) {
    std::string error;
    if (!CheckMeasurement(robot.model(), m.items[i], &error)) {
      Fail("measurement " + std::to_string(i) + ": " + error);
    }
  }
  WriteText(path, MeasurementsCsvText(robot.model(), m.items, format));
}

py::tuple ReadPosesPy(const Robot& robot, const py::object& path_obj,
                      bool reject_duplicates) {
  const std::string path = PathArg(path_obj);
  PoseList list;
  std::string error;
  if (!ReadPosesCsv(path, robot.model(), reject_duplicates, &list, &error)) {
    Fail(error);
  }
  return py::make_tuple(list.joints, py::array(py::cast(list.pose_indices)));
}

// A Cartesian targets CSV (targets_csv.h): points, rotation vectors and
// start joints when the file has them (else None), pose indices.
py::tuple ReadTargetsPy(const Robot& robot, const py::object& path_obj) {
  const std::string path = PathArg(path_obj);
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

void WritePosesPy(const Robot& robot, const py::object& path_obj,
                  const py::object& joints, const py::object& indices) {
  const std::string path = PathArg(path_obj);
  const RobotModel& model = robot.model();
  PoseList list;
  list.joints = MatrixArg(joints, "joint_angles", model.num_joints(), false);
  if (indices.is_none()) {
    for (int64_t i = 0; i < list.joints.rows(); ++i) {
      list.pose_indices.push_back(i);
    }
  } else {
    list.pose_indices = IntegerVector(indices, "pose_indices");
    if (static_cast<int64_t>(list.pose_indices.size()) != list.joints.rows()) {
      Fail("pose_indices: expected " + std::to_string(list.joints.rows()) +
           " values (one per pose), got " +
           std::to_string(list.pose_indices.size()));
    }
    std::string error;
    if (!CheckPoseIndices(list.pose_indices, /*unique=*/false, &error)) {
      Fail(error);
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
  std::vector<int64_t> mk;
  if (!markers.is_none()) {
    mk = IntegerVector(markers, "markers");
    if (static_cast<int>(mk.size()) != n) {
      Fail("markers: expected " + std::to_string(n) + " values, got " +
           std::to_string(mk.size()));
    }
    for (size_t i = 0; i < mk.size(); ++i) {
      if (mk[i] < 0 || mk[i] > std::numeric_limits<int>::max()) {
        Fail(
            "markers: expected marker numbers >= 0 (markers are numbered "
            "from 0), got " +
            std::to_string(mk[i]) + " in row " + std::to_string(i));
      }
    }
  }
  Measurements out;
  out.num_joints = nj;
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
    if (!mk.empty()) m.marker = static_cast<int>(mk[i]);
  }
  return out;
}

}  // namespace

const Measurements& MeasurementsArg(const py::object& obj,
                                    const std::string& what) {
  if (!py::isinstance<Measurements>(obj)) {
    Fail(what + ": expected activecal.Measurements, got " +
         std::string(py::str(py::type::of(obj).attr("__name__"))));
  }
  return py::cast<const Measurements&>(obj);
}

namespace {

int NumJoints(const Measurements& m) {
  return m.items.empty() ? m.num_joints
                         : static_cast<int>(m.items[0].joints.size());
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
    if (a.size() == 0 && a.ndim() == 1) {
      // m[[]]: numpy makes [] float64; empty, as an empty index array.
    } else if (a.dtype().kind() == 'b') {
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
  // The subset keeps the reader's warnings and notes (they are about the
  // file) and the joint count (an empty subset's joints: (0, num_joints)).
  Measurements out;
  out.warnings = m.warnings;
  out.notes = m.notes;
  out.num_joints = NumJoints(m);
  for (int64_t i : index) out.items.push_back(m.items[i]);
  return out;
}

// Pickle state: per row the type, marker, joint counts, sigma_rad and
// distance; the joints (both poses) concatenated; positions, rotations,
// sigma_m as (n, 3).
py::tuple MeasurementsState(const Measurements& m) {
  const size_t n = m.items.size();
  std::vector<int> types(n), markers(n), nj(n), nj2(n);
  std::vector<double> joints, scalars(2 * n);
  Eigen::MatrixXd vectors(n, 9);
  for (size_t i = 0; i < n; ++i) {
    const Measurement& x = m.items[i];
    types[i] = static_cast<int>(x.type);
    markers[i] = x.marker;
    nj[i] = static_cast<int>(x.joints.size());
    nj2[i] = static_cast<int>(x.joints2.size());
    joints.insert(joints.end(), x.joints.data(), x.joints.data() + nj[i]);
    joints.insert(joints.end(), x.joints2.data(), x.joints2.data() + nj2[i]);
    scalars[2 * i] = x.distance;
    scalars[2 * i + 1] = x.sigma_rad;
    vectors.row(i) << x.position.transpose(), x.rotation.transpose(),
        x.sigma_m.transpose();
  }
  return py::make_tuple(1, m.num_joints, py::array(py::cast(types)),
                        py::array(py::cast(markers)), py::array(py::cast(nj)),
                        py::array(py::cast(nj2)), py::array(py::cast(joints)),
                        py::array(py::cast(scalars)), py::cast(vectors),
                        m.warnings, m.notes);
}

Measurements MeasurementsFromState(const py::tuple& state) {
  if (state.size() != 11 || py::cast<int>(state[0]) != 1) {
    Fail("Measurements: unknown pickle state");
  }
  Measurements m;
  m.num_joints = py::cast<int>(state[1]);
  const auto types = py::cast<std::vector<int>>(state[2]);
  const auto markers = py::cast<std::vector<int>>(state[3]);
  const auto nj = py::cast<std::vector<int>>(state[4]);
  const auto nj2 = py::cast<std::vector<int>>(state[5]);
  const auto joints = py::cast<std::vector<double>>(state[6]);
  const auto scalars = py::cast<std::vector<double>>(state[7]);
  const auto vectors = py::cast<Eigen::MatrixXd>(state[8]);
  const size_t n = types.size();
  if (markers.size() != n || nj.size() != n || nj2.size() != n ||
      scalars.size() != 2 * n || vectors.rows() != static_cast<int64_t>(n) ||
      vectors.cols() != 9) {
    Fail("Measurements: inconsistent pickle state");
  }
  size_t k = 0;
  m.items.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Measurement& x = m.items[i];
    if (types[i] < 0 ||
        types[i] > static_cast<int>(MeasurementType::kDistance) || nj[i] < 0 ||
        nj2[i] < 0 || k + nj[i] + nj2[i] > joints.size()) {
      Fail("Measurements: inconsistent pickle state");
    }
    x.type = static_cast<MeasurementType>(types[i]);
    x.marker = markers[i];
    x.joints = Eigen::Map<const Eigen::VectorXd>(joints.data() + k, nj[i]);
    k += nj[i];
    x.joints2 = Eigen::Map<const Eigen::VectorXd>(joints.data() + k, nj2[i]);
    k += nj2[i];
    x.distance = scalars[2 * i];
    x.sigma_rad = scalars[2 * i + 1];
    x.position = vectors.row(i).segment<3>(0).transpose();
    x.rotation = vectors.row(i).segment<3>(3).transpose();
    x.sigma_m = vectors.row(i).segment<3>(6).transpose();
  }
  m.warnings = py::cast<std::vector<std::string>>(state[9]);
  m.notes = py::cast<std::vector<std::string>>(state[10]);
  return m;
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
  int identical = -1;
  if (!SimulationPlan(joints, type, &plan, &identical)) {
    if (identical < 0) {
      Fail("type=distance needs at least 2 poses, got " +
           std::to_string(joints.rows()));
    }
    Fail("type=distance: poses " + std::to_string(identical) + " and " +
         std::to_string(identical + 1) +
         " (rows of joint_angles) are identical: a distance between "
         "them measures nothing; remove one");
  }
  SimulationNoise noise;
  noise.position_m = noise_m;
  noise.rotation_rad = rotation_noise_rad;
  Measurements out;
  out.num_joints = model.num_joints();
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

}  // namespace

void BindMeasurements(py::module_& m) {
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
}

}  // namespace python
}  // namespace activecal
