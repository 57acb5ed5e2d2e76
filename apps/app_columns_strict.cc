// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// --columns_strict and the function that reads it, in a file of its own
// (see app_parameter_set.cc): the programs that read a file with optional
// columns (measurements, Cartesian targets) call ColumnsStrict().

#include <gflags/gflags.h>

#include "app_common.h"

DEFINE_bool(columns_strict, false,
            "Refuse a measurements or targets file with columns activecal "
            "does not read (a device's temperature, timestamps, ...). "
            "Default: they are ignored and listed in a note.");

namespace activecal {
namespace app {

bool ColumnsStrict() { return FLAGS_columns_strict; }

}  // namespace app
}  // namespace activecal
