// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/residuals/joint_error_jacobian.h"

#include <Eigen/QR>
#include <cmath>
#include <memory>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "activecal/residuals/joint_error_residual.h"

namespace activecal {

std::vector<Eigen::VectorXd> MeasurementTermFeatures(
    const RobotModel& model, const Eigen::VectorXd& parameters,
    const JointErrorModel& errors,
    const std::vector<Measurement>& measurements) {
  std::vector<Eigen::VectorXd> features;
  features.reserve(measurements.size());
  for (const Measurement& m : measurements) {
    features.push_back(JointTermFeatures(model, parameters, errors, m.joints));
  }
  return features;
}

bool CheckJointErrorInputs(const RobotModel& model,
                           const JointErrorModel& errors,
                           const std::vector<Measurement>& measurements,
                           std::string* error) {
  if (!errors.Validate(model, error)) return false;
  if (errors.empty()) return true;
  for (size_t i = 0; i < measurements.size(); ++i) {
    if (!JointErrorResidualSupports(measurements[i])) {
      if (error) {
        *error = "measurement " + std::to_string(i) +
                 ": a distance between two poses cannot be used with joint "
                 "error terms (compliance, harmonics); use position or pose "
                 "measurements";
      }
      return false;
    }
  }
  return true;
}

namespace {

bool Evaluate(const RobotModel& model, const Eigen::VectorXd& parameters,
              const JointErrorModel& errors,
              const std::vector<Measurement>& measurements,
              const std::vector<Eigen::VectorXd>& features, double rw,
              Eigen::MatrixXd* jacobian, Eigen::VectorXd* residuals,
              Eigen::VectorXd* norms, std::string* error) {
  if (!CheckJointErrorInputs(model, errors, measurements, error)) return false;
  if (!model.CheckParameters(parameters, error)) return false;
  auto shared_model = std::make_shared<const RobotModel>(model);
  auto shared_errors = std::make_shared<const JointErrorModel>(errors);
  std::vector<const double*> blocks = BlockPointers(model, parameters.data());
  if (!errors.empty()) blocks.push_back(errors.values.data());
  std::vector<std::pair<int, int>> columns;  // (block, index)
  for (int b = 0; b < model.num_blocks(); ++b) {
    for (int j = 0; j < model.block_size(b); ++j) {
      if (model.IsFree(model.block_offset(b) + j)) columns.push_back({b, j});
    }
  }
  for (int t = 0; t < errors.size(); ++t) {
    columns.push_back({model.num_blocks(), t});
  }
  int rows = 0;
  for (const Measurement& m : measurements) rows += m.dimension();
  const int p = static_cast<int>(columns.size());
  if (jacobian) jacobian->setZero(rows, p);
  if (residuals) residuals->setZero(rows);
  if (norms) norms->setZero(static_cast<int>(measurements.size()));
  std::vector<std::vector<double>> block_jacobians(blocks.size());
  std::vector<double*> pointers(blocks.size(), nullptr);
  int row = 0;
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    const int d = m.dimension();
    std::unique_ptr<ceres::CostFunction> cost(
        errors.empty() ? static_cast<ceres::CostFunction*>(
                             MeasurementResidual::Create(shared_model, m, rw))
                       : JointErrorResidual::Create(
                             shared_model, m, rw, shared_errors, features[i]));
    if (jacobian) {
      for (const auto& [b, j] : columns) {
        const int size =
            b < model.num_blocks() ? model.block_size(b) : errors.size();
        block_jacobians[b].resize(d * size);
        pointers[b] = block_jacobians[b].data();
      }
    }
    double r[6];
    if (!cost->Evaluate(blocks.data(), r,
                        jacobian ? pointers.data() : nullptr)) {
      if (error) {
        *error = "measurement " + std::to_string(i) +
                 ": the residual could not be evaluated";
      }
      return false;
    }
    Eigen::Map<const Eigen::VectorXd> rv(r, d);
    if (residuals) residuals->segment(row, d) = rv;
    if (norms) (*norms)[static_cast<int>(i)] = rv.norm();
    if (jacobian) {
      for (int c = 0; c < p; ++c) {
        const auto [b, j] = columns[c];
        const int size =
            b < model.num_blocks() ? model.block_size(b) : errors.size();
        for (int k = 0; k < d; ++k) {
          (*jacobian)(row + k, c) = block_jacobians[b][k * size + j];
        }
      }
    }
    row += d;
  }
  return true;
}

}  // namespace

bool JointErrorJacobian(const RobotModel& model,
                        const Eigen::VectorXd& parameters,
                        const JointErrorModel& errors,
                        const std::vector<Measurement>& measurements,
                        const std::vector<Eigen::VectorXd>& features,
                        double rotation_weight_m_per_rad,
                        Eigen::MatrixXd* jacobian, Eigen::VectorXd* residuals,
                        std::string* error) {
  return Evaluate(model, parameters, errors, measurements, features,
                  rotation_weight_m_per_rad, jacobian, residuals, nullptr,
                  error);
}

bool JointErrorResidualNorms(const RobotModel& model,
                             const Eigen::VectorXd& parameters,
                             const JointErrorModel& errors,
                             const std::vector<Measurement>& measurements,
                             const std::vector<Eigen::VectorXd>& features,
                             double rotation_weight_m_per_rad,
                             Eigen::VectorXd* norms, std::string* error) {
  return Evaluate(model, parameters, errors, measurements, features,
                  rotation_weight_m_per_rad, nullptr, nullptr, norms, error);
}

std::vector<int> IdentifiableTerms(const RobotModel& model,
                                   const JointErrorModel& errors,
                                   const Eigen::MatrixXd& jacobian,
                                   double rank_tolerance,
                                   std::vector<std::string>* dropped) {
  const int g = static_cast<int>(jacobian.cols()) - errors.size();
  // Unit-norm columns; the accepted ones (geometry, then kept terms).
  Eigen::MatrixXd basis(jacobian.rows(), 0);
  auto unit = [&jacobian](int c) {
    const double n = jacobian.col(c).norm();
    return n > 0 ? Eigen::VectorXd(jacobian.col(c) / n)
                 : Eigen::VectorXd(Eigen::VectorXd::Zero(jacobian.rows()));
  };
  for (int c = 0; c < g; ++c) {
    basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
    basis.col(basis.cols() - 1) = unit(c);
  }
  const double threshold = std::sqrt(rank_tolerance);
  std::vector<int> keep;
  for (int t = 0; t < errors.size(); ++t) {
    const int c = g + t;
    const double norm = jacobian.col(c).norm();
    std::ostringstream why;
    why << errors.Name(model, t) << ": ";
    bool ok = norm > 0;
    if (!ok) {
      why << "has no effect on these measurements";
    } else {
      Eigen::VectorXd u = unit(c);
      double rel = 1.0;
      if (basis.cols() > 0) {
        const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(basis);
        const Eigen::VectorXd coef = qr.solve(u);
        rel = (u - basis * coef).norm();
      }
      ok = rel > threshold;
      if (!ok) {
        why << "a combination of the geometric parameters and earlier terms "
               "(residual "
            << rel << ")";
      }
    }
    if (ok) {
      keep.push_back(t);
      basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
      basis.col(basis.cols() - 1) = unit(c);
    } else if (dropped) {
      dropped->push_back(why.str());
    }
  }
  return keep;
}

}  // namespace activecal
