// Jacobians of the measurements with respect to the free parameters: the
// design matrix rows consumed by the pose selector. They are evaluated
// through the same cost functions the identification uses
// (position_residual.h), so selection and identification see the same
// derivatives.

#ifndef ACTIVECAL_RESIDUALS_JACOBIANS_H_
#define ACTIVECAL_RESIDUALS_JACOBIANS_H_

#include <Eigen/Core>
#include <string>

#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"

namespace activecal {

// The 3 x num_free Jacobian of the measured point at joint readings `joints`
// and the full parameter vector `parameters`, columns in free-parameter
// order. Returns false with a message on bad input.
bool PositionJacobian(const RobotModel& model,
                      const Eigen::VectorXd& parameters,
                      const Eigen::VectorXd& joints, Eigen::MatrixXd* jacobian,
                      std::string* error);

struct PoolJacobianOptions {
  // Threads to spread the poses over; <= 0: all hardware threads. The result
  // is the same for every thread count.
  int num_threads = 0;
};

// Jacobians of every pose in `joints` (one pose per row), stacked: rows
// 3i, 3i+1, 3i+2 are pose i's x, y, z rows. Row-major, so each pose's block
// is contiguous. Returns false with a message naming the first bad pose.
bool PoolPositionJacobians(const RobotModel& model,
                           const Eigen::VectorXd& parameters,
                           const Eigen::MatrixXd& joints,
                           const PoolJacobianOptions& options,
                           RowMatrixXd* stacked, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_RESIDUALS_JACOBIANS_H_
