// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/residuals/jacobians.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

#include "activecal/core/kinematics.h"
#include "activecal/core/parallel.h"
#include "activecal/core/point_jacobian.h"
#include "activecal/residuals/measurement_residual.h"

namespace activecal {
namespace {

// Evaluates MeasurementResidual Jacobians for one model and parameter
// vector, asking Ceres only for blocks that hold free parameters. Not
// thread-safe: use one per thread.
class JacobianEvaluator {
 public:
  JacobianEvaluator(std::shared_ptr<const RobotModel> model,
                    const Eigen::VectorXd& parameters, double rotation_weight)
      : model_(std::move(model)),
        parameters_(parameters),
        rotation_weight_(rotation_weight) {
    const RobotModel& m = *model_;
    blocks_ = BlockPointers(m, parameters_.data());
    block_jacobians_.resize(m.num_blocks());
    jacobian_ptrs_.assign(m.num_blocks(), nullptr);
    for (int b = 0; b < m.num_blocks(); ++b) {
      for (int j = 0; j < m.block_size(b); ++j) {
        if (m.IsFree(m.block_offset(b) + j)) columns_.push_back({b, j});
      }
    }
  }

  // Writes the dimension() x num_free Jacobian, row-major, to `jacobian`
  // and, if not null, the residuals to `residuals`.
  bool Evaluate(const Measurement& measurement, double* jacobian,
                double* residuals = nullptr) {
    const RobotModel& m = *model_;
    const int rows = measurement.dimension();
    std::unique_ptr<ceres::CostFunction> cost(
        MeasurementResidual::Create(model_, measurement, rotation_weight_));
    double r[6];
    if (jacobian) {
      // Ask Ceres only for the blocks that hold a free parameter.
      for (const auto& [b, j] : columns_) {
        block_jacobians_[b].resize(rows * m.block_size(b));
        jacobian_ptrs_[b] = block_jacobians_[b].data();
      }
    }
    if (!cost->Evaluate(blocks_.data(), r,
                        jacobian ? jacobian_ptrs_.data() : nullptr)) {
      return false;
    }
    if (residuals) std::copy(r, r + rows, residuals);
    if (!jacobian) return true;
    const int p = static_cast<int>(columns_.size());
    for (int c = 0; c < p; ++c) {
      const auto [b, j] = columns_[c];
      const int size = m.block_size(b);
      for (int k = 0; k < rows; ++k) {
        jacobian[k * p + c] = block_jacobians_[b][k * size + j];
      }
    }
    return true;
  }

 private:
  std::shared_ptr<const RobotModel> model_;
  Eigen::VectorXd parameters_;
  double rotation_weight_;
  std::vector<const double*> blocks_;
  std::vector<std::vector<double>> block_jacobians_;
  std::vector<double*> jacobian_ptrs_;
  std::vector<std::pair<int, int>> columns_;  // (block, index in block)
};

bool CheckInputs(const RobotModel& model, const Eigen::VectorXd& parameters,
                 double rotation_weight, std::string* error) {
  if (!model.Validate(error)) return false;
  if (!model.CheckParameters(parameters, error)) return false;
  if (model.num_free() == 0) {
    if (error) *error = "robot '" + model.name + "': no free parameters";
    return false;
  }
  if (!(rotation_weight > 0) || !std::isfinite(rotation_weight)) {
    if (error) {
      *error = "rotation weight must be finite and > 0, got " +
               std::to_string(rotation_weight);
    }
    return false;
  }
  return true;
}

bool CheckAll(const RobotModel& model,
              const std::vector<Measurement>& measurements,
              std::string* error) {
  for (size_t i = 0; i < measurements.size(); ++i) {
    std::string why;
    if (!CheckMeasurement(model, measurements[i], &why)) {
      if (error) *error = "measurement " + std::to_string(i) + ": " + why;
      return false;
    }
  }
  return true;
}

}  // namespace

bool MeasurementJacobian(const RobotModel& model,
                         const Eigen::VectorXd& parameters,
                         const Measurement& measurement,
                         double rotation_weight_m_per_rad,
                         Eigen::MatrixXd* jacobian, std::string* error) {
  return StackedJacobian(model, parameters, {measurement},
                         rotation_weight_m_per_rad, jacobian, error);
}

bool StackedJacobian(const RobotModel& model, const Eigen::VectorXd& parameters,
                     const std::vector<Measurement>& measurements,
                     double rotation_weight_m_per_rad,
                     Eigen::MatrixXd* jacobian, std::string* error) {
  if (!CheckInputs(model, parameters, rotation_weight_m_per_rad, error) ||
      !CheckAll(model, measurements, error)) {
    return false;
  }
  int rows = 0;
  for (const Measurement& m : measurements) rows += m.dimension();
  const int p = model.num_free();
  RowMatrixXd J(rows, p);
  JacobianEvaluator evaluator(std::make_shared<const RobotModel>(model),
                              parameters, rotation_weight_m_per_rad);
  int row = 0;
  for (size_t i = 0; i < measurements.size(); ++i) {
    if (!evaluator.Evaluate(measurements[i], J.data() + row * p)) {
      if (error) {
        *error = "measurement " + std::to_string(i) +
                 (measurements[i].type == MeasurementType::kDistance
                      ? ": the distance's two poses put the measured point at "
                        "the same place (the points coincide): its Jacobian "
                        "is undefined"
                      : ": Jacobian evaluation failed");
      }
      return false;
    }
    row += measurements[i].dimension();
  }
  *jacobian = J;
  return true;
}

bool MeasurementErrors(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const std::vector<Measurement>& measurements,
                       double rotation_weight_m_per_rad, Eigen::VectorXd* norms,
                       std::string* error) {
  if (!model.Validate(error) || !model.CheckParameters(parameters, error) ||
      !CheckAll(model, measurements, error)) {
    return false;
  }
  JacobianEvaluator evaluator(std::make_shared<const RobotModel>(model),
                              parameters, rotation_weight_m_per_rad);
  norms->resize(measurements.size());
  for (size_t i = 0; i < measurements.size(); ++i) {
    double r[6];
    if (!evaluator.Evaluate(measurements[i], nullptr, r)) {
      if (error) {
        *error = "measurement " + std::to_string(i) + ": evaluation failed";
      }
      return false;
    }
    (*norms)[i] =
        Eigen::Map<Eigen::VectorXd>(r, measurements[i].dimension()).norm();
  }
  return true;
}

bool PoolJacobians(const RobotModel& model, const Eigen::VectorXd& parameters,
                   const Eigen::MatrixXd& joints,
                   const PoolJacobianOptions& options, RowMatrixXd* stacked,
                   std::string* error) {
  if (!CheckInputs(model, parameters, options.rotation_weight_m_per_rad,
                   error)) {
    return false;
  }
  stacked->resize(MeasurementDimension(options.type) * joints.rows(),
                  model.num_free());
  return PoolJacobians(model, parameters, joints, options, stacked->data(),
                       error);
}

bool PoolJacobians(const RobotModel& model, const Eigen::VectorXd& parameters,
                   const Eigen::MatrixXd& joints,
                   const PoolJacobianOptions& options, double* out,
                   std::string* error) {
  if (!CheckInputs(model, parameters, options.rotation_weight_m_per_rad,
                   error)) {
    return false;
  }
  if (options.type == MeasurementType::kDistance) {
    if (error) {
      *error =
          "pool: a distance measurement needs two poses; pool Jacobians "
          "are per pose (position or pose)";
    }
    return false;
  }
  if (joints.cols() != model.num_joints()) {
    if (error) {
      *error = "pool: expected " + std::to_string(model.num_joints()) +
               " joint values per pose, got " + std::to_string(joints.cols());
    }
    return false;
  }
  if (options.marker < 0 || options.marker >= model.num_markers()) {
    if (error) {
      *error = "pool: marker must be in [0, " +
               std::to_string(model.num_markers() - 1) + "], got " +
               std::to_string(options.marker);
    }
    return false;
  }
  const int64_t n = joints.rows();
  for (int64_t i = 0; i < n; ++i) {
    // Inside every range and finite: valid (CheckJointValues, which builds
    // its message, only for a pose that is not).
    bool inside = true;
    for (int j = 0; j < model.num_joints(); ++j) {
      const double v = joints(i, j);
      const Link& link = model.links[j];
      inside = inside && std::isfinite(v) && v >= link.joint_min &&
               v <= link.joint_max;
    }
    if (inside) continue;
    std::string why;
    if (!model.CheckJointValues(joints.row(i).transpose(), &why,
                                options.joint_tolerance_rad,
                                options.joint_tolerance_m)) {
      if (error) *error = "pool pose " + std::to_string(i) + ": " + why;
      return false;
    }
  }
  const int p = model.num_free();
  const int t = MeasurementDimension(options.type);
  auto shared = std::make_shared<const RobotModel>(model);
  std::atomic<int64_t> failed{-1};
  std::atomic<int64_t> done{0};
  constexpr int64_t kReportEvery = 4096;
  const bool analytic =
      options.analytic && options.type == MeasurementType::kPosition;
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  // The pose-independent work once, shared by the threads (immutable).
  std::unique_ptr<const PointJacobianKernel> kernel;
  if (analytic) {
    kernel = std::make_unique<const PointJacobianKernel>(model, blocks.data(),
                                                         options.marker);
  }
  ParallelFor(n, options.num_threads, [&](int64_t begin, int64_t end, int) {
    auto report = [&](int64_t i) {
      if (options.progress && (i - begin + 1) % kReportEvery == 0) {
        options.progress(done += kReportEvery, n);
      }
    };
    if (analytic) {
      // Poses in runs of kReportEvery (the kernel's bits do not depend on
      // the run).
      for (int64_t i = begin; i < end; i += kReportEvery) {
        const int64_t count = std::min(kReportEvery, end - i);
        kernel->Evaluate(count, joints.data() + i, 1, n, out + t * i * p);
        report(i + count - 1);
      }
      return;
    }
    JacobianEvaluator evaluator(shared, parameters,
                                options.rotation_weight_m_per_rad);
    Measurement m;
    m.type = options.type;
    m.marker = options.marker;
    for (int64_t i = begin; i < end; ++i) {
      m.joints = joints.row(i).transpose();
      if (!evaluator.Evaluate(m, out + t * i * p)) {
        failed = i;
        return;
      }
      report(i);
    }
  });
  if (options.progress) options.progress(n, n);
  if (failed >= 0) {
    if (error) {
      *error = "Jacobian evaluation failed at pool pose " +
               std::to_string(failed.load());
    }
    return false;
  }
  return true;
}

}  // namespace activecal
