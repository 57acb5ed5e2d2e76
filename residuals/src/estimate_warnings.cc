#include "activecal/residuals/estimate_warnings.h"

#include <glog/logging.h>

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
  for (int k = 0; k < p; ++k) {
    const double sd = summary.standard_deviations[k];
    const double limit = is_length(k) ? options.max_std_m : options.max_std_rad;
    if (sd > limit) {
      std::ostringstream line;
      line << summary.names[k] << " has std " << sd << " "
           << model.ParameterUnit(free[k]) << " > " << limit
           << ": the measurements hardly determine it";
      lines.push_back(line.str());
    }
  }
  for (int a = 0; a < p; ++a) {
    for (int b = a + 1; b < p; ++b) {
      const double c = summary.correlation(a, b);
      if (std::abs(c) > options.max_abs_correlation) {
        std::ostringstream line;
        line.precision(4);
        line << summary.names[a] << " and " << summary.names[b]
             << " are correlated " << c
             << ": the measurements separate only their combination";
        lines.push_back(line.str());
      }
    }
  }
  // The moved ones in one line: a wrong nominal model moves many at once.
  std::ostringstream moved_line;
  moved_line.precision(3);
  int num_moved = 0;
  for (int k = 0; k < p; ++k) {
    const int i = free[k];
    const int block = model.BlockOf(i);
    if (block == 0 || model.is_marker_block(block)) continue;
    const double sd = summary.standard_deviations[k];
    const double moved = summary.estimates[k] - model.nominal[i];
    if (sd > 0 && std::abs(moved) > options.max_moved_std * sd) {
      moved_line << (num_moved++ ? ", " : " ") << summary.names[k] << " "
                 << moved << " " << model.ParameterUnit(i) << " ("
                 << std::abs(moved) / sd << " std)";
    }
  }
  if (num_moved > 0) {
    std::ostringstream line;
    line << num_moved << " link parameter" << (num_moved > 1 ? "s" : "")
         << " moved more than " << options.max_moved_std
         << " std from nominal (is the nominal model the right one?):"
         << moved_line.str();
    lines.push_back(line.str());
  }
  return lines;
}

}  // namespace activecal
