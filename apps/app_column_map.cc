// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// --column_map and the function that reads it, in a file of its own (see
// app_parameter_set.cc): the programs that read measurements call
// ColumnMapOrDie().

#include <gflags/gflags.h>

#include "app_common.h"

DEFINE_string(column_map, "",
              "A YAML column map (docs/formats.md, \"Column maps\") to read "
              "the measurements file as a device exports it: its delimiter, "
              "decimal comma, column names and Euler-angle orientation. "
              "Default: the file is in activecal's own form.");

namespace activecal {
namespace app {

const std::optional<ColumnMap>& ColumnMapOrDie() {
  static const std::optional<ColumnMap> map = [] {
    std::optional<ColumnMap> m;
    if (FLAGS_column_map.empty()) return m;
    ColumnMap read;
    std::string error;
    if (!ReadColumnMap(FLAGS_column_map, &read, &error)) {
      Fail("--column_map: " + error);
    }
    m = read;
    return m;
  }();
  return map;
}

}  // namespace app
}  // namespace activecal
