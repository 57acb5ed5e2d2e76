// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/estimate_warnings.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace activecal {

std::vector<std::string> EstimateWarnings(
    const RobotModel& model, const IdentificationSummary& summary,
    const EstimateWarningOptions& options) {
  std::vector<std::string> lines;
  const std::vector<int> free = model.FreeParameterIndices();
  const int p = static_cast<int>(free.size());
  CHECK_EQ(summary.standard_deviations.size(), p);
  CHECK_EQ(summary.correlation.rows(), p);
  auto is_length = [&](int k) {
    return std::string(model.ParameterUnit(free[k])) == "m";
  };
  // Stated sigmas that the residuals contradict (chi^2 / dof outside its
  // 99.9 % interval): the std the implied noise gives.
  const bool scaled = !summary.chi_square_plausible &&
                      summary.scaled_standard_deviations.size() == p;
  const Eigen::VectorXd& std_used =
      scaled ? summary.scaled_standard_deviations : summary.standard_deviations;
  const std::string std_label = scaled ? " scaled std" : " std";
  if (summary.weighted && !summary.chi_square_plausible &&
      summary.degrees_of_freedom > 0) {
    std::ostringstream line;
    line.precision(4);
    line << "chi^2 / dof = " << summary.chi_square_per_dof
         << " is outside the 99.9 % interval of chi-square for "
         << summary.degrees_of_freedom << " dof ["
         << summary.chi_square_per_dof_low << ", "
         << summary.chi_square_per_dof_high
         << "]: the stated sigmas do not describe the residuals, which imply "
         << summary.implied_sigma_m * 1e3
         << " mm per position row; the std below are scaled by sqrt(chi^2 / "
            "dof) = "
         << std::sqrt(summary.chi_square_per_dof) << " (scaled std)";
    lines.push_back(line.str());
  }
  for (int k = 0; k < p; ++k) {
    const double sd = std_used[k];
    const double limit = is_length(k) ? options.max_std_m : options.max_std_rad;
    if (sd > limit) {
      std::ostringstream line;
      line << summary.names[k] << " has" << std_label << " " << sd << " "
           << model.ParameterUnit(free[k]) << " > " << limit
           << ": the measurements hardly determine it";
      lines.push_back(line.str());
    }
  }
  // Correlations: parameters linked by pairs beyond the threshold form a
  // group, one line each (a pair as such; five parameters of one weak
  // direction are one line, not ten).
  std::vector<int> group(p);
  for (int k = 0; k < p; ++k) group[k] = k;
  auto root = [&](int k) {
    while (group[k] != k) k = group[k] = group[group[k]];
    return k;
  };
  auto beyond = [&](int a, int b) {
    return std::abs(summary.correlation(a, b)) > options.max_abs_correlation;
  };
  for (int a = 0; a < p; ++a) {
    for (int b = a + 1; b < p; ++b) {
      if (beyond(a, b))
        group[std::max(root(a), root(b))] = std::min(root(a), root(b));
    }
  }
  for (int r = 0; r < p; ++r) {
    std::vector<int> members;
    for (int k = r; k < p; ++k) {
      if (root(k) == r) members.push_back(k);
    }
    if (members.size() < 2) continue;
    std::ostringstream line;
    line.precision(4);
    if (members.size() == 2) {
      line << summary.names[members[0]] << " and " << summary.names[members[1]]
           << " are correlated " << summary.correlation(members[0], members[1])
           << ": the measurements separate only their combination";
    } else {
      int pairs = 0;
      double largest = 0.0;
      for (size_t i = 0; i < members.size(); ++i) {
        for (size_t j = i + 1; j < members.size(); ++j) {
          const double c = summary.correlation(members[i], members[j]);
          if (!beyond(members[i], members[j])) continue;
          ++pairs;
          if (std::abs(c) > std::abs(largest)) largest = c;
        }
      }
      for (size_t i = 0; i < members.size(); ++i) {
        line << (i == 0                    ? ""
                 : i + 1 == members.size() ? " and "
                                           : ", ")
             << summary.names[members[i]];
      }
      line << " are correlated beyond " << options.max_abs_correlation << " in "
           << pairs << " of their pairs (up to " << largest
           << "): the measurements separate only combinations of them";
    }
    lines.push_back(line.str());
  }
  // The moved ones in one line: a wrong nominal model moves many at once.
  std::ostringstream moved_line;
  moved_line.precision(3);
  int num_moved = 0;
  for (int k = 0; k < p; ++k) {
    const int i = free[k];
    const int block = model.BlockOf(i);
    if (block == 0 || model.is_marker_block(block)) continue;
    const double sd = std_used[k];
    const double moved = summary.estimates[k] - model.nominal[i];
    const bool length = is_length(k);
    const double large = length ? options.max_moved_m : options.max_moved_rad;
    if (sd > 0 && std::abs(moved) > options.max_moved_std * sd &&
        std::abs(moved) > large) {
      // mm / mrad beside SI (a gain: per mille).
      const std::string unit = model.ParameterUnit(i);
      moved_line << (num_moved++ ? ", " : " ") << summary.names[k] << " "
                 << moved << " " << unit << " (" << 1e3 * moved << " "
                 << (length          ? "mm"
                     : unit == "rad" ? "mrad"
                                     : "per mille")
                 << ", " << std::abs(moved) / sd << std_label << ")";
    }
  }
  if (num_moved > 0) {
    std::ostringstream line;
    line << num_moved << " link parameter" << (num_moved > 1 ? "s" : "")
         << " moved from nominal by more than " << 1e3 * options.max_moved_m
         << " mm / " << 1e3 * options.max_moved_rad << " mrad and "
         << options.max_moved_std << std_label
         << " (is the nominal model the right one?):" << moved_line.str();
    lines.push_back(line.str());
  }
  return lines;
}

}  // namespace activecal
