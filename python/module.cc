// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: thin pybind11 bindings over the library,
// numpy in and out (docs/python.md). One file a library area binds its
// classes and functions (BindRobot, ..., common.h); this file calls them.

#include <glog/logging.h>

#include "common.h"

using namespace activecal;
using namespace activecal::python;

PYBIND11_MODULE(_activecal, m) {
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

  BindRobot(m);
  BindMeasurements(m);
  BindDesign(m);
  BindIdentify(m);
  BindCompensate(m);
  BindExport(m);
  BindReport(m);
}
