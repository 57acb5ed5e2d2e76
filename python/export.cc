// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: what the programs write from an Estimate
// (the calibrated URDF, the frames file, the frames for ROS 2) and the ROS
// frames reader, through the same io functions the programs call.
//
// Estimate.write_urdf is activecal_identify --urdf_out's library call
// (calibration_export.h: MakeCalibratedUrdf, the same choice of writer and
// the same 1e-9 m reload check); Estimate.write_ur_calibration is
// --ur_calibration_out's (MakeUrCalibration).

#include <fstream>

#include "activecal/calibration/calibration_export.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/frames_file.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/ros_frames.h"
#include "activecal/io/urdf_export.h"
#include "common.h"

namespace activecal {
namespace python {
namespace {

std::string SourceNote(const EstimateResult& e) {
  return std::to_string(e.fit().num_measurements) +
         " measurements, RMS residual " + std::to_string(e.fit().rms_m) + " m";
}

// The chain the URDF robot was loaded with, its ends resolved from the
// file when load_robot was not told them (they name the tf frames).
void ResolvedChain(const Robot& robot, UrdfChainOptions* chain,
                   std::string* base, std::string* tip) {
  *chain = robot.chain;
  *base = "base_link";
  *tip = "tip";  // UrdfFromModel's links
  if (!robot.urdf) return;
  std::string xml, error;
  std::vector<UrdfChainJoint> joints;
  if (!ReadUrdfText(robot.path, &xml, &error) ||
      !UrdfChainJoints(xml, robot.path, robot.chain, &joints, &error)) {
    Fail(error);
  }
  if (joints.empty()) Fail(robot.path + ": the chain has no joints");
  *base = joints.front().parent_link;
  *tip = joints.back().child_link;
}

// write_urdf: the text, checked, then written; returns the largest
// distance found by the check (m).
double WriteUrdfPy(const EstimateResult& e, const py::object& path_obj,
                   const py::object& measurements_obj) {
  const std::string path = PathArg(path_obj);
  const Robot& robot = *e.robot;
  std::vector<Measurement> check = e.measurements;
  if (!measurements_obj.is_none()) {
    check = MeasurementsArg(measurements_obj, "measurements").items;
    CheckMarkers(e.model(), check, "measurements");
  }
  CalibratedUrdfOptions options;
  if (robot.urdf) options.source_path = robot.path;
  options.chain = robot.chain;
  options.output_path = path;
  CalibratedUrdf urdf;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = MakeCalibratedUrdf(e.model(), e.fit().parameters, check, options,
                            &urdf, &error);
  }
  if (!ok) Fail("write_urdf: " + error);
  WriteText(path, urdf.text);
  return urdf.worst_m;
}

// write_ur_calibration: activecal_identify --ur_calibration_out's call;
// returns the check's largest differences (m, rad).
py::tuple WriteUrCalibrationPy(const EstimateResult& e,
                               const py::object& path_obj) {
  const std::string path = PathArg(path_obj);
  UrCalibration ur;
  std::string error;
  if (!MakeUrCalibration(
          e.model(), e.fit().parameters, e.measurements,
          "Calibrated by activecal (Python) from " + SourceNote(e), &ur,
          &error)) {
    Fail("write_ur_calibration: " + error);
  }
  WriteText(path, ur.text);
  return py::make_tuple(ur.worst_m, ur.worst_rad);
}

std::vector<RosTransform> Transforms(const EstimateResult& e,
                                     const std::string& device_frame,
                                     const py::object& base_frame,
                                     const py::object& tip_frame) {
  RosFramesOptions options;
  UrdfChainOptions chain;
  ResolvedChain(*e.robot, &chain, &options.base_frame, &options.tip_frame);
  options.device_frame = device_frame;
  if (!base_frame.is_none()) options.base_frame = py::str(base_frame);
  if (!tip_frame.is_none()) options.tip_frame = py::str(tip_frame);
  std::vector<RosTransform> transforms;
  std::string error;
  if (!MetrologyRosTransforms(e.model(), e.fit().parameters, options,
                              &transforms, &error)) {
    Fail("write_ros_frames: " + error);
  }
  return transforms;
}

void WriteRosFramesPy(const EstimateResult& e, const py::object& path_obj,
                      const std::string& format,
                      const std::string& device_frame,
                      const py::object& base_frame,
                      const py::object& tip_frame) {
  const std::string path = PathArg(path_obj);
  if (format != "yaml" && format != "script") {
    Fail("write_ros_frames: format must be yaml or script, got '" + format +
         "'");
  }
  const std::vector<RosTransform> transforms =
      Transforms(e, device_frame, base_frame, tip_frame);
  const std::string comment =
      "Metrology frames identified by activecal (Python) from " + SourceNote(e);
  WriteText(path, format == "yaml"
                      ? Tf2StaticTransformsYaml(transforms, comment)
                      : StaticTransformPublisherScript(transforms, comment));
}

py::list ReadRosFramesPy(const py::object& path_obj,
                         const py::object& format_obj) {
  const std::string path = PathArg(path_obj);
  std::string format;
  if (format_obj.is_none()) {
    const auto ends = [&](const std::string& suffix) {
      return path.size() >= suffix.size() &&
             path.compare(path.size() - suffix.size(), suffix.size(), suffix) ==
                 0;
    };
    format = ends(".yaml") || ends(".yml") ? "yaml" : "script";
  } else {
    format = py::str(format_obj);
    if (format != "yaml" && format != "script") {
      Fail("read_ros_frames: format must be yaml or script, got '" + format +
           "'");
    }
  }
  std::string text, error;
  std::vector<RosTransform> transforms;
  if (!ReadTextFile(path, &text, &error) ||
      !(format == "yaml"
            ? ParseTf2StaticTransformsYaml(text, path, &transforms, &error)
            : ParseStaticTransformPublisherScript(text, path, &transforms,
                                                  &error))) {
    Fail(error);
  }
  py::list out;
  for (const RosTransform& t : transforms) {
    py::dict d;
    d["frame_id"] = t.frame_id;
    d["child_frame_id"] = t.child_frame_id;
    d["translation"] = Eigen::Vector3d(t.translation);
    d["rotation"] = Eigen::Vector4d(t.rotation.coeffs());  // x, y, z, w
    d["matrix"] = t.Matrix();
    out.append(d);
  }
  return out;
}

// `f` as the method `name` of class `cls` (the class is defined in
// module.cc).
template <typename F, typename... Extra>
void AddMethod(py::object cls, const char* name, F&& f, const Extra&... extra) {
  cls.attr(name) = py::cpp_function(
      std::forward<F>(f), py::name(name), py::is_method(cls),
      py::sibling(py::getattr(cls, name, py::none())), extra...);
}

}  // namespace

void BindExport(py::module_& m) {
  const py::object estimate = m.attr("Estimate");
  AddMethod(estimate, "write_urdf", &WriteUrdfPy, py::arg("path"),
            py::arg("measurements") = py::none(),
            "Writes the calibrated robot as URDF (as activecal_identify "
            "--urdf_out): a URDF robot's file with only the calibrated "
            "joints' origins changed, or a YAML robot written as URDF. "
            "Before writing, the URDF is reloaded and must predict every "
            "measurement (default: those identified from and the "
            "validation rows) within 1e-9 m of the calibrated model, or "
            "ValueError. Returns the largest difference (m).");
  AddMethod(estimate, "write_ur_calibration", &WriteUrCalibrationPy,
            py::arg("path"),
            "Writes the calibrated UR's kinematics for the UR ROS driver "
            "(as activecal_identify --ur_calibration_out: ur_description's "
            "default_kinematics.yaml form, for kinematics_params_file:=). "
            "Only for a UR loaded from its URDF, base_link to tool0; the "
            "chain rebuilt from the written numbers as ur_description does "
            "must match the calibrated model within 1e-9 m and 1e-9 rad, or "
            "ValueError. Returns the largest differences (m, rad).");
  AddMethod(
      estimate, "write_frames",
      [](const EstimateResult& e, const py::object& path) {
        WriteText(PathArg(path),
                  FramesFileText(e.model(), e.fit().parameters,
                                 "Metrology frames identified by activecal "
                                 "(Python) from " +
                                     SourceNote(e)));
      },
      py::arg("path"),
      "Writes the metrology frames (base registration, markers) as "
      "activecal_identify --frames_out, for load_robot(frames=...).");
  AddMethod(estimate, "write_ros_frames", &WriteRosFramesPy, py::arg("path"),
            py::arg("format") = "yaml", py::arg("device_frame") = "device",
            py::arg("base_frame") = py::none(),
            py::arg("tip_frame") = py::none(),
            "Writes the metrology frames for ROS 2: format='yaml' a "
            "tf2_msgs/msg/TFMessage (for ros2 topic pub /tf_static), "
            "'script' an sh script of ros2 run tf2_ros "
            "static_transform_publisher lines. Transforms device_frame -> "
            "base_frame (the base registration) and tip_frame -> each "
            "marker; base_frame and tip_frame default to the chain's ends "
            "(URDF robot) or base_link and tip (a YAML robot's URDF).");
  m.def("read_ros_frames", &ReadRosFramesPy, py::arg("path"),
        py::arg("format") = py::none(),
        "Reads static transforms written by Estimate.write_ros_frames "
        "(format 'yaml' or 'script'; default by the suffix: .yaml/.yml "
        "are yaml): a list of dicts with frame_id, child_frame_id, "
        "translation (3,) m, rotation (4,) quaternion x, y, z, w, matrix "
        "(4, 4).");
}

}  // namespace python
}  // namespace activecal
