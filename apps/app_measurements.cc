// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// --strict_limits and ReadMeasurementsOrDie, which reads it (and
// --columns_strict), in a file of their own (see app_parameter_set.cc).

#include <gflags/gflags.h>

#include <iostream>

#include "app_common.h"

DEFINE_bool(strict_limits, false,
            "Refuse a measurements file whose joint readings lie beyond the "
            "robot's joint limits. Default: readings within 5 deg (revolute) "
            "or 10 mm (prismatic) of a limit are accepted with one warning "
            "per file; farther out they are always an error.");

namespace activecal {
namespace app {

std::vector<Measurement> ReadMeasurementsOrDie(const std::string& path,
                                               const RobotModel& model,
                                               const std::string& flag,
                                               std::vector<int>* lines) {
  MeasurementsCsvOptions options;
  options.strict_limits = FLAGS_strict_limits;
  options.columns_strict = ColumnsStrict();
  options.column_map = ColumnMapOrDie();
  std::vector<Measurement> measurements;
  MeasurementsCsvReport report;
  std::string error;
  if (!ReadMeasurementsCsv(path, model, options, &measurements, &report,
                           &error)) {
    Fail("--" + flag + ": " + error);
  }
  // On stdout: stderr keeps one line for an error.
  for (const std::string& w : report.warnings) {
    std::cout << ProgramName() << ": warning: " << w << std::endl;
  }
  for (const std::string& n : report.notes) {
    std::cout << ProgramName() << ": note: " << n << std::endl;
  }
  if (lines) *lines = report.lines;
  return measurements;
}

std::vector<CommandedPose> ReadCommandedPosesOrDie(const std::string& path,
                                                   const RobotModel& model,
                                                   const std::string& flag) {
  MeasurementsCsvOptions options;
  options.column_map = ColumnMapOrDie();
  std::vector<CommandedPose> poses;
  std::string error;
  if (!ReadCommandedPosesCsv(path, model, options, &poses, &error)) {
    Fail("--" + flag + ": " + error);
  }
  return poses;
}

}  // namespace app
}  // namespace activecal
