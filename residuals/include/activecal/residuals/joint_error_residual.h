// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The residual of one measurement with joint error terms (joint_errors.h:
// compliance under gravity, joint-periodic errors): the geometric residual
// (measurement_residual.h) with each joint's motion offset moved by its
// error e_i(q) = sum_t theta_t phi_t(q). The cost function takes the
// model's blocks and, last, one block of the terms' values theta; exact
// automatic derivatives through the templated kinematics.
//
// The features phi_t(q) (torques, sines, cosines) are fixed per
// measurement (computed at the nominal geometry, see joint_errors.h).
// Measurements of one pose only: a distance between two poses is refused
// (JointErrorResidualSupports).

#ifndef ACTIVECAL_RESIDUALS_JOINT_ERROR_RESIDUAL_H_
#define ACTIVECAL_RESIDUALS_JOINT_ERROR_RESIDUAL_H_

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "activecal/core/joint_errors.h"
#include "activecal/residuals/measurement_residual.h"

namespace activecal {

// A measurement the joint error residual handles (one pose).
inline bool JointErrorResidualSupports(const Measurement& m) {
  return m.type != MeasurementType::kDistance;
}

class JointErrorResidual {
 public:
  using CostFunction =
      ceres::DynamicAutoDiffCostFunction<JointErrorResidual, kAutoDiffStride>;

  JointErrorResidual(std::shared_ptr<const RobotModel> model,
                     const Measurement& measurement,
                     double rotation_weight_m_per_rad,
                     std::shared_ptr<const JointErrorModel> errors,
                     Eigen::VectorXd features)
      : model_(model),
        inner_(std::move(model), measurement, rotation_weight_m_per_rad),
        errors_(std::move(errors)),
        features_(std::move(features)) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    const RobotModel& model = *model_;
    const int n = model.num_joints();
    const T* theta = blocks[model.num_blocks()];
    std::vector<T> e(n);
    JointErrors(*errors_, features_, theta, n, e.data());
    std::vector<std::array<T, kMaxBlockSize>> moved(n);
    std::vector<const T*> shifted(blocks, blocks + model.num_blocks());
    for (int i = 0; i < n; ++i) {
      const int size = model.block_size(i + 1);
      for (int j = 0; j < size; ++j) moved[i][j] = blocks[i + 1][j];
      moved[i][MotionOffsetEntry(model.links[i])] += e[i];
      shifted[i + 1] = moved[i].data();
    }
    return inner_(shifted.data(), residuals);
  }

  static CostFunction* Create(std::shared_ptr<const RobotModel> model,
                              const Measurement& measurement,
                              double rotation_weight_m_per_rad,
                              std::shared_ptr<const JointErrorModel> errors,
                              Eigen::VectorXd features) {
    const RobotModel& m = *model;
    const int num_terms = errors->size();
    const int rows = measurement.dimension();
    auto* cost = new CostFunction(new JointErrorResidual(
        std::move(model), measurement, rotation_weight_m_per_rad,
        std::move(errors), std::move(features)));
    for (int b = 0; b < m.num_blocks(); ++b) {
      cost->AddParameterBlock(m.block_size(b));
    }
    cost->AddParameterBlock(num_terms);
    cost->SetNumResiduals(rows);
    return cost;
  }

 private:
  std::shared_ptr<const RobotModel> model_;
  MeasurementResidual inner_;
  std::shared_ptr<const JointErrorModel> errors_;
  Eigen::VectorXd features_;
};

}  // namespace activecal

#endif  // ACTIVECAL_RESIDUALS_JOINT_ERROR_RESIDUAL_H_
