// Common matrix types.

#ifndef ACTIVECAL_CORE_TYPES_H_
#define ACTIVECAL_CORE_TYPES_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>

namespace activecal {

// Row-major dynamic matrix: stacked Jacobian blocks are contiguous per pose.
using RowMatrixXd =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Reports progress of long work: `done` of `total` units (poses, restarts,
// rounds). It may be called from several worker threads at once, so it must
// be thread-safe; it never changes a result. Empty: no reports.
using ProgressCallback = std::function<void(int64_t done, int64_t total)>;

}  // namespace activecal

#endif  // ACTIVECAL_CORE_TYPES_H_
