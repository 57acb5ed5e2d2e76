// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Identification of the free kinematic parameters from measurements of any
// kind (measurement.h: position, 6D pose, distance, fixed points, mixed;
// the coordinates of fixed points are fitted too), by nonlinear
// least squares (Ceres, Levenberg-Marquardt), optionally with a robust loss.
//
//   IdentificationOptions options;
//   IdentificationSummary summary;
//   Identify(model, measurements, model.nominal, options, &summary);
//   if (summary.termination_type != TerminationType::kConvergence) {
//     LOG(ERROR) << summary.message;  // e.g. which parameters are not
//   }                                 // identifiable from these poses
//   std::cout << summary.BriefReport();
//
// Standard deviations come from ceres::Covariance, (J^T J)^-1 at the
// solution, scaled by the residual variance s^2 = SSR / (m - p), m scalar
// residuals, p free parameters: the usual estimate when the measurement
// noise is unknown. Every residual row is assumed to carry the same noise;
// for 6D poses choose rotation_weight_m_per_rad to make it so. With a
// robust loss, Ceres' covariance uses the robustified Jacobian and s^2 is
// taken over the measurements not flagged as outliers.
//
// Per-measurement uncertainty: when measurements carry standard deviations
// (Measurement::sigma_m per axis, sigma_rad for a pose's rotation rows),
// every row is divided by its sigma (weighted least squares). Rows without
// one take default_sigma_m / default_sigma_rad; if some rows have a sigma
// and others none and no default covers them, the identification refuses
// (mixing rows in sigma units with rows in metres has no meaning). With
// every row weighted, the covariance is (J^T W J)^-1, the stated noise
// taken at its word, and the summary reports chi^2 / dof (about 1 when
// the stated sigmas fit the residuals) and the noise level the residuals
// imply. Outliers are still judged on the unweighted rows (in metres).
// Without sigmas nothing changes.
//
// chi^2 / dof far from 1: the stated sigmas do not describe the residuals
// (a tracker's datasheet sigma against a robot's unmodelled errors). The
// rule: chi^2 outside the central 99.9 % interval of the chi-square
// distribution with dof degrees of freedom (chi_square_plausible false).
// The covariance stays the one of the stated sigmas; scaled_standard_
// deviations are multiplied by sqrt(chi^2 / dof), the std the implied noise
// gives (filled whenever the rows are weighted).
//
// MAP fit: prior_std_m / prior_std_rad > 0 add a Gaussian prior centred on
// `initial` to every free link (geometric) parameter, not to the base frame
// or the markers, whose values are unknown rather than nominal. A prior row
// is sigma_ref * (x - x0) / prior_std: sigma_ref is 1 when the rows are
// weighted (dimensionless) and prior_reference_sigma_m otherwise (the
// noise of one unweighted row, m; required then).

#ifndef ACTIVECAL_ESTIMATION_IDENTIFICATION_H_
#define ACTIVECAL_ESTIMATION_IDENTIFICATION_H_

#include <ceres/solver.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/free_set.h"
#include "activecal/core/joint_errors.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/simulation.h"
#include "activecal/core/types.h"

namespace activecal {

enum class RobustLoss {
  kNone,    // plain least squares
  kHuber,   // quadratic up to the scale, linear beyond
  kCauchy,  // log(1 + (r/scale)^2): strong down-weighting of gross errors
};
// "none", "huber", "cauchy".
const char* RobustLossToString(RobustLoss loss);
bool StringToRobustLoss(const std::string& text, RobustLoss* loss);

struct IdentificationOptions {
  // A robust loss on each measurement's residual norm, with its scale (m):
  // residual norms below the scale count as in least squares.
  RobustLoss robust_loss = RobustLoss::kNone;
  double robust_scale_m = 0.0;
  // A measurement is reported as an outlier when its residual is
  // improbable under the fitted noise: d^2 = sum over its rows of
  // (r / s_class)^2 beyond the chi-square quantile of its dimension at
  // 1 - outlier_probability / N (Bonferroni over the N measurements), so
  // that clean data flag any measurement with probability about
  // outlier_probability. s_class is a robust scale, 1.4826 times the median
  // absolute row, taken apart for each row of each measurement type (x, y,
  // z of a position; of a pose's point and each of its weighted rotation
  // components; a distance): rows of different units, or of axes with
  // different noise, are never judged on one scale. In (0, 1).
  double outlier_probability = 0.01;
  // Floor of that robust standard deviation (m): with exact or nearly
  // exact data the median residual is ~0 and, without a floor, every
  // rounding-level residual would be an outlier. A micrometre is below the
  // noise of any calibration device.
  double outlier_min_sigma_m = 1e-6;
  // Scales the orientation rows of 6D pose measurements (m per rad).
  double rotation_weight_m_per_rad = 1.0;
  // Standard deviation of rows whose measurement states none (0: none).
  // Position and distance rows: default_sigma_m (m); a pose's rotation
  // rows: default_sigma_rad (rad).
  double default_sigma_m = 0.0;
  double default_sigma_rad = 0.0;
  // Prior standard deviations of the free link parameters (0: no prior);
  // see the MAP fit above. Lengths (m) and angles (rad) apart; a joint gain
  // (unitless) takes prior_std_rad.
  double prior_std_m = 0.0;
  double prior_std_rad = 0.0;
  double prior_reference_sigma_m = 0.0;

  // Joint error terms (joint_errors.h: compliance under gravity,
  // joint-periodic errors) identified with the geometry, started at
  // joint_errors.values; their features are taken at `initial` (the nominal
  // geometry). Empty: the geometric model alone. Distances between two
  // poses are refused with terms.
  JointErrorModel joint_errors;

  // False: skip the covariance (standard_deviations, covariance and
  // correlation stay empty), e.g. for the many fits of a model selection.
  bool compute_covariance = true;

  int max_num_iterations = 200;
  double function_tolerance = 1e-15;
  double gradient_tolerance = 1e-15;
  double parameter_tolerance = 1e-14;
  // Ceres runs single-threaded: its threaded evaluator sums the cost and
  // gradient in an order that depends on the thread count, which changes
  // the last bits of the estimates. Run several identifications in
  // parallel instead (as RunMonteCarlo does).
  // The stacked Jacobian, columns scaled to unit norm, is taken as rank
  // deficient when sigma_min / sigma_max falls below this.
  double rank_tolerance = 1e-10;

  bool IsValid(std::string* error) const;
};

// What the Jacobian says about which parameters the measurements determine.
struct IdentifiabilityReport {
  int num_equations = 0;
  int num_free = 0;
  int rank = 0;
  // Singular values of the column-normalised stacked Jacobian, descending.
  Eigen::VectorXd singular_values;
  // One line per direction the data cannot see, e.g.
  // "0.71 * L1.gamma - 0.71 * B.gamma" or "L3.d has no effect".
  std::vector<std::string> unidentifiable;
  bool identifiable() const {
    return num_equations >= num_free && rank == num_free;
  }
  std::string Message() const;
};

// Analyses a stacked (m x num_free) Jacobian whose columns follow
// model.FreeParameterNames().
IdentifiabilityReport AnalyzeIdentifiability(const RobotModel& model,
                                             const Eigen::MatrixXd& jacobian,
                                             double rank_tolerance = 1e-10);

// Free parameters (positions in free-parameter order, ascending) to hold
// at their current values so that the rest are identifiable from
// `jacobian`: the columns left over by QR with column pivoting on the
// column-normalised Jacobian, i.e. those closest to combinations of the
// others. Empty when all are identifiable.
std::vector<int> SuggestParametersToFix(const Eigen::MatrixXd& jacobian,
                                        double rank_tolerance = 1e-10);

// The auto-fix policy: analyses `jacobian` (m x num_free, columns in
// model.FreeParameterNames() order) into *report and, when it does not
// identify every free parameter but has at least as many rows as columns,
// holds fixed the parameters SuggestParametersToFix names: *free is the
// model's free set without them, *held names them (stage kAutoFix). The
// rule is deterministic: columns with no effect first, then QR with column
// pivoting on the unit-norm columns keeps the rank-many columns it pivots
// first (the largest remaining norm; on a tie the earlier parameter in
// free-parameter order) and fixes the rest. *fixed_columns (may be null)
// gets their positions among the free parameters (ascending). Returns true
// when every free parameter was identifiable (nothing held) or the
// parameters were held (the rest then have a full-rank Jacobian by
// construction of the rank-revealing QR); false, with *free the model's
// set, when there are fewer rows than free parameters.
bool FixUnidentifiableParameters(const RobotModel& model,
                                 const Eigen::MatrixXd& jacobian,
                                 double rank_tolerance,
                                 IdentifiabilityReport* report, FreeSet* free,
                                 std::vector<HeldParameter>* held,
                                 std::vector<int>* fixed_columns = nullptr);

struct IdentificationSummary {
  // kConvergence when the problem was identifiable, the solver converged
  // and the covariance was computed. Otherwise `message` says why.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;

  std::vector<std::string> names;       // free parameters, in order
  Eigen::VectorXd initial;              // full vector
  Eigen::VectorXd parameters;           // full vector, identified
  Eigen::VectorXd estimates;            // free parameters
  Eigen::VectorXd standard_deviations;  // free parameters
  Eigen::MatrixXd covariance;           // free x free, scaled by s^2
  Eigen::MatrixXd correlation;          // free x free
  // Residual rows of every measurement, in order (dimension() each).
  Eigen::VectorXd residuals;
  // With joint error terms (options.joint_errors): the terms with their
  // identified values, their names and standard deviations (the rows of
  // `covariance` hold the geometric parameters only; term_covariance is
  // the joint covariance of geometric parameters then terms).
  JointErrorModel joint_errors;
  std::vector<std::string> term_names;
  Eigen::VectorXd term_standard_deviations;
  Eigen::MatrixXd term_covariance;
  // Fixed points (point rows, point_constraints.h): their labels (in
  // PointLabels order) and identified coordinates (x, y, z of each, m, in
  // the device frame: the base frame when no row sees a device), with their
  // standard deviations and covariance (the coordinates are fitted with the
  // model; `covariance` holds the model's parameters only).
  std::vector<std::string> point_labels;
  Eigen::VectorXd point_coordinates;
  Eigen::VectorXd point_standard_deviations;
  Eigen::MatrixXd point_covariance;
  // Planes (plane rows, plane_constraints.h): their labels (PlaneLabels
  // order) and identified planes, 4 values each (unit normal n, offset d:
  // n . x = d, m), with 3 standard deviations each: of the normal's two
  // tangent directions (rad; Ceres's SphereManifold basis at n) and of d
  // (m). plane_covariance: the tangent-space covariance (3 per plane).
  std::vector<std::string> plane_labels;
  Eigen::VectorXd plane_parameters;
  Eigen::VectorXd plane_standard_deviations;
  Eigen::MatrixXd plane_covariance;
  // Per measurement: the norm of its residual rows at start and at the
  // estimate (m; a 6D pose's rotation rows weighted).
  Eigen::VectorXd initial_residual_norms;
  Eigen::VectorXd residual_norms;
  // Measurements flagged as outliers at the estimate (indices, ascending):
  // outlier_d2 > outlier_threshold (OutlierStatistics below).
  std::vector<int> outliers;
  Eigen::VectorXd outlier_d2, outlier_threshold;  // per measurement
  int num_measurements = 0;
  int num_residuals = 0;
  int num_free = 0;
  double initial_rms_m = 0.0;  // RMS of the residual norms at start
  double rms_m = 0.0;          // ... at the estimate
  double sigma_m = 0.0;        // s = sqrt(SSR / (m - p)), per residual row
  // True when every row was divided by its standard deviation (stated by
  // the measurement or a default). Then:
  bool weighted = false;
  double chi_square = 0.0;          // sum of the weighted squared rows
  int degrees_of_freedom = 0;       // rows - free parameters
  double chi_square_per_dof = 0.0;  // ~1 when the stated sigmas fit
  // The central 99.9 % interval of chi^2 / dof for this dof, and whether
  // chi_square_per_dof lies inside it (true when not weighted).
  double chi_square_per_dof_low = 0.0, chi_square_per_dof_high = 0.0;
  bool chi_square_plausible = true;
  Eigen::VectorXd scaled_standard_deviations;  // weighted only, see above
  // The noise of a position (or distance) row the residuals imply, m:
  // sqrt(chi^2 / dof) times the RMS of the stated sigmas when weighted,
  // sigma_m otherwise.
  double implied_sigma_m = 0.0;
  bool with_prior = false;  // a MAP fit (prior_std_m or prior_std_rad > 0)
  int iterations = 0;
  IdentifiabilityReport identifiability;
  ceres::Solver::Summary solver_summary;

  std::string BriefReport() const;
};

// Identifies the free parameters of `model` from `measurements`, starting
// from the full parameter vector `initial` (usually model.nominal).
// summary->termination_type says how it ended; unless kConvergence,
// summary->message names the problem: bad input, too few equations,
// unidentifiable parameters, no convergence. `summary` must not be null.
void Identify(const RobotModel& model,
              const std::vector<Measurement>& measurements,
              const Eigen::VectorXd& initial,
              const IdentificationOptions& options,
              IdentificationSummary* summary);

// The outlier rule of IdentificationOptions::outlier_probability, per
// measurement: *d2 its residual rows (`residuals`, stacked in measurement
// order) over the robust scale of their class, squared and summed, and
// *threshold the chi-square quantile of its dimension at 1 - probability /
// N. A measurement is an outlier when d2 > threshold.
void OutlierStatistics(const std::vector<Measurement>& measurements,
                       const Eigen::VectorXd& residuals, double probability,
                       double min_sigma_m, Eigen::VectorXd* d2,
                       Eigen::VectorXd* threshold);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_IDENTIFICATION_H_
