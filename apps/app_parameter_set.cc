// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// --parameter_set and the function that reads it. A file of its own: the
// programs link activecal_app_common as a static library, so only those
// that call ParameterSetOrDie or ReducedParameterSetOrDie have (and list in
// --help) the flag.

#include <gflags/gflags.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "activecal/estimation/parameter_reduction.h"
#include "app_common.h"

DEFINE_string(parameter_set, "",
              "Which parameters to identify: registration (base frame and "
              "marker points), offsets (+ joint offsets), full (+ every "
              "geometric correction of every link), file (the robot file's "
              "'free' lists). Empty: full for a URDF robot, file otherwise. "
              "Sets other than file are reduced to what the measurements "
              "(or the pool) can separate; the parameters held are named.");

namespace activecal {
namespace app {

ParameterSet ParameterSetOrDie(bool urdf_robot) {
  ParameterSet set = urdf_robot ? ParameterSet::kFull : ParameterSet::kFile;
  if (!FLAGS_parameter_set.empty() &&
      !StringToParameterSet(FLAGS_parameter_set, &set)) {
    Fail("--parameter_set must be registration, offsets, full or file, got '" +
         FLAGS_parameter_set + "'");
  }
  return set;
}

FreeSet ReducedParameterSetOrDie(const RobotModel& model, bool urdf_robot,
                                 const Eigen::MatrixXd& joints) {
  const ParameterSet set = ParameterSetOrDie(urdf_robot);
  const Eigen::Index n = std::min<Eigen::Index>(joints.rows(), 2000);
  Eigen::MatrixXd sample(n, joints.cols());
  for (Eigen::Index i = 0; i < n; ++i) {
    sample.row(i) = joints.row(i * joints.rows() / n);
  }
  Eigen::VectorXd point = model.nominal;
  FreeSet free;
  std::vector<HeldParameter> dropped;
  std::string error;
  if (!ReduceParameterSet(model, set, MeasurementPlan(sample), 1.0, &point,
                          &free, &dropped, &error)) {
    Fail("--parameter_set=" + std::string(ParameterSetToString(set)) + ": " +
         error);
  }
  for (const HeldParameter& d : dropped) {
    std::printf("  --parameter_set=%s: %s held fixed: %s\n",
                ParameterSetToString(set), d.name.c_str(), d.reason.c_str());
  }
  return free;
}

}  // namespace app
}  // namespace activecal
