// Common matrix types.

#ifndef ACTIVECAL_CORE_TYPES_H_
#define ACTIVECAL_CORE_TYPES_H_

#include <Eigen/Core>

namespace activecal {

// Row-major dynamic matrix: stacked Jacobian blocks are contiguous per pose.
using RowMatrixXd =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace activecal

#endif  // ACTIVECAL_CORE_TYPES_H_
