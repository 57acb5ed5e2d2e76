// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Ceres residual of one measurement (measurement.h): predicted minus
// measured, with exact automatic derivatives through the templated
// kinematics.
//
//   position  3 rows (m):  predicted point - measured point
//   pose      6 rows:      predicted point - measured point (m), then
//                          w * Log(R_measured^T R_predicted) (rad scaled by
//                          w, the rotation weight in m/rad)
//   distance  1 row (m):   |p(q1) - p(q2)| - measured distance
//   point     3 rows (m):  predicted point - c, c the fixed point's
//                          coordinates (an extra parameter block of 3,
//                          after the model's)
//   point_distance 1 row (m): |c1 - c2| - known distance (two extra
//                          blocks of 3; the model's blocks have no effect)
//   plane     1 row (m):   n . p - d - probe radius, (n, d) the plane's
//                          block of 4 after the model's (unit normal n,
//                          offset d; Ceres keeps n on the sphere with
//                          PlaneManifold, plane_constraints.h)
//
// The rotation weight puts the orientation rows on the same scale as the
// position rows; set it to sigma_position / sigma_rotation of the device so
// every row has the same noise (identification assumes that).
//
// The cost function takes one parameter block per group of the RobotModel
// (base, each link, tool; see robot_model.h), so any group can be held
// constant with Problem::SetParameterBlockConstant and part of one with a
// SubsetManifold. It is a ceres::DynamicAutoDiffCostFunction because the
// number of blocks is the robot's, known only at run time.
//
//   std::shared_ptr<const RobotModel> model = ...;
//   ceres::CostFunction* cost = MeasurementResidual::Create(model, m);
//   std::vector<double*> blocks = ...;  // model->num_blocks() pointers
//   problem.AddResidualBlock(cost, nullptr, blocks);

#ifndef ACTIVECAL_RESIDUALS_MEASUREMENT_RESIDUAL_H_
#define ACTIVECAL_RESIDUALS_MEASUREMENT_RESIDUAL_H_

#include <ceres/dynamic_autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <utility>

#include "activecal/core/kinematics.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// Derivatives are propagated this many at a time (Jet size). 14 covers the
// PUMA's 42 parameters of its seven non-constant blocks in three passes.
inline constexpr int kAutoDiffStride = 14;

class MeasurementResidual {
 public:
  using CostFunction =
      ceres::DynamicAutoDiffCostFunction<MeasurementResidual, kAutoDiffStride>;

  MeasurementResidual(std::shared_ptr<const RobotModel> model,
                      Measurement measurement, double rotation_weight_m_per_rad)
      : model_(std::move(model)),
        m_(std::move(measurement)),
        rotation_weight_(rotation_weight_m_per_rad) {
    const double angle = m_.rotation.norm();
    measured_rotation_transposed_ =
        (angle > 0
             ? Eigen::AngleAxisd(angle, m_.rotation / angle).toRotationMatrix()
             : Eigen::Matrix3d::Identity())
            .transpose();
  }

  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    switch (m_.type) {
      case MeasurementType::kPosition: {
        const Vector3<T> p =
            MeasuredPoint<T>(*model_, blocks, m_.joints.data(), m_.marker);
        for (int k = 0; k < 3; ++k) residuals[k] = p[k] - T(m_.position[k]);
        return true;
      }
      case MeasurementType::kPose: {
        Matrix3<T> R;
        Vector3<T> t;
        TargetFrame<T>(*model_, blocks, m_.joints.data(), &R, &t, m_.marker);
        for (int k = 0; k < 3; ++k) residuals[k] = t[k] - T(m_.position[k]);
        const Matrix3<T> error =
            measured_rotation_transposed_.template cast<T>() * R;
        T log[3];
        ceres::RotationMatrixToAngleAxis(error.data(), log);
        for (int k = 0; k < 3; ++k) {
          residuals[3 + k] = T(rotation_weight_) * log[k];
        }
        return true;
      }
      case MeasurementType::kDistance: {
        const Vector3<T> a =
            MeasuredPoint<T>(*model_, blocks, m_.joints.data(), m_.marker);
        const Vector3<T> b =
            MeasuredPoint<T>(*model_, blocks, m_.joints2.data(), m_.marker);
        // Coinciding points (up to rounding, 1e-12 m): the norm has no
        // derivative there (NaN) or a meaningless one.
        if ((a - b).squaredNorm() < T(1e-24)) return false;
        residuals[0] = (a - b).norm() - T(m_.distance);
        return true;
      }
      case MeasurementType::kPoint: {
        const Vector3<T> p =
            MeasuredPoint<T>(*model_, blocks, m_.joints.data(), m_.marker);
        const T* c = blocks[model_->num_blocks()];
        for (int k = 0; k < 3; ++k) residuals[k] = p[k] - c[k];
        return true;
      }
      case MeasurementType::kPointDistance: {
        const T* a = blocks[model_->num_blocks()];
        const T* b = blocks[model_->num_blocks() + 1];
        const Vector3<T> d(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
        if (d.squaredNorm() < T(1e-24)) return false;
        residuals[0] = d.norm() - T(m_.distance);
        return true;
      }
      case MeasurementType::kPlane: {
        const Vector3<T> p =
            MeasuredPoint<T>(*model_, blocks, m_.joints.data(), m_.marker);
        const T* plane = blocks[model_->num_blocks()];
        residuals[0] = plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] -
                       plane[3] - T(m_.probe_radius_m);
        return true;
      }
    }
    return false;
  }

  // The parameter blocks of fixed points (3 each) or planes (4) a
  // measurement of `type` takes after the model's: 1 for a point or a
  // plane, 2 for a point distance.
  static int NumPointBlocks(MeasurementType type) {
    return type == MeasurementType::kPoint           ? 1
           : type == MeasurementType::kPlane         ? 1
           : type == MeasurementType::kPointDistance ? 2
                                                     : 0;
  }

  // A cost function with the model's blocks declared (then the point
  // blocks, NumPointBlocks), owned by the caller (or by the ceres::Problem
  // it is added to).
  static CostFunction* Create(std::shared_ptr<const RobotModel> model,
                              Measurement measurement,
                              double rotation_weight_m_per_rad = 1.0) {
    const RobotModel& m = *model;
    const int rows = measurement.dimension();
    const MeasurementType type = measurement.type;
    auto* cost = new CostFunction(new MeasurementResidual(
        std::move(model), std::move(measurement), rotation_weight_m_per_rad));
    const int extra = NumPointBlocks(type);
    for (int b = 0; b < m.num_blocks(); ++b) {
      cost->AddParameterBlock(m.block_size(b));
    }
    for (int k = 0; k < extra; ++k) {
      cost->AddParameterBlock(type == MeasurementType::kPlane ? 4 : 3);
    }
    cost->SetNumResiduals(rows);
    return cost;
  }

 private:
  std::shared_ptr<const RobotModel> model_;
  Measurement m_;
  double rotation_weight_;
  Eigen::Matrix3d measured_rotation_transposed_;
};

}  // namespace activecal

#endif  // ACTIVECAL_RESIDUALS_MEASUREMENT_RESIDUAL_H_
