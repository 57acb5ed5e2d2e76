// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/residuals/jacobians.h"

#include <Eigen/QR>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <vector>

#include "activecal/core/kinematics.h"
#include "activecal/core/parallel.h"
#include "activecal/core/plane_constraints.h"
#include "activecal/core/point_constraints.h"
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
  // and, if not null, the residuals to `residuals`. A plane row needs its
  // plane's 4 values (n, d) in `plane`.
  bool Evaluate(const Measurement& measurement, double* jacobian,
                double* residuals = nullptr, const double* plane = nullptr) {
    const RobotModel& m = *model_;
    const int rows = measurement.dimension();
    std::unique_ptr<ceres::CostFunction> cost(
        MeasurementResidual::Create(model_, measurement, rotation_weight_));
    double r[6];
    if (measurement.type == MeasurementType::kPointDistance) {
      // Depends on the points' coordinates only (StackedJacobian).
      if (jacobian) std::fill(jacobian, jacobian + rows * columns_.size(), 0.0);
      if (residuals) std::fill(residuals, residuals + rows, 0.0);
      return true;
    }
    // A point row's point block (its coordinates do not change the
    // Jacobian of the model's blocks): zero here.
    std::vector<const double*> blocks = blocks_;
    const double zero_point[3] = {0.0, 0.0, 0.0};
    if (measurement.type == MeasurementType::kPoint) {
      blocks.push_back(zero_point);
      jacobian_ptrs_.resize(m.num_blocks() + 1, nullptr);
    }
    if (measurement.type == MeasurementType::kPlane) {
      if (plane == nullptr) return false;
      blocks.push_back(plane);
      jacobian_ptrs_.resize(m.num_blocks() + 1, nullptr);
    }
    if (jacobian) {
      // Ask Ceres only for the blocks that hold a free parameter.
      for (const auto& [b, j] : columns_) {
        block_jacobians_[b].resize(rows * m.block_size(b));
        jacobian_ptrs_[b] = block_jacobians_[b].data();
      }
    }
    const bool ok = cost->Evaluate(blocks.data(), r,
                                   jacobian ? jacobian_ptrs_.data() : nullptr);
    jacobian_ptrs_.resize(m.num_blocks());
    if (!ok) return false;
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

// The Jacobian with the fixed points' coordinates eliminated
// (jacobians.h): point rows evaluated at their consistent joints, then the
// columns of the points' coordinates projected out of every row that
// involves them.
bool EliminatedPointJacobian(const RobotModel& model,
                             const Eigen::VectorXd& parameters,
                             const std::vector<Measurement>& measurements,
                             double rotation_weight, RowMatrixXd* J,
                             std::string* error) {
  const std::vector<std::string> labels = PointLabels(measurements);
  const std::vector<Eigen::Vector3d> centre =
      MeanPointPositions(model, parameters, measurements, labels);
  // Planes: fitted to the predicted touches; 3 columns each (a tangent
  // step of the normal, the offset), after the points'.
  const std::vector<std::string> plane_labels = PlaneLabels(measurements);
  std::vector<Eigen::Vector4d> planes;
  if (!FitPlanes(model, parameters, measurements, plane_labels, &planes,
                 error)) {
    return false;
  }
  const int p = model.num_free();
  const int num_points_c = 3 * static_cast<int>(labels.size());
  const int num_c = num_points_c + 3 * static_cast<int>(plane_labels.size());
  JacobianEvaluator evaluator(std::make_shared<const RobotModel>(model),
                              parameters, rotation_weight);
  std::vector<int> point_rows;  // rows that involve the coordinates
  Eigen::MatrixXd Jc;           // their derivatives by the coordinates
  std::vector<Eigen::RowVectorXd> jc_rows;
  int row = 0;
  for (size_t i = 0; i < measurements.size(); ++i) {
    Measurement m = measurements[i];
    const int t = m.dimension();
    if (m.type == MeasurementType::kPoint) {
      // Where the model itself reaches the label's point: there the
      // motions of the robot and the points together that leave the rows
      // unchanged (a rotation of the base with the points, a scale) are
      // exact null directions, as they are at the solution, and the
      // reduction sees them as such.
      ReachPoint(model, parameters, m.marker,
                 centre[LabelIndex(labels, m.point)], &m.joints);
    }
    const double* plane = nullptr;
    if (m.type == MeasurementType::kPlane) {
      // The same for a touch: the nearest joints at which the model puts
      // the probe's centre at its radius from the fitted plane.
      const Eigen::Vector4d& pl = planes[LabelIndex(plane_labels, m.plane)];
      const Eigen::Vector3d c =
          MeasuredPoint(model, parameters, m.joints, m.marker);
      ReachPoint(model, parameters, m.marker,
                 c - PlaneResidual(pl, c, m.probe_radius_m) * pl.head<3>(),
                 &m.joints);
      plane = pl.data();
    }
    if (!evaluator.Evaluate(m, J->data() + row * p, nullptr, plane)) {
      if (error) {
        *error = "measurement " + std::to_string(i) +
                 (m.type == MeasurementType::kDistance
                      ? ": the distance's two poses put the measured point at "
                        "the same place (the points coincide): its Jacobian "
                        "is undefined"
                      : ": Jacobian evaluation failed");
      }
      return false;
    }
    if (m.type == MeasurementType::kPoint) {
      const int k = LabelIndex(labels, m.point);
      for (int a = 0; a < 3; ++a) {
        Eigen::RowVectorXd r = Eigen::RowVectorXd::Zero(num_c);
        r[3 * k + a] = -1.0;
        jc_rows.push_back(r);
        point_rows.push_back(row + a);
      }
    } else if (m.type == MeasurementType::kPlane) {
      const int k = LabelIndex(plane_labels, m.plane);
      const Eigen::Vector4d& pl = planes[k];
      const Eigen::Matrix<double, 3, 2> basis = PlaneTangentBasis(pl.head<3>());
      const Eigen::Vector3d c =
          MeasuredPoint(model, parameters, m.joints, m.marker);
      Eigen::RowVectorXd r = Eigen::RowVectorXd::Zero(num_c);
      r[num_points_c + 3 * k] = basis.col(0).dot(c);
      r[num_points_c + 3 * k + 1] = basis.col(1).dot(c);
      r[num_points_c + 3 * k + 2] = -1.0;
      jc_rows.push_back(r);
      point_rows.push_back(row);
    } else if (m.type == MeasurementType::kPointDistance) {
      const int a = LabelIndex(labels, m.point),
                b = LabelIndex(labels, m.point2);
      const Eigen::Vector3d d = centre[a] - centre[b];
      if (d.norm() < 1e-12) {
        if (error) {
          *error = "measurement " + std::to_string(i) + ": points '" + m.point +
                   "' and '" + m.point2 +
                   "' are predicted at the same place: the distance's "
                   "Jacobian is undefined";
        }
        return false;
      }
      Eigen::RowVectorXd r = Eigen::RowVectorXd::Zero(num_c);
      r.segment<3>(3 * a) = d.normalized().transpose();
      r.segment<3>(3 * b) = -d.normalized().transpose();
      jc_rows.push_back(r);
      point_rows.push_back(row);
    }
    row += t;
  }
  const int s = static_cast<int>(point_rows.size());
  Jc.resize(s, num_c);
  Eigen::MatrixXd Jt(s, p);
  for (int k = 0; k < s; ++k) {
    Jc.row(k) = jc_rows[k];
    Jt.row(k) = J->row(point_rows[k]);
  }
  // Jt - Q Q^T Jt, Q an orthonormal basis of the coordinates' columns.
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Jc);
  const int rank = static_cast<int>(qr.rank());
  const Eigen::MatrixXd Q = Eigen::MatrixXd(qr.householderQ()).leftCols(rank);
  Jt -= Q * (Q.transpose() * Jt);
  for (int k = 0; k < s; ++k) J->row(point_rows[k]) = Jt.row(k);
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
  if (HasPointRows(measurements)) {
    if (!EliminatedPointJacobian(model, parameters, measurements,
                                 rotation_weight_m_per_rad, &J, error)) {
      return false;
    }
    *jacobian = J;
    return true;
  }
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
  const std::vector<std::string> labels = PointLabels(measurements);
  const std::vector<Eigen::Vector3d> centre =
      MeanPointPositions(model, parameters, measurements, labels);
  auto centre_of = [&](const std::string& label) {
    return centre[std::find(labels.begin(), labels.end(), label) -
                  labels.begin()];
  };
  const std::vector<std::string> plane_labels = PlaneLabels(measurements);
  std::vector<Eigen::Vector4d> planes;
  if (!FitPlanes(model, parameters, measurements, plane_labels, &planes,
                 error)) {
    return false;
  }
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    if (m.type == MeasurementType::kPoint) {
      (*norms)[i] = (MeasuredPoint(model, parameters, m.joints, m.marker) -
                     centre_of(m.point))
                        .norm();
      continue;
    }
    if (m.type == MeasurementType::kPointDistance) {
      (*norms)[i] = std::abs((centre_of(m.point) - centre_of(m.point2)).norm() -
                             m.distance);
      continue;
    }
    if (m.type == MeasurementType::kPlane) {
      const Eigen::Vector4d& pl =
          planes[std::find(plane_labels.begin(), plane_labels.end(), m.plane) -
                 plane_labels.begin()];
      (*norms)[i] = std::abs(PlaneResidual(
          pl, MeasuredPoint(model, parameters, m.joints, m.marker),
          m.probe_radius_m));
      continue;
    }
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
