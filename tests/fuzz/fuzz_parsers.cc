// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// libFuzzer targets of the file parsers: whatever the bytes, a parser
// returns true or false with a message; it never crashes, reads out of
// bounds, overflows or hangs. One binary per parser, chosen at compile time
// by ACTIVECAL_FUZZ_TARGET (1 robot YAML, 2 poses CSV, 3 measurements CSV,
// 4 URDF, 5 frames YAML).
// 6: the targets CSV (targets_csv.h).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/puma560.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/frames_file.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/targets_csv.h"
#include "activecal/io/urdf_export.h"
#include "activecal/io/urdf_robot.h"

namespace {

// A two-joint URDF robot with a 6-DOF base, for the frames parser.
const activecal::RobotDescription& SmallUrdfRobot() {
  static const activecal::RobotDescription robot = [] {
    activecal::RobotDescription r;
    std::string error;
    activecal::ParseUrdfRobot(
        "<robot name='r'><link name='a'/><link name='b'/><link name='c'/>"
        "<joint name='j1' type='revolute'><parent link='a'/><child "
        "link='b'/><axis xyz='0 0 1'/><limit lower='-1' upper='1' "
        "effort='1' velocity='1'/></joint><joint name='j2' "
        "type='prismatic'><parent link='b'/><child link='c'/><origin "
        "xyz='0 0 1'/><axis xyz='1 0 0'/><limit lower='0' upper='1' "
        "effort='1' velocity='1'/></joint></robot>",
        "small.urdf", {}, &r, &error);
    return r;
  }();
  return robot;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string error;
#if ACTIVECAL_FUZZ_TARGET == 1
  activecal::RobotDescription robot;
  if (activecal::ParseRobotDescription(text, "fuzz.yaml", &robot, &error)) {
    // A description that loads must be valid and write back loadably.
    std::string why;
    if (!robot.model.Validate(&why)) __builtin_trap();
    activecal::RobotDescription back;
    if (!activecal::ParseRobotDescription(
            activecal::RobotFileText(robot.model, robot.model.nominal), "back",
            &back, &why)) {
      __builtin_trap();
    }
  } else if (error.empty()) {
    __builtin_trap();  // a failure always says why
  }
#elif ACTIVECAL_FUZZ_TARGET == 4
  activecal::RobotDescription robot;
  if (activecal::ParseUrdfRobot(text, "fuzz.urdf", {}, &robot, &error)) {
    // A chain that loads is valid, and writes back as a URDF that loads.
    std::string why, out;
    if (!robot.model.Validate(&why)) __builtin_trap();
    std::vector<std::string> warnings;
    if (!activecal::CalibratedUrdfText(text, "fuzz.urdf", {}, robot.model,
                                       robot.model.nominal, &out, &warnings,
                                       &why)) {
      __builtin_trap();
    }
    activecal::RobotDescription back;
    if (!activecal::ParseUrdfRobot(out, "back.urdf", {}, &back, &why)) {
      __builtin_trap();
    }
  } else if (error.empty()) {
    __builtin_trap();
  }
#elif ACTIVECAL_FUZZ_TARGET == 5
  activecal::RobotDescription robot = SmallUrdfRobot();
  if (activecal::ParseFramesFile(text, "fuzz.yaml", &robot, &error)) {
    std::string why;
    if (!robot.model.Validate(&why)) __builtin_trap();
    if (robot.model.nominal.size() != robot.model.num_parameters()) {
      __builtin_trap();
    }
  } else if (error.empty()) {
    __builtin_trap();
  }
#elif ACTIVECAL_FUZZ_TARGET == 6
  static const activecal::RobotModel model = activecal::Puma560PaperModel();
  activecal::TargetList targets;
  if (activecal::ParseTargetsCsv(text, "fuzz.csv", model, &targets, &error)) {
    // Targets that load are finite, start inside the limits, and write back
    // to the same values.
    const int64_t n = targets.points.rows();
    if (n < 1 || static_cast<int64_t>(targets.pose_indices.size()) != n ||
        !targets.points.allFinite() || !targets.rotation_vectors.allFinite()) {
      __builtin_trap();
    }
    std::string why;
    for (int64_t i = 0; i < targets.start_joints.rows(); ++i) {
      if (!model.CheckJointValues(targets.start_joints.row(i).transpose(),
                                  &why)) {
        __builtin_trap();
      }
    }
    activecal::TargetList back;
    if (!activecal::ParseTargetsCsv(activecal::TargetsCsvText(model, targets),
                                    "back.csv", model, &back, &why) ||
        back.points != targets.points ||
        back.start_joints != targets.start_joints ||
        back.pose_indices != targets.pose_indices) {
      __builtin_trap();
    }
  } else if (error.empty()) {
    __builtin_trap();
  }
#else
  static const activecal::RobotModel model = activecal::Puma560PaperModel();
#if ACTIVECAL_FUZZ_TARGET == 2
  activecal::PoseList poses;
  const bool ok =
      activecal::ParsePosesCsv(text, "fuzz.csv", model, true, &poses, &error);
  if (ok) {
    for (int i = 0; i < poses.joints.rows(); ++i) {
      if (!model.CheckJointValues(poses.joints.row(i).transpose(), &error)) {
        __builtin_trap();
      }
    }
  }
#else
  // Every form of the measurements CSV (units, quaternion, RPY, joints by
  // name, wide markers, sigma and U95 columns, device columns, readings
  // beyond the limits): what parses passes CheckMeasurement, one line per
  // measurement, and writes back to the same measurements; the strict
  // options accept nothing the default ones refuse.
  std::vector<activecal::Measurement> measurements;
  activecal::MeasurementsCsvReport report;
  const bool ok = activecal::ParseMeasurementsCsv(
      text, "fuzz.csv", model, {}, &measurements, &report, &error);
  if (ok) {
    if (report.lines.size() != measurements.size()) __builtin_trap();
    if (report.warnings.size() > 1) __builtin_trap();
    for (const activecal::Measurement& m : measurements) {
      if (!activecal::CheckMeasurement(model, m, &error)) __builtin_trap();
    }
    std::vector<activecal::Measurement> back;
    if (!activecal::ParseMeasurementsCsv(
            activecal::MeasurementsCsvText(model, measurements), "back.csv",
            model, &back, &error) ||
        back.size() != measurements.size()) {
      __builtin_trap();
    }
    for (size_t i = 0; i < back.size(); ++i) {
      if (back[i].joints != measurements[i].joints ||
          back[i].sigma_rad != measurements[i].sigma_rad) {
        __builtin_trap();
      }
    }
  }
  activecal::MeasurementsCsvOptions strict;
  strict.strict_limits = true;
  strict.columns_strict = true;
  std::vector<activecal::Measurement> strict_out;
  std::string strict_error;
  if (activecal::ParseMeasurementsCsv(text, "fuzz.csv", model, strict,
                                      &strict_out, nullptr, &strict_error)) {
    if (!ok || strict_out.size() != measurements.size()) __builtin_trap();
  } else if (strict_error.empty()) {
    __builtin_trap();
  }
#endif
  if (!ok && error.empty()) __builtin_trap();
#endif
  return 0;
}
