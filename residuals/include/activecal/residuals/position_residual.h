// The Ceres residual of a 3D position measurement (laser tracker, stereo
// camera): predicted measured point minus measured point, in metres.
//
// The cost function takes one parameter block per group of the RobotModel
// (base, each link, tool; see robot_model.h), so any group can be held
// constant with Problem::SetParameterBlockConstant and part of one with a
// SubsetManifold. It is a ceres::DynamicAutoDiffCostFunction because the
// number of blocks is the robot's, known only at run time; the derivatives
// are exact automatic derivatives through the templated kinematics.
//
//   std::shared_ptr<const RobotModel> model = ...;
//   ceres::CostFunction* cost =
//       PositionResidual::Create(model, joints, measured_point);
//   std::vector<double*> blocks = ...;  // model->num_blocks() pointers
//   problem.AddResidualBlock(cost, nullptr, blocks);

#ifndef ACTIVECAL_RESIDUALS_POSITION_RESIDUAL_H_
#define ACTIVECAL_RESIDUALS_POSITION_RESIDUAL_H_

#include <ceres/dynamic_autodiff_cost_function.h>

#include <Eigen/Core>
#include <memory>
#include <utility>

#include "activecal/core/kinematics.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// Derivatives are propagated this many at a time (Jet size). 14 covers the
// PUMA's 42 parameters of its seven non-constant blocks in three passes.
inline constexpr int kAutoDiffStride = 14;

class PositionResidual {
 public:
  using CostFunction =
      ceres::DynamicAutoDiffCostFunction<PositionResidual, kAutoDiffStride>;

  // joints: model->num_joints() readings; measured: the device's reading.
  PositionResidual(std::shared_ptr<const RobotModel> model,
                   Eigen::VectorXd joints, const Eigen::Vector3d& measured)
      : model_(std::move(model)),
        joints_(std::move(joints)),
        measured_(measured) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    const Vector3<T> p = MeasuredPoint<T>(*model_, blocks, joints_.data());
    for (int k = 0; k < 3; ++k) residuals[k] = p[k] - T(measured_[k]);
    return true;
  }

  // A cost function with the model's blocks declared, owned by the caller
  // (or by the ceres::Problem it is added to).
  static CostFunction* Create(std::shared_ptr<const RobotModel> model,
                              Eigen::VectorXd joints,
                              const Eigen::Vector3d& measured) {
    const RobotModel& m = *model;
    auto* cost = new CostFunction(
        new PositionResidual(std::move(model), std::move(joints), measured));
    for (int b = 0; b < m.num_blocks(); ++b) {
      cost->AddParameterBlock(m.block_size(b));
    }
    cost->SetNumResiduals(3);
    return cost;
  }

 private:
  std::shared_ptr<const RobotModel> model_;
  Eigen::VectorXd joints_;
  Eigen::Vector3d measured_;
};

}  // namespace activecal

#endif  // ACTIVECAL_RESIDUALS_POSITION_RESIDUAL_H_
