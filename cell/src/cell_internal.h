// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Small helpers shared by the cell library's sources (not installed).

#ifndef ACTIVECAL_CELL_SRC_CELL_INTERNAL_H_
#define ACTIVECAL_CELL_SRC_CELL_INTERNAL_H_

#include <string>

#include "activecal/core/robot_model.h"

namespace activecal {
namespace internal {

// a followed by b: x -> a(b(x)).
inline FixedTransform Compose(const FixedTransform& a,
                              const FixedTransform& b) {
  FixedTransform t;
  t.rotation = a.rotation * b.rotation;
  t.translation = a.translation + a.rotation * b.translation;
  return t;
}

// The folder of a path ("" for a bare file name).
inline std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "" : path.substr(0, slash);
}

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_CELL_SRC_CELL_INTERNAL_H_
