// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// --points (a points file of known distances between fixed points,
// io/points_file.h) appended to the measurements, in a file of its own.

#include "activecal/io/points_file.h"
#include "app_common.h"

namespace activecal {
namespace app {

std::vector<Measurement> WithPointsFileOrDie(
    const std::string& path, std::vector<Measurement> measurements) {
  if (path.empty()) return measurements;
  std::vector<Measurement> distances;
  std::vector<int> lines;
  std::string error;
  if (!ReadPointsFile(path, &distances, &lines, &error) ||
      !CheckPointDistanceLabels(measurements, distances, lines, path, &error)) {
    Fail("--points: " + error);
  }
  measurements.insert(measurements.end(), distances.begin(), distances.end());
  return measurements;
}

}  // namespace app
}  // namespace activecal
