// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// --parameter_set and the function that reads it. A file of its own: the
// programs link activecal_app_common as a static library, so only those
// that call ParameterSetOrDie have (and list in
// --help) the flag.

#include <gflags/gflags.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

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
  ParameterSet set;
  std::string error;
  if (!ParseParameterSet(FLAGS_parameter_set, urdf_robot, &set, &error)) {
    Fail("--" + error);
  }
  return set;
}

}  // namespace app
}  // namespace activecal
