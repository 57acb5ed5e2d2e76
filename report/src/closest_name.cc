// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/report/closest_name.h"

#include <algorithm>
#include <limits>

namespace activecal {

int EditDistance(const std::string& a, const std::string& b) {
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1,
                         diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string ClosestName(const std::string& name,
                        const std::vector<std::string>& names) {
  std::string best;
  int best_distance = std::numeric_limits<int>::max();
  for (const std::string& candidate : names) {
    const int d = EditDistance(name, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  // --num_pose for --num_poses: 1.
  const int tolerance = std::max(2, static_cast<int>(name.size()) / 3);
  return best_distance <= tolerance ? best : "";
}

}  // namespace activecal
