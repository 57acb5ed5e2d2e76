// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/identification.h"

#include <ceres/ceres.h>
#include <ceres/covariance.h>
#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/sphere_manifold.h>
#include <glog/logging.h>

#include <Eigen/SVD>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/plane_constraints.h"
#include "activecal/core/point_constraints.h"
#include "activecal/core/validation.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/residuals/joint_error_jacobian.h"
#include "activecal/residuals/joint_error_residual.h"
#include "activecal/residuals/measurement_residual.h"

namespace activecal {
namespace {
// Columns shorter than this times the longest are taken as zero
// (residuals/jacobians.h).
constexpr double kNoEffectTolerance = kNoEffectRelativeNorm;
// Each tail of the chi-square interval of IdentificationSummary (99.9 %).
constexpr double kChiSquareTail = 0.0005;
}  // namespace

constexpr const char* kRobustLossNames[] = {"none", "huber", "cauchy"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(RobustLoss, kRobustLossNames)

bool IdentificationOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (robust_loss != RobustLoss::kNone &&
      !(robust_scale_m > 0 && std::isfinite(robust_scale_m))) {
    msg << "robust loss '" << RobustLossToString(robust_loss)
        << "' needs robust_scale_m > 0 (m), got " << robust_scale_m;
  } else if (!(outlier_probability > 0 && outlier_probability < 1)) {
    msg << "outlier_probability must be in (0, 1), got " << outlier_probability;
  } else if (!(outlier_min_sigma_m >= 0 &&
               std::isfinite(outlier_min_sigma_m))) {
    msg << "outlier_min_sigma_m must be finite and >= 0, got "
        << outlier_min_sigma_m;
  } else if (!(rotation_weight_m_per_rad > 0 &&
               std::isfinite(rotation_weight_m_per_rad))) {
    msg << "rotation_weight_m_per_rad must be finite and > 0, got "
        << rotation_weight_m_per_rad;
  } else if (max_num_iterations <= 0) {
    msg << "max_num_iterations must be > 0, got " << max_num_iterations;
  } else if (!(function_tolerance >= 0 && gradient_tolerance >= 0 &&
               parameter_tolerance >= 0)) {
    msg << "tolerances must be >= 0";
  } else if (!(default_sigma_m >= 0 && std::isfinite(default_sigma_m) &&
               default_sigma_rad >= 0 && std::isfinite(default_sigma_rad))) {
    msg << "default_sigma_m and default_sigma_rad must be finite and >= 0, "
           "got "
        << default_sigma_m << ", " << default_sigma_rad;
  } else if (!(prior_std_m >= 0 && std::isfinite(prior_std_m) &&
               prior_std_rad >= 0 && std::isfinite(prior_std_rad) &&
               prior_reference_sigma_m >= 0 &&
               std::isfinite(prior_reference_sigma_m))) {
    msg << "prior_std_m, prior_std_rad and prior_reference_sigma_m must be "
           "finite and >= 0";
  } else if (!(rank_tolerance > 0 && rank_tolerance < 1)) {
    msg << "rank_tolerance must be in (0, 1), got " << rank_tolerance;
  }
  return FinishValidation(msg, error);
}

std::string IdentifiabilityReport::Message() const {
  std::ostringstream msg;
  if (num_equations < num_free) {
    msg << "too few equations: " << num_equations << " measurement rows for "
        << num_free << " free parameters";
    return msg.str();
  }
  if (rank == num_free) {
    msg << "all " << num_free << " free parameters are identifiable";
    return msg.str();
  }
  msg << "the Jacobian has rank " << rank << " < " << num_free
      << " free parameters; not identifiable from these measurements:";
  for (const std::string& u : unidentifiable) msg << " [" << u << "]";
  return msg.str();
}

IdentifiabilityReport AnalyzeIdentifiability(const RobotModel& model,
                                             const Eigen::MatrixXd& jacobian,
                                             double rank_tolerance) {
  IdentifiabilityReport report;
  report.num_equations = static_cast<int>(jacobian.rows());
  report.num_free = static_cast<int>(jacobian.cols());
  const std::vector<std::string> names = model.FreeParameterNames();
  // Column scaling makes the test independent of units (m against rad).
  Eigen::VectorXd norms = jacobian.colwise().norm();
  // A column that is zero up to rounding has no effect; normalising it
  // would blow its rounding noise up into a direction of its own.
  const double no_effect = kNoEffectTolerance * norms.maxCoeff();
  for (int c = 0; c < norms.size(); ++c) {
    if (norms[c] <= no_effect) norms[c] = 0.0;
  }
  Eigen::MatrixXd scaled = jacobian;
  for (int c = 0; c < scaled.cols(); ++c) {
    if (norms[c] > 0) {
      scaled.col(c) /= norms[c];
    } else {
      report.unidentifiable.push_back(names[c] + " has no effect");
    }
  }
  if (report.num_equations < report.num_free) {
    report.rank = std::min(report.num_equations, report.num_free);
    return report;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeFullV);
  report.singular_values = svd.singularValues();
  const double smax =
      report.singular_values.size() ? report.singular_values[0] : 0.0;
  report.rank = 0;
  for (int i = 0; i < report.singular_values.size(); ++i) {
    if (report.singular_values[i] > rank_tolerance * smax) ++report.rank;
  }
  const Eigen::MatrixXd& V = svd.matrixV();
  for (int k = report.rank; k < report.num_free; ++k) {
    const Eigen::VectorXd v = V.col(k);
    // Skip directions already explained by a column with no effect.
    int top;
    v.cwiseAbs().maxCoeff(&top);
    if (norms[top] == 0) continue;
    std::ostringstream combo;
    bool first = true;
    for (int c = 0; c < v.size(); ++c) {
      if (std::abs(v[c]) < 0.05) continue;
      combo << (first ? (v[c] < 0 ? "-" : "") : (v[c] < 0 ? " - " : " + "));
      combo.precision(2);
      combo << std::fixed << std::abs(v[c]) << " * " << names[c];
      first = false;
    }
    report.unidentifiable.push_back(combo.str());
  }
  return report;
}

std::vector<int> SuggestParametersToFix(const Eigen::MatrixXd& jacobian,
                                        double rank_tolerance) {
  const int p = static_cast<int>(jacobian.cols());
  Eigen::MatrixXd scaled = jacobian;
  std::vector<int> to_fix;
  std::vector<int> live;
  const double no_effect =
      p ? kNoEffectTolerance * jacobian.colwise().norm().maxCoeff() : 0.0;
  for (int c = 0; c < p; ++c) {
    const double norm = scaled.col(c).norm();
    if (norm > no_effect) {
      scaled.col(c) /= norm;
      live.push_back(c);
    } else {
      to_fix.push_back(c);
    }
  }
  Eigen::MatrixXd kept(scaled.rows(), live.size());
  for (size_t k = 0; k < live.size(); ++k) kept.col(k) = scaled.col(live[k]);
  if (!live.empty()) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(kept);
    const Eigen::VectorXd sv = svd.singularValues();
    int rank = 0;
    for (int i = 0; i < sv.size(); ++i) {
      if (sv[i] > rank_tolerance * sv[0]) ++rank;
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(kept);
    const auto& perm = qr.colsPermutation().indices();
    for (int k = rank; k < static_cast<int>(live.size()); ++k) {
      to_fix.push_back(live[perm[k]]);
    }
  }
  std::sort(to_fix.begin(), to_fix.end());
  return to_fix;
}

bool FixUnidentifiableParameters(const RobotModel& model,
                                 const Eigen::MatrixXd& jacobian,
                                 double rank_tolerance,
                                 IdentifiabilityReport* report, FreeSet* free,
                                 std::vector<HeldParameter>* held,
                                 std::vector<int>* fixed_columns) {
  CHECK(report != nullptr);
  CHECK(free != nullptr);
  CHECK(held != nullptr);
  CHECK_EQ(jacobian.cols(), model.num_free());
  *free = FreeSet(model);
  held->clear();
  if (fixed_columns) fixed_columns->clear();
  *report = AnalyzeIdentifiability(model, jacobian, rank_tolerance);
  if (report->identifiable()) return true;
  if (report->num_equations < report->num_free) return false;
  const std::vector<int> columns =
      SuggestParametersToFix(jacobian, rank_tolerance);
  const std::vector<std::string> names = model.FreeParameterNames();
  const std::vector<int> indices = model.FreeParameterIndices();
  for (int c : columns) {
    free->Set(indices[c], false);
    held->push_back({names[c],
                     "not identifiable from these measurements (a "
                     "combination of the kept parameters, or no effect)",
                     HoldStage::kAutoFix});
  }
  if (fixed_columns) *fixed_columns = columns;
  return true;
}

namespace {

double Rms(const Eigen::VectorXd& norms) {
  return norms.size() ? std::sqrt(norms.squaredNorm() / norms.size()) : 0.0;
}

// Norm of each measurement's rows of the stacked residual vector.
Eigen::VectorXd BlockNorms(const std::vector<Measurement>& measurements,
                           const Eigen::VectorXd& residuals) {
  Eigen::VectorXd norms(measurements.size());
  int row = 0;
  for (size_t i = 0; i < measurements.size(); ++i) {
    const int t = measurements[i].dimension();
    norms[i] = residuals.segment(row, t).norm();
    row += t;
  }
  return norms;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) {
    m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + mid));
  }
  return m;
}

// The raw residuals (no loss function applied) of every cost function at
// the current parameter values.
Eigen::VectorXd RawResiduals(const std::vector<ceres::CostFunction*>& costs,
                             const std::vector<std::vector<double*>>& blocks) {
  int rows = 0;
  for (const ceres::CostFunction* c : costs) rows += c->num_residuals();
  Eigen::VectorXd r(rows);
  int row = 0;
  for (size_t i = 0; i < costs.size(); ++i) {
    const ceres::CostFunction* c = costs[i];
    if (!c->Evaluate(blocks[i].data(), r.data() + row, nullptr)) {
      r.segment(row, c->num_residuals())
          .setConstant(std::numeric_limits<double>::quiet_NaN());
    }
    row += c->num_residuals();
  }
  return r;
}

// A cost function whose rows are those of `inner` times fixed weights (1 /
// the row's standard deviation). Owns `inner`.
class WeightedCost : public ceres::CostFunction {
 public:
  WeightedCost(ceres::CostFunction* inner, Eigen::VectorXd weights)
      : inner_(inner), weights_(std::move(weights)) {
    set_num_residuals(inner->num_residuals());
    *mutable_parameter_block_sizes() = inner->parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (!inner_->Evaluate(parameters, residuals, jacobians)) return false;
    const int rows = num_residuals();
    for (int r = 0; r < rows; ++r) residuals[r] *= weights_[r];
    if (jacobians != nullptr) {
      const std::vector<int32_t>& sizes = parameter_block_sizes();
      for (size_t b = 0; b < sizes.size(); ++b) {
        if (jacobians[b] == nullptr) continue;
        for (int r = 0; r < rows; ++r) {
          for (int c = 0; c < sizes[b]; ++c) {
            jacobians[b][r * sizes[b] + c] *= weights_[r];
          }
        }
      }
    }
    return true;
  }
  const ceres::CostFunction* inner() const { return inner_.get(); }

 private:
  std::unique_ptr<ceres::CostFunction> inner_;
  Eigen::VectorXd weights_;
};

// The prior rows of one parameter block: w_j (x_j - x0_j), w_j = 0 for the
// entries without a prior.
class PriorCost : public ceres::CostFunction {
 public:
  PriorCost(Eigen::VectorXd center, Eigen::VectorXd weights)
      : center_(std::move(center)), weights_(std::move(weights)) {
    set_num_residuals(static_cast<int>(center_.size()));
    mutable_parameter_block_sizes()->assign(1,
                                            static_cast<int>(center_.size()));
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int n = static_cast<int>(center_.size());
    for (int j = 0; j < n; ++j) {
      residuals[j] = weights_[j] * (parameters[0][j] - center_[j]);
    }
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<RowMatrixXd>(jacobians[0], n, n) = weights_.asDiagonal();
    }
    return true;
  }

 private:
  Eigen::VectorXd center_;
  Eigen::VectorXd weights_;
};

// Row weights 1 / sigma of every measurement (stated, or the defaults).
// *weighted: every row has a sigma; false with all weights 1 when no row
// has one. False with *error when some rows have one and others none.
bool RowWeights(const std::vector<Measurement>& measurements,
                const IdentificationOptions& options,
                std::vector<Eigen::VectorXd>* weights, bool* weighted,
                double* rms_sigma_m, std::string* error) {
  weights->clear();
  int with = 0, without = 0, first_without = -1;
  bool first_without_states_some = false;
  double sum_sigma2 = 0.0;
  int num_metric = 0;
  std::vector<Eigen::VectorXd> sigmas;
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    Eigen::VectorXd s(m.dimension());
    if (m.dimension() == 1) {  // a distance or a known point distance
      s[0] = m.sigma_m[0] > 0 ? m.sigma_m[0] : options.default_sigma_m;
    } else {
      for (int k = 0; k < 3; ++k) {
        s[k] = m.sigma_m[k] > 0 ? m.sigma_m[k] : options.default_sigma_m;
      }
      if (m.type == MeasurementType::kPose) {
        // The rotation rows are w * log(R): their sigma is w * sigma_rad.
        const double r =
            m.sigma_rad > 0 ? m.sigma_rad : options.default_sigma_rad;
        s.tail<3>().setConstant(options.rotation_weight_m_per_rad * r);
      }
    }
    const bool stated = m.sigma_m.maxCoeff() > 0 || m.sigma_rad > 0;
    if (stated) ++with;
    if ((s.array() > 0).all()) {
      for (int k = 0; k < std::min(3, static_cast<int>(s.size())); ++k) {
        sum_sigma2 += s[k] * s[k];
        ++num_metric;
      }
    } else {
      ++without;
      if (first_without < 0) {
        first_without = static_cast<int>(i);
        first_without_states_some = stated;
      }
    }
    sigmas.push_back(s);
  }
  const bool defaults =
      options.default_sigma_m > 0 || options.default_sigma_rad > 0;
  *weighted = without == 0 && !measurements.empty();
  if (!*weighted && (with > 0 || defaults)) {
    std::ostringstream msg;
    const Measurement& m = measurements[first_without];
    if (first_without_states_some && m.type == MeasurementType::kPose) {
      // A pose row with a sigma for one half only: say which half.
      msg << "measurement " << first_without << " (a pose) states the "
          << (m.sigma_rad > 0 ? "rotation's standard deviation but not the "
                                "position's"
                              : "position's standard deviation but not the "
                                "rotation's (sigma_rad)")
          << ": give both, or a default sigma (m for points and distances, "
             "rad for pose rotations) for the rows without";
      if (error) *error = msg.str();
      return false;
    }
    msg << "measurement " << first_without
        << " has no standard deviation for some of its rows while "
        << (with > 0 ? "other measurements state one"
                     : "a default sigma is given for others")
        << ": give every measurement sigma columns, or a default sigma "
           "(m for points and distances, rad for pose rotations) for the "
           "rows without";
    if (error) *error = msg.str();
    return false;
  }
  *rms_sigma_m = num_metric ? std::sqrt(sum_sigma2 / num_metric) : 0.0;
  for (const Eigen::VectorXd& s : sigmas) {
    weights->push_back(*weighted ? Eigen::VectorXd(s.cwiseInverse())
                                 : Eigen::VectorXd::Ones(s.size()));
  }
  return true;
}

}  // namespace

void Identify(const RobotModel& model,
              const std::vector<Measurement>& measurements,
              const Eigen::VectorXd& initial,
              const IdentificationOptions& options,
              IdentificationSummary* summary) {
  CHECK(summary != nullptr);
  *summary = IdentificationSummary();
  summary->initial = initial;
  summary->names = model.FreeParameterNames();
  summary->num_free = model.num_free();
  summary->num_measurements = static_cast<int>(measurements.size());
  summary->num_residuals = 0;
  for (const Measurement& m : measurements) {
    summary->num_residuals += m.dimension();
  }
  std::string error;
  auto end = [summary](TerminationType type, const std::string& why) {
    summary->termination_type = type;
    summary->message = why;
  };
  auto fail = [&end](const std::string& why) {
    end(TerminationType::kFailure, why);
  };
  auto user_failure = [&end](const std::string& why) {
    end(TerminationType::kUserFailure, why);
  };
  if (!options.IsValid(&error))
    return user_failure("invalid options: " + error);
  if (!model.Validate(&error)) return user_failure(error);
  if (!model.CheckParameters(initial, &error)) {
    return user_failure("initial values: " + error);
  }
  if (summary->num_free == 0) {
    return user_failure("no free parameters to identify");
  }
  const JointErrorModel& terms = options.joint_errors;
  const int num_terms = terms.size();
  if (!CheckJointErrorInputs(model, terms, measurements, &error)) {
    return user_failure(error);
  }
  summary->joint_errors = terms;
  summary->term_names = terms.Names(model);
  std::vector<Eigen::VectorXd> features;
  if (num_terms > 0) {
    features = MeasurementTermFeatures(model, initial, terms, measurements);
  }
  // Fixed points: 3 unknown coordinates per label, after the terms.
  const bool with_points = HasPointRows(measurements);
  if (with_points) {
    if (num_terms > 0) {
      return user_failure(
          "joint error terms with fixed-point rows are not supported");
    }
    if (!CheckPointLabels(measurements, &error)) return user_failure(error);
    if (!CheckPlaneLabels(measurements, &error)) return user_failure(error);
    summary->point_labels = PointLabels(measurements);
    summary->plane_labels = PlaneLabels(measurements);
  }
  const int num_point_values =
      3 * static_cast<int>(summary->point_labels.size());
  const int num_planes = static_cast<int>(summary->plane_labels.size());
  const int p =
      summary->num_free + num_terms + num_point_values + 3 * num_planes;
  // Identifiability at the starting point, before any solving (this also
  // checks every measurement).
  Eigen::MatrixXd stacked;
  if (!StackedJacobian(model, initial, measurements,
                       options.rotation_weight_m_per_rad, &stacked, &error)) {
    return user_failure(error);
  }
  summary->identifiability =
      AnalyzeIdentifiability(model, stacked, options.rank_tolerance);
  if (!summary->identifiability.identifiable()) {
    return fail(summary->identifiability.Message());
  }
  if (num_terms > 0) {
    Eigen::MatrixXd with_terms;
    if (!JointErrorJacobian(model, initial, terms, measurements, features,
                            options.rotation_weight_m_per_rad, &with_terms,
                            nullptr, &error)) {
      return user_failure(error);
    }
    std::vector<std::string> dropped;
    IdentifiableTerms(model, terms, with_terms, options.rank_tolerance,
                      &dropped);
    if (!dropped.empty()) {
      return fail("joint error term not identifiable from these poses: " +
                  dropped.front());
    }
  }
  if (summary->num_residuals <= p) {
    std::ostringstream msg;
    msg << summary->num_residuals << " measurement rows for " << p
        << " free parameters leave 0 degrees of freedom: the estimates would "
           "fit the data exactly and their standard deviations cannot be "
           "estimated; measure more poses";
    return fail(msg.str());
  }

  std::vector<Eigen::VectorXd> row_weights;
  double rms_sigma_m = 0.0;
  if (!RowWeights(measurements, options, &row_weights, &summary->weighted,
                  &rms_sigma_m, &error)) {
    return user_failure(error);
  }
  if (summary->weighted && options.robust_loss != RobustLoss::kNone) {
    return user_failure(
        "a robust loss together with per-measurement standard deviations is "
        "not supported: its scale would be in sigma units; use one or the "
        "other");
  }
  summary->with_prior = options.prior_std_m > 0 || options.prior_std_rad > 0;
  const double prior_reference =
      summary->weighted ? 1.0 : options.prior_reference_sigma_m;
  if (summary->with_prior && !(prior_reference > 0)) {
    return user_failure(
        "a prior (prior_std_m, prior_std_rad) on unweighted measurements "
        "needs prior_reference_sigma_m > 0, the noise of one row (m)");
  }

  // One block per group; constant groups fixed, partly free groups through a
  // SubsetManifold.
  Eigen::VectorXd x = initial;
  std::vector<double*> blocks(model.num_blocks());
  for (int b = 0; b < model.num_blocks(); ++b) {
    blocks[b] = x.data() + model.block_offset(b);
  }
  ceres::Problem problem;
  auto shared = std::make_shared<const RobotModel>(model);
  auto shared_terms = std::make_shared<const JointErrorModel>(terms);
  Eigen::VectorXd theta = terms.values;
  if (num_terms > 0) blocks.push_back(theta.data());
  // The points' coordinates start at the mean predicted point of each.
  Eigen::VectorXd points(num_point_values);
  {
    const std::vector<Eigen::Vector3d> mean =
        MeanPointPositions(model, initial, measurements, summary->point_labels);
    for (size_t k = 0; k < mean.size(); ++k) points.segment<3>(3 * k) = mean[k];
  }
  // The planes start at the planes fitted to the predicted touches
  // (plane_constraints.h: the normal's sign is kept from there).
  Eigen::VectorXd planes(4 * num_planes);
  if (num_planes > 0) {
    std::vector<Eigen::Vector4d> fitted;
    if (!FitPlanes(model, initial, measurements, summary->plane_labels, &fitted,
                   &error)) {
      return user_failure(error);
    }
    for (int k = 0; k < num_planes; ++k) planes.segment<4>(4 * k) = fitted[k];
  }
  const Eigen::VectorXd start_planes = planes;
  auto plane_block = [&](const std::string& label) {
    return planes.data() + 4 * LabelIndex(summary->plane_labels, label);
  };
  auto point_block = [&](const std::string& label) {
    return points.data() + 3 * LabelIndex(summary->point_labels, label);
  };
  std::vector<ceres::CostFunction*> costs;  // unweighted; owned by problem
  std::vector<std::vector<double*>> cost_blocks;
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    cost_blocks.push_back(blocks);
    if (m.type == MeasurementType::kPlane) {
      cost_blocks.back().push_back(plane_block(m.plane));
    } else if (m.type == MeasurementType::kPoint) {
      cost_blocks.back().push_back(point_block(m.point));
    } else if (m.type == MeasurementType::kPointDistance) {
      cost_blocks.back().push_back(point_block(m.point));
      cost_blocks.back().push_back(point_block(m.point2));
    }
    ceres::LossFunction* loss = nullptr;
    if (options.robust_loss == RobustLoss::kHuber) {
      loss = new ceres::HuberLoss(options.robust_scale_m);
    } else if (options.robust_loss == RobustLoss::kCauchy) {
      loss = new ceres::CauchyLoss(options.robust_scale_m);
    }
    if (num_terms > 0) {
      costs.push_back(JointErrorResidual::Create(
          shared, m, options.rotation_weight_m_per_rad, shared_terms,
          features[i]));
    } else {
      costs.push_back(MeasurementResidual::Create(
          shared, m, options.rotation_weight_m_per_rad));
    }
    ceres::CostFunction* cost = costs.back();
    if (summary->weighted) cost = new WeightedCost(cost, row_weights[i]);
    problem.AddResidualBlock(cost, loss, cost_blocks.back());
  }
  if (summary->with_prior) {
    for (int b = 1; b <= model.num_joints(); ++b) {
      const int n = model.block_size(b);
      Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
      for (int j = 0; j < n; ++j) {
        const int i = model.block_offset(b) + j;
        if (!model.IsFree(i)) continue;
        const double prior = std::string(model.ParameterUnit(i)) == "m"
                                 ? options.prior_std_m
                                 : options.prior_std_rad;
        if (prior > 0) w[j] = prior_reference / prior;
      }
      if (w.isZero(0)) continue;
      problem.AddResidualBlock(
          new PriorCost(initial.segment(model.block_offset(b), n), w), nullptr,
          blocks[b]);
    }
  }
  std::vector<const double*> free_blocks;
  for (int b = 0; b < model.num_blocks(); ++b) {
    // The geometric blocks (the terms' block, last, is wholly free).
    std::vector<int> constant;
    for (int j = 0; j < model.block_size(b); ++j) {
      if (!model.IsFree(model.block_offset(b) + j)) constant.push_back(j);
    }
    if (static_cast<int>(constant.size()) == model.block_size(b)) {
      problem.SetParameterBlockConstant(blocks[b]);
    } else {
      if (!constant.empty()) {
        problem.SetManifold(blocks[b], new ceres::SubsetManifold(
                                           model.block_size(b), constant));
      }
      free_blocks.push_back(blocks[b]);
    }
  }
  if (num_terms > 0) free_blocks.push_back(blocks.back());
  for (int k = 0; k < num_point_values; k += 3) {
    free_blocks.push_back(points.data() + k);
  }
  for (int k = 0; k < num_planes; ++k) {
    // The unit normal on the sphere, the offset free (plane_constraints.h).
    problem.SetManifold(
        planes.data() + 4 * k,
        new ceres::ProductManifold<ceres::SphereManifold<3>,
                                   ceres::EuclideanManifold<1>>(
            ceres::SphereManifold<3>(), ceres::EuclideanManifold<1>()));
    free_blocks.push_back(planes.data() + 4 * k);
  }
  const Eigen::VectorXd r0 = RawResiduals(costs, cost_blocks);
  summary->initial_residual_norms = BlockNorms(measurements, r0);
  summary->initial_rms_m = Rms(summary->initial_residual_norms);

  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_num_iterations;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solve(solver_options, &problem, &summary->solver_summary);
  // A plane the solver turned over: back to the start's side.
  OrientPlanesLike(start_planes, measurements, summary->plane_labels, &planes);
  const ceres::Solver::Summary& ss = summary->solver_summary;
  // Not iterations.size() - 1, which is -1 when Ceres stops before its
  // first iteration.
  summary->iterations = ss.num_successful_steps + ss.num_unsuccessful_steps;
  summary->parameters = x;
  summary->estimates = ExtractFree(model, x);
  summary->joint_errors.values = theta;
  summary->residuals = RawResiduals(costs, cost_blocks);
  summary->point_coordinates = points;
  summary->plane_parameters = planes;
  summary->residual_norms = BlockNorms(measurements, summary->residuals);
  summary->rms_m = Rms(summary->residual_norms);
  OutlierStatistics(measurements, summary->residuals,
                    options.outlier_probability, options.outlier_min_sigma_m,
                    &summary->outlier_d2, &summary->outlier_threshold);
  for (int i = 0; i < summary->outlier_d2.size(); ++i) {
    if (summary->outlier_d2[i] > summary->outlier_threshold[i]) {
      summary->outliers.push_back(i);
    }
  }
  // s^2 over all rows; with a robust loss over the rows of the inliers.
  double ssr = summary->residuals.squaredNorm();
  int rows_used = summary->num_residuals;
  if (options.robust_loss != RobustLoss::kNone) {
    for (int i : summary->outliers) {
      ssr -= summary->residual_norms[i] * summary->residual_norms[i];
      rows_used -= measurements[i].dimension();
    }
  }
  const int dof = rows_used - p;
  summary->sigma_m = dof > 0 ? std::sqrt(std::max(0.0, ssr) / dof) : 0.0;
  summary->degrees_of_freedom = std::max(0, dof);
  summary->implied_sigma_m = summary->sigma_m;
  if (summary->weighted && dof > 0) {
    int row = 0;
    for (size_t i = 0; i < measurements.size(); ++i) {
      const int t = measurements[i].dimension();
      summary->chi_square += summary->residuals.segment(row, t)
                                 .cwiseProduct(row_weights[i])
                                 .squaredNorm();
      row += t;
    }
    summary->chi_square_per_dof = summary->chi_square / dof;
    summary->implied_sigma_m =
        std::sqrt(summary->chi_square_per_dof) * rms_sigma_m;
    const boost::math::chi_squared_distribution<double> chi2(dof);
    summary->chi_square_per_dof_low =
        boost::math::quantile(chi2, kChiSquareTail) / dof;
    summary->chi_square_per_dof_high =
        boost::math::quantile(boost::math::complement(chi2, kChiSquareTail)) /
        dof;
    summary->chi_square_plausible =
        summary->chi_square_per_dof >= summary->chi_square_per_dof_low &&
        summary->chi_square_per_dof <= summary->chi_square_per_dof_high;
  }
  if (dof <= 0) {
    std::ostringstream msg;
    msg << "after leaving out the " << summary->outliers.size()
        << " outlier(s), " << rows_used << " measurement rows for " << p
        << " free parameters leave " << std::max(0, dof)
        << " degrees of freedom: the standard deviations cannot be estimated";
    return fail(msg.str());
  }
  if (ss.termination_type == ceres::NO_CONVERGENCE) {
    return end(TerminationType::kNoConvergence,
               "the solver did not converge: " + ss.message);
  }
  if (ss.termination_type != ceres::CONVERGENCE) {
    return fail("the solver failed: " + ss.message);
  }
  if (!summary->parameters.allFinite() || !theta.allFinite() ||
      !points.allFinite() || !planes.allFinite()) {
    return fail("the solver produced non-finite estimates");
  }

  if (!options.compute_covariance) {
    summary->termination_type = TerminationType::kConvergence;
    summary->message = "identified " + std::to_string(p) +
                       " parameters (no covariance asked for)";
    return;
  }
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  cov_options.null_space_rank = 0;
  // One thread: the threaded dense SVD sums in a different order, and the
  // result must not depend on the thread count.
  cov_options.num_threads = 1;
  ceres::Covariance covariance(cov_options);
  std::vector<std::pair<const double*, const double*>> pairs;
  for (size_t i = 0; i < free_blocks.size(); ++i) {
    for (size_t j = i; j < free_blocks.size(); ++j) {
      pairs.emplace_back(free_blocks[i], free_blocks[j]);
    }
  }
  RowMatrixXd cov(p, p);
  if (!covariance.Compute(pairs, &problem) ||
      !covariance.GetCovarianceMatrixInTangentSpace(free_blocks, cov.data())) {
    return fail(
        "the covariance could not be computed: the Jacobian at the solution "
        "is rank deficient (parameters not identifiable from these poses)");
  }
  // Weighted rows have unit variance by statement: (J^T W J)^-1 as is.
  const Eigen::MatrixXd full_covariance =
      summary->weighted
          ? Eigen::MatrixXd(cov)
          : Eigen::MatrixXd(cov * (summary->sigma_m * summary->sigma_m));
  const int g = summary->num_free;
  summary->covariance = full_covariance.topLeftCorner(g, g);
  if (num_point_values > 0) {
    summary->point_covariance = full_covariance.block(
        g + num_terms, g + num_terms, num_point_values, num_point_values);
    summary->point_standard_deviations =
        summary->point_covariance.diagonal().cwiseSqrt();
  }
  if (num_planes > 0) {
    summary->plane_covariance =
        full_covariance.bottomRightCorner(3 * num_planes, 3 * num_planes);
    summary->plane_standard_deviations =
        summary->plane_covariance.diagonal().cwiseSqrt();
  }
  if (num_terms > 0) {
    summary->term_covariance = full_covariance;
    summary->term_standard_deviations =
        full_covariance.diagonal().tail(num_terms).cwiseSqrt();
  }
  summary->standard_deviations = summary->covariance.diagonal().cwiseSqrt();
  if (summary->weighted) {
    summary->scaled_standard_deviations =
        summary->standard_deviations * std::sqrt(summary->chi_square_per_dof);
  }
  summary->correlation = summary->covariance;
  for (int i = 0; i < g; ++i) {
    for (int j = 0; j < g; ++j) {
      const double denom =
          summary->standard_deviations[i] * summary->standard_deviations[j];
      summary->correlation(i, j) =
          denom > 0 ? summary->covariance(i, j) / denom : 0.0;
    }
  }
  summary->termination_type = TerminationType::kConvergence;
  std::ostringstream msg;
  msg << "identified " << p << " parameters from " << summary->num_measurements
      << " measurements in " << summary->iterations << " iterations";
  summary->message = msg.str();
}

void OutlierStatistics(const std::vector<Measurement>& measurements,
                       const Eigen::VectorXd& residuals, double probability,
                       double min_sigma_m, Eigen::VectorXd* d2,
                       Eigen::VectorXd* threshold) {
  const int n = static_cast<int>(measurements.size());
  d2->setZero(n);
  threshold->setZero(n);
  if (n == 0) return;
  // A row's class: its measurement type and its row (x, y, z of a point,
  // each weighted rotation component of a pose apart: the axes of a device
  // and of a robot's unmodelled errors differ, by 4 times on the UR10e's
  // camera data).
  auto row_class = [](const Measurement& m, int t) {
    return std::make_pair(static_cast<int>(m.type), t);
  };
  std::map<std::pair<int, int>, std::vector<double>> rows;
  int row = 0;
  for (const Measurement& m : measurements) {
    for (int t = 0; t < m.dimension(); ++t) {
      rows[row_class(m, t)].push_back(std::abs(residuals[row + t]));
    }
    row += m.dimension();
  }
  CHECK_EQ(row, residuals.size());
  std::map<std::pair<int, int>, double> scale;
  for (const auto& [key, values] : rows) {
    // 1.4826 median |r|: the standard deviation of zero-mean Gaussian rows.
    scale[key] = std::max(1.4826 * Median(values), min_sigma_m);
  }
  std::map<int, double> quantile;  // by dimension
  row = 0;
  for (int i = 0; i < n; ++i) {
    const Measurement& m = measurements[i];
    const int dim = m.dimension();
    for (int t = 0; t < dim; ++t) {
      const double z = residuals[row + t] / scale[row_class(m, t)];
      (*d2)[i] += z * z;
    }
    row += dim;
    if (!quantile.count(dim)) {
      const boost::math::chi_squared_distribution<double> chi2(dim);
      quantile[dim] =
          boost::math::quantile(boost::math::complement(chi2, probability / n));
    }
    (*threshold)[i] = quantile[dim];
  }
}

std::string IdentificationSummary::BriefReport() const {
  std::ostringstream out;
  out << "activecal identification: "
      << TerminationTypeToString(termination_type) << "\n  " << message << "\n";
  out << "  measurements: " << num_measurements << " (" << num_residuals
      << " equations), free parameters: " << num_free << "\n";
  out << "  RMS residual: " << initial_rms_m << " m at start -> " << rms_m
      << " m at the estimate; sigma per row " << sigma_m << " m\n";
  if (weighted) {
    out << "  weighted by the stated sigmas: chi^2 / dof = "
        << chi_square_per_dof << " (" << degrees_of_freedom
        << " dof); the residuals imply " << implied_sigma_m
        << " m per position row\n";
    // Implausible: said once, by the warnings (estimate_warnings.h).
  }
  if (with_prior) out << "  MAP fit: a prior on the link parameters\n";
  if (!outliers.empty()) {
    out << "  outliers flagged: " << outliers.size() << " measurement(s)\n";
  }
  out << "  solver: " << solver_summary.BriefReport() << "\n";
  return out.str();
}

}  // namespace activecal
