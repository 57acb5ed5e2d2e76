// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// --points (a points file of known distances between fixed points,
// io/points_file.h) appended to the measurements, and the fixed points'
// spread (identify, evaluate), in a file of their own.

#include <cstdio>

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

std::string PointSpreadText(const EvaluationSummary& summary) {
  std::string text;
  char line[512];
  for (size_t k = 0; k < summary.point_labels.size(); ++k) {
    const ErrorStatistics& s = summary.point_spread[k];
    const Eigen::Vector3d& c = summary.point_coordinates[k];
    std::snprintf(line, sizeof(line),
                  "  point %s (%d rows, refitted at %.6f, %.6f, %.6f m): "
                  "distance to the point's mean %.3f mm mean, RMS %.3f mm, "
                  "max %.3f mm\n",
                  summary.point_labels[k].c_str(), s.count, c.x(), c.y(), c.z(),
                  s.mean * 1e3, s.rms * 1e3, s.max * 1e3);
    text += line;
  }
  for (size_t k = 0; k < summary.plane_labels.size(); ++k) {
    const ErrorStatistics& s = summary.plane_flatness[k];
    const Eigen::Vector4d& p = summary.plane_parameters[k];
    std::snprintf(line, sizeof(line),
                  "  plane %s (%d rows, refitted: normal %.6f, %.6f, %.6f, "
                  "offset %.6f m): flatness RMS %.3f mm, max %.3f mm\n",
                  summary.plane_labels[k].c_str(), s.count, p[0], p[1], p[2],
                  p[3], s.rms * 1e3, s.max * 1e3);
    text += line;
  }
  return text;
}

}  // namespace app
}  // namespace activecal
