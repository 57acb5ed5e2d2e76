// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Accuracy on real data: per-measurement sigma weighting, the MAP fit, the
// registration-only baseline, model selection by held-out error, the
// warnings on the estimates and the posture groups of an evaluation.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <map>
#include <string>

#include "activecal/core/lattice.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/estimate_warnings.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/model_selection.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/estimation/registration.h"
#include "activecal/estimation/registration_fit.h"
#include "activecal/estimation/residual_scale.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/residuals/jacobians.h"
#include "test_util.h"

namespace activecal {
namespace {

std::vector<Measurement> Simulate(const RobotModel& m,
                                  const Eigen::VectorXd& truth,
                                  const std::vector<Measurement>& plan,
                                  double noise_m, uint64_t seed) {
  std::vector<Measurement> out;
  std::string error;
  EXPECT_TRUE(
      SimulateMeasurements(m, truth, plan, {noise_m, 0.0}, seed, &out, &error))
      << error;
  return out;
}

std::vector<Measurement> PumaMeasurements(int num_poses, double noise_m,
                                          uint64_t seed) {
  return Simulate(Puma560PaperModel(), Puma560TrueParameters(),
                  MeasurementPlan(testing::PumaLatticeSample(num_poses, seed)),
                  noise_m, seed + 100);
}

IdentificationSummary Fit(const RobotModel& m,
                          const std::vector<Measurement>& data,
                          const IdentificationOptions& options) {
  IdentificationSummary s;
  Identify(m, data, m.nominal, options, &s);
  EXPECT_EQ(s.termination_type, TerminationType::kConvergence) << s.message;
  return s;
}

TEST(WeightedIdentificationTest, UniformSigmaGivesTheSameFitAndItsCovariance) {
  const RobotModel m = Puma560PaperModel();
  std::vector<Measurement> data = PumaMeasurements(30, 0.001, 1);
  const IdentificationSummary plain = Fit(m, data, {});
  EXPECT_FALSE(plain.weighted);
  const double sigma = 0.002;
  for (Measurement& d : data) d.sigma_m.setConstant(sigma);
  const IdentificationSummary weighted = Fit(m, data, {});
  ASSERT_TRUE(weighted.weighted);
  EXPECT_LT((weighted.estimates - plain.estimates).cwiseAbs().maxCoeff(), 1e-9);
  // chi^2 / dof = s^2 / sigma^2, and the implied noise is s.
  const double ratio = plain.sigma_m * plain.sigma_m / (sigma * sigma);
  EXPECT_NEAR(weighted.chi_square_per_dof, ratio, 1e-9 * ratio);
  EXPECT_NEAR(weighted.implied_sigma_m, plain.sigma_m, 1e-9 * plain.sigma_m);
  EXPECT_EQ(weighted.degrees_of_freedom, 90 - m.num_free());
  // The stated sigma is taken at its word: cov = (J^T J)^-1 sigma^2.
  const Eigen::MatrixXd expected = plain.covariance / ratio;
  EXPECT_LT((weighted.covariance - expected).norm(), 1e-6 * expected.norm());
}

TEST(WeightedIdentificationTest, CovarianceIsTheInverseOfJtWJ) {
  const RobotModel m = Puma560PaperModel();
  // Half the poses measured with 0.5 mm, half with 4 mm noise.
  const Eigen::MatrixXd poses = testing::PumaLatticeSample(40, 2);
  std::vector<Measurement> data;
  for (int half = 0; half < 2; ++half) {
    const double sigma = half ? 0.004 : 0.0005;
    std::vector<Measurement> part = Simulate(
        m, Puma560TrueParameters(),
        MeasurementPlan(poses.middleRows(20 * half, 20)), sigma, 7 + half);
    for (Measurement& d : part) d.sigma_m.setConstant(sigma);
    data.insert(data.end(), part.begin(), part.end());
  }
  const IdentificationSummary s = Fit(m, data, {});
  ASSERT_TRUE(s.weighted);
  Eigen::MatrixXd J;
  std::string error;
  ASSERT_TRUE(StackedJacobian(m, s.parameters, data, 1.0, &J, &error));
  for (int r = 0; r < J.rows(); ++r) J.row(r) /= r < 60 ? 0.0005 : 0.004;
  const Eigen::MatrixXd info = J.transpose() * J;
  const Eigen::MatrixXd cov =
      info.ldlt().solve(Eigen::MatrixXd::Identity(info.rows(), info.cols()));
  EXPECT_LT((s.covariance - cov).norm(), 1e-6 * cov.norm());
  // The stated noise fits: chi^2 / dof near 1 (dof = 120 - p).
  EXPECT_GT(s.chi_square_per_dof, 0.6);
  EXPECT_LT(s.chi_square_per_dof, 1.5);
  // chi^2 recomputed from the raw residuals.
  double chi2 = 0.0;
  for (int r = 0; r < s.residuals.size(); ++r) {
    chi2 += std::pow(s.residuals[r] / (r < 60 ? 0.0005 : 0.004), 2);
  }
  EXPECT_NEAR(s.chi_square, chi2, 1e-9 * chi2);
}

TEST(WeightedIdentificationTest, SomeRowsWithoutSigmaNeedADefault) {
  const RobotModel m = Puma560PaperModel();
  std::vector<Measurement> data = PumaMeasurements(30, 0.001, 3);
  for (size_t i = 0; i < data.size(); i += 2) data[i].sigma_m.setConstant(1e-3);
  IdentificationSummary s;
  Identify(m, data, m.nominal, {}, &s);
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);
  EXPECT_NE(s.message.find("measurement 1 has no standard deviation"),
            std::string::npos)
      << s.message;
  IdentificationOptions options;
  options.default_sigma_m = 1e-3;
  const IdentificationSummary with_default = Fit(m, data, options);
  EXPECT_TRUE(with_default.weighted);
  // Defaults alone weight every row too.
  for (Measurement& d : data) d.sigma_m.setZero();
  EXPECT_TRUE(Fit(m, data, options).weighted);
  // A robust loss with sigmas is refused (its scale would be in sigmas).
  options.robust_loss = RobustLoss::kHuber;
  options.robust_scale_m = 0.003;
  Identify(m, data, m.nominal, options, &s);
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);
}

TEST(WeightedIdentificationTest, NegativeOrNonFiniteSigmaIsRefused) {
  const RobotModel m = Puma560PaperModel();
  for (double bad : {-1e-3, std::nan(""), HUGE_VAL}) {
    std::vector<Measurement> data = PumaMeasurements(30, 0.001, 5);
    for (Measurement& d : data) d.sigma_m.setConstant(1e-3);
    data[4].sigma_m[1] = bad;
    IdentificationSummary s;
    Identify(m, data, m.nominal, {}, &s);
    EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);
    EXPECT_NE(s.message.find("measurement 4"), std::string::npos) << s.message;
    EXPECT_NE(s.message.find("sigma_m"), std::string::npos) << s.message;
  }
}

TEST(MapFitTest, WidePriorIsLeastSquaresNarrowPriorHoldsTheNominal) {
  const RobotModel m = Puma560PaperModel();
  const std::vector<Measurement> data = PumaMeasurements(30, 0.001, 4);
  const IdentificationSummary plain = Fit(m, data, {});
  IdentificationOptions options;
  options.prior_std_m = 1e3;
  options.prior_std_rad = 1e3;
  IdentificationSummary s;
  Identify(m, data, m.nominal, options, &s);
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure)
      << "unweighted rows need prior_reference_sigma_m";
  options.prior_reference_sigma_m = plain.sigma_m;
  const IdentificationSummary wide = Fit(m, data, options);
  EXPECT_TRUE(wide.with_prior);
  EXPECT_LT((wide.estimates - plain.estimates).cwiseAbs().maxCoeff(), 1e-8);
  options.prior_std_m = options.prior_std_rad = 1e-9;
  const IdentificationSummary narrow = Fit(m, data, options);
  const std::vector<int> free = m.FreeParameterIndices();
  for (size_t k = 0; k < free.size(); ++k) {
    const int block = m.BlockOf(free[k]);
    if (block == 0 || m.is_marker_block(block)) continue;  // no prior
    EXPECT_NEAR(narrow.estimates[k], m.nominal[free[k]], 1e-7)
        << narrow.names[k];
  }
}

// data/ur10e.urdf, the chain from base_link to tool0.
RobotDescription Ur10e() {
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(LoadUrdfRobot(std::string(ACTIVECAL_DATA_DIR) + "/ur10e.urdf",
                            chain, &robot, &error))
      << error;
  return robot;
}

std::vector<Measurement> UrPlan(const RobotModel& m, int num_poses,
                                MeasurementType type, uint64_t seed) {
  Random random(seed);
  Eigen::MatrixXd joints(num_poses, m.num_joints());
  for (int i = 0; i < num_poses; ++i) {
    for (int j = 0; j < m.num_joints(); ++j) {
      joints(i, j) = -2.5 + 5.0 * random.Uniform();
    }
  }
  return MeasurementPlan(joints, type);
}

// The UR10e seen from a device 1.2 m away and turned: base frame set.
Eigen::VectorXd Ur10eInDeviceFrame(const RobotModel& m) {
  Eigen::VectorXd truth = m.nominal;
  truth.head(6) << 1.2, -0.4, 0.3, 0.2, -0.1, 2.0;
  return truth;
}

TEST(RegistrationFitTest, EqualsADirectRegistrationIdentification) {
  const RobotDescription robot = Ur10e();
  const RobotModel& m = robot.model;
  const Eigen::VectorXd truth = Ur10eInDeviceFrame(m);
  const std::vector<Measurement> data = Simulate(
      m, truth, UrPlan(m, 25, MeasurementType::kPosition, 5), 0.0005, 6);
  RegistrationFitSummary fit;
  FitRegistration(m, m.nominal, data, {}, &fit);
  ASSERT_EQ(fit.termination_type, TerminationType::kConvergence) << fit.message;
  // The same thing done by hand: closed form, registration set, Identify.
  RobotModel direct = m;
  Eigen::VectorXd start = m.nominal;
  RegistrationSummary closed_form;
  ASSERT_TRUE(RegisterBaseFrame(direct, data, &start, &closed_form));
  std::vector<HeldParameter> dropped;
  std::string error;
  ASSERT_TRUE(testing::ReduceModel(ParameterSet::kRegistration, data, 1.0,
                                   &direct, &start, &dropped, &error));
  const IdentificationSummary id = Fit(direct, data, {});
  (void)id;
  IdentificationSummary by_hand;
  Identify(direct, data, start, {}, &by_hand);
  ASSERT_EQ(by_hand.termination_type, TerminationType::kConvergence);
  EXPECT_NEAR(fit.rms_m, by_hand.rms_m, 1e-12);
  EXPECT_EQ(fit.names, direct.FreeParameterNames());
  // The markers fitted too: no worse than the closed form alone.
  EXPECT_LE(fit.rms_m, closed_form.rms_m + 1e-12);
  // Nominal geometry, so the fit leaves the noise: about 0.5 mm per axis.
  EXPECT_LT(fit.rms_m, 3 * 0.0005 * std::sqrt(3.0));
  EXPECT_LT((fit.parameters.head(3) - truth.head(3)).norm(), 0.002);
  // Geometry untouched.
  const int links = m.block_offset(m.marker_block(0)) - m.block_offset(1);
  EXPECT_EQ(fit.parameters.segment(m.block_offset(1), links),
            m.nominal.segment(m.block_offset(1), links));
}

// The baseline of a calibration frees only the registration parameters
// the calibrated model has free: the PUMA file holds its tool point, and
// the registration set freed it anyway ("0.350 m -> 0.378 m calibrated
// (-8.0 % lower)": a baseline with more parameters than the calibration).
TEST(RegistrationFitTest, BaselineOfTheFreeSetIsASubsetOfIt) {
  const RobotModel m = Puma560PaperModel();
  const std::vector<Measurement> data = PumaMeasurements(30, 0.001, 4);
  RegistrationFitSummary all, of_free;
  FitRegistration(m, m.nominal, data, {}, &all);
  FitRegistrationOfFreeSet(m, m.nominal, data, {}, &of_free);
  ASSERT_EQ(of_free.termination_type, TerminationType::kConvergence)
      << of_free.message;
  const std::vector<std::string> free = m.FreeParameterNames();
  for (const std::string& name : of_free.names) {
    EXPECT_NE(std::find(free.begin(), free.end(), name), free.end()) << name;
  }
  EXPECT_EQ(of_free.names,
            (std::vector<std::string>{"B.gamma", "B.alpha", "B.a", "B.beta"}));
  // The registration set alone frees the held tool point too.
  EXPECT_GT(all.names.size(), of_free.names.size());
  const int tool = m.block_offset(m.marker_block(0));
  EXPECT_EQ(of_free.parameters.segment(tool, 3), m.nominal.segment(tool, 3));
  // A calibration of the free set fits at least as well as its baseline.
  IdentificationSummary fit;
  Identify(m, data, m.nominal, {}, &fit);
  ASSERT_EQ(fit.termination_type, TerminationType::kConvergence);
  EXPECT_LE(fit.rms_m, of_free.rms_m);
  // A URDF chain with the full set reduced: a subset again, and a model
  // that holds its whole base gets no closed-form registration.
  const RobotDescription ur = Ur10e();
  RobotModel reduced = ur.model;
  Eigen::VectorXd start = reduced.nominal;
  const std::vector<Measurement> points =
      Simulate(reduced, Ur10eInDeviceFrame(reduced),
               UrPlan(reduced, 25, MeasurementType::kPosition, 5), 0.0005, 6);
  std::vector<HeldParameter> dropped;
  std::string error;
  ASSERT_TRUE(testing::ReduceModel(ParameterSet::kFull, points, 1.0, &reduced,
                                   &start, &dropped, &error));
  FitRegistrationOfFreeSet(reduced, reduced.nominal, points, {}, &of_free);
  ASSERT_EQ(of_free.termination_type, TerminationType::kConvergence);
  const std::vector<std::string> ur_free = reduced.FreeParameterNames();
  for (const std::string& name : of_free.names) {
    EXPECT_NE(std::find(ur_free.begin(), ur_free.end(), name), ur_free.end())
        << name;
  }
  EXPECT_EQ(of_free.names.size(), 9u);  // base and reflector point
  RobotModel held = reduced;
  for (int j = 0; j < 6; ++j) held.SetFree(j, false);
  FitRegistrationOfFreeSet(held, held.nominal, points, {}, &of_free);
  ASSERT_EQ(of_free.termination_type, TerminationType::kConvergence);
  EXPECT_EQ(of_free.names.size(), 3u);
  EXPECT_EQ(of_free.parameters.head(6), held.nominal.head(6));
}

// chi^2 / dof against its 99.9 % interval (identification.h): the sigma
// stated just inside and just outside each end. chi^2 scales exactly with
// 1 / sigma^2 for a uniform sigma (the estimates do not change).
TEST(WeightedIdentificationTest, ChiSquareOutsideItsIntervalScalesTheStd) {
  const RobotModel m = Puma560PaperModel();
  std::vector<Measurement> data = PumaMeasurements(60, 0.001, 3);
  for (Measurement& d : data) d.sigma_m.setConstant(0.001);
  const IdentificationSummary first = Fit(m, data, {});
  ASSERT_TRUE(first.weighted);
  const double c = first.chi_square_per_dof;
  const double low = first.chi_square_per_dof_low;
  const double high = first.chi_square_per_dof_high;
  EXPECT_EQ(first.degrees_of_freedom, 180 - 27);
  EXPECT_LT(low, 1.0);
  EXPECT_GT(high, 1.0);
  EXPECT_GT(low, 0.5);  // 153 dof: about 0.66 .. 1.42
  EXPECT_LT(high, 1.6);
  for (double target : {low, high}) {
    for (double side : {-1.0, 1.0}) {
      // chi^2 / dof = target * (1 + side * 1e-3): inside for side = -1 at
      // the high end and +1 at the low one.
      const double wanted = target * (1 + side * 1e-3);
      const double sigma = 0.001 * std::sqrt(c / wanted);
      for (Measurement& d : data) d.sigma_m.setConstant(sigma);
      const IdentificationSummary s = Fit(m, data, {});
      ASSERT_NEAR(s.chi_square_per_dof, wanted, 1e-6 * wanted);
      const bool inside = (target == high) == (side < 0);
      EXPECT_EQ(s.chi_square_plausible, inside) << target << " " << side;
      ASSERT_EQ(s.scaled_standard_deviations.size(), 27);
      EXPECT_LT((s.scaled_standard_deviations -
                 s.standard_deviations * std::sqrt(wanted))
                    .cwiseAbs()
                    .maxCoeff(),
                1e-9 * s.standard_deviations.maxCoeff());
      std::string warned;
      for (const std::string& w : EstimateWarnings(m, s, {})) warned += w;
      const bool says =
          warned.find("outside the 99.9 % interval") != std::string::npos;
      EXPECT_EQ(says, !inside);
    }
  }
  // Far outside (a tracker's datasheet sigma against a robot's errors):
  // the warnings use the scaled std and say so.
  for (Measurement& d : data) d.sigma_m.setConstant(1e-5);
  const IdentificationSummary s = Fit(m, data, {});
  EXPECT_FALSE(s.chi_square_plausible);
  EXPECT_GT(s.chi_square_per_dof, 1000);
  std::string all;
  for (const std::string& w : EstimateWarnings(m, s, {})) all += w + "\n";
  EXPECT_NE(all.find("the std below are scaled by sqrt(chi^2 / dof)"),
            std::string::npos)
      << all;
  // Without sigmas nothing is scaled.
  for (Measurement& d : data) d.sigma_m.setZero();
  const IdentificationSummary plain = Fit(m, data, {});
  EXPECT_TRUE(plain.chi_square_plausible);
  EXPECT_EQ(plain.scaled_standard_deviations.size(), 0);
}

// The unit check (residual_scale.h): the reach is the farthest measured
// point from the base frame with the base at the identity, and the rule
// refuses an RMS residual just above it, accepts it at the reach.
TEST(ResidualScaleTest, ReachIsTheFarthestPointAndTheRuleCrossesIt) {
  const RobotModel m = Puma560PaperModel();
  const std::vector<Measurement> data = PumaMeasurements(20, 0.001, 6);
  Eigen::VectorXd at_origin = m.nominal;
  at_origin.head(m.block_size(0)).setZero();
  double farthest = 0.0;
  for (const Measurement& d : data) {
    farthest =
        std::max(farthest, PredictMeasurement(m, at_origin, d).position.norm());
  }
  const double reach = ReachAtPoses(m, m.nominal, data);
  EXPECT_NEAR(reach, farthest, 1e-12);
  EXPECT_GT(reach, 0.5);  // a PUMA arm, not its base 20 m away
  EXPECT_LT(reach, 1.5);
  std::string error;
  EXPECT_TRUE(ResidualWithinReach(m, m.nominal, data, reach, &error));
  EXPECT_FALSE(
      ResidualWithinReach(m, m.nominal, data, reach * (1 + 1e-9), &error));
  EXPECT_NE(error.find("are the measured values in millimetres?"),
            std::string::npos)
      << error;
  // Points in mm read as m: the registration-only residual is far beyond.
  std::vector<Measurement> mm = data;
  for (Measurement& d : mm) d.position *= 1000;
  RegistrationFitSummary fit;
  FitRegistrationOfFreeSet(m, m.nominal, mm, {}, &fit);
  EXPECT_FALSE(ResidualWithinReach(m, m.nominal, mm, fit.rms_m, &error));
  FitRegistrationOfFreeSet(m, m.nominal, data, {}, &fit);
  ASSERT_EQ(fit.termination_type, TerminationType::kConvergence);
  EXPECT_TRUE(ResidualWithinReach(m, m.nominal, data, fit.rms_m, &error));
}

TEST(ModelSelectionTest, RankingPutsRegistrationFirstAndEachPrefixHasFullRank) {
  RobotDescription robot = Ur10e();
  RobotModel m = robot.model;
  const std::vector<Measurement> data =
      UrPlan(m, 20, MeasurementType::kPose, 8);
  Eigen::VectorXd point = m.nominal;
  std::vector<HeldParameter> dropped;
  std::string error;
  ASSERT_TRUE(testing::ReduceModel(ParameterSet::kFull, data, 0.1, &m, &point,
                                   &dropped, &error));
  Eigen::MatrixXd J;
  ASSERT_TRUE(StackedJacobian(m, point, data, 0.1, &J, &error));
  int num_registration = 0;
  const std::vector<int> order = RankFreeParameters(m, J, &num_registration);
  ASSERT_EQ(static_cast<int>(order.size()), m.num_free());
  EXPECT_EQ(num_registration, 12);  // base frame and a 6D marker
  const std::vector<int> free = m.FreeParameterIndices();
  for (int k = 0; k < static_cast<int>(order.size()); ++k) {
    const int block = m.BlockOf(free[order[k]]);
    EXPECT_EQ(k < num_registration, block == 0 || m.is_marker_block(block));
    Eigen::MatrixXd prefix(J.rows(), k + 1);
    for (int c = 0; c <= k; ++c) {
      prefix.col(c) = J.col(order[c]).normalized();
    }
    const Eigen::VectorXd sv =
        Eigen::JacobiSVD<Eigen::MatrixXd>(prefix).singularValues();
    EXPECT_GT(sv[k], 1e-6 * sv[0]) << "prefix " << k + 1;
  }
  // A permutation of the free parameters.
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 0; k < static_cast<int>(sorted.size()); ++k) {
    EXPECT_EQ(sorted[k], k);
  }
}

TEST(ModelSelectionTest, FoldsKeepPosesTogetherAndFollowTheSeed) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::MatrixXd poses = testing::PumaLatticeSample(11, 9);
  // Every pose measured twice (position, then pose).
  std::vector<Measurement> data = MeasurementPlan(poses);
  const std::vector<Measurement> again =
      MeasurementPlan(poses, MeasurementType::kPose);
  data.insert(data.end(), again.begin(), again.end());
  std::vector<int> fold, fold2, other;
  int num_poses = 0;
  std::string error;
  ASSERT_TRUE(AssignPoseFolds(data, 5, 1, &fold, &num_poses, &error));
  EXPECT_EQ(num_poses, 11);
  std::vector<int> per_fold(5, 0);
  for (int i = 0; i < 11; ++i) {
    EXPECT_EQ(fold[i], fold[11 + i]);
    ++per_fold[fold[i]];
  }
  for (int c : per_fold) EXPECT_TRUE(c == 2 || c == 3) << c;
  ASSERT_TRUE(AssignPoseFolds(data, 5, 1, &fold2, &num_poses, &error));
  EXPECT_EQ(fold, fold2);
  ASSERT_TRUE(AssignPoseFolds(data, 5, 2, &other, &num_poses, &error));
  EXPECT_NE(fold, other);
  // 11 poses: 11 folds work, 12 do not.
  EXPECT_TRUE(AssignPoseFolds(data, 11, 1, &fold, &num_poses, &error));
  EXPECT_FALSE(AssignPoseFolds(data, 12, 1, &fold, &num_poses, &error));
  EXPECT_EQ(error,
            "12 folds need at least 12 distinct poses, the "
            "measurements have 11");
}

// The UR10e with errors in a few joint origins only, plus noise: every
// other link parameter is fitted noise.
struct SparseErrors {
  RobotModel model;  // full set, reduced
  Eigen::VectorXd start;
  std::vector<Measurement> training, validation;
};

SparseErrors MakeSparseErrors(uint64_t seed) {
  SparseErrors out;
  const RobotDescription robot = Ur10e();
  out.model = robot.model;
  Eigen::VectorXd truth = Ur10eInDeviceFrame(out.model);
  // 2 mm and 3 mrad errors in two joints' origins.
  truth[out.model.ParameterIndex("shoulder_lift_joint.offset")] += 0.003;
  truth[out.model.ParameterIndex("elbow_joint.x")] += 0.002;
  truth[out.model.ParameterIndex("wrist_1_joint.offset")] -= 0.003;
  out.training = Simulate(
      out.model, truth, UrPlan(out.model, 30, MeasurementType::kPosition, seed),
      0.001, seed + 1);
  out.validation =
      Simulate(out.model, truth,
               UrPlan(out.model, 60, MeasurementType::kPosition, seed + 2),
               0.001, seed + 3);
  out.start = out.model.nominal;
  RegistrationSummary reg;
  EXPECT_TRUE(RegisterBaseFrame(out.model, out.training, &out.start, &reg));
  std::vector<HeldParameter> dropped;
  std::string error;
  EXPECT_TRUE(testing::ReduceModel(ParameterSet::kFull, out.training, 1.0,
                                   &out.model, &out.start, &dropped, &error))
      << error;
  return out;
}

TEST(ModelSelectionTest, CrossValidationKeepsTheMinimumOfItsCurve) {
  SparseErrors problem = MakeSparseErrors(20);
  const int p = problem.model.num_free();
  ModelSelectionOptions options;
  options.method = ModelSelectionMethod::kCrossValidation;
  options.rule = SelectionRule::kMinimum;
  options.num_folds = 4;
  RobotModel chosen = problem.model;
  ModelSelectionSummary summary;
  SelectModel(chosen, problem.start, problem.training, {}, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  ASSERT_EQ(static_cast<int>(summary.curve.size()),
            p - summary.num_registration + 1);
  double best = 1e300;
  int argmin = 0;
  for (size_t k = 0; k < summary.curve.size(); ++k) {
    const ModelSelectionPoint& pt = summary.curve[k];
    EXPECT_EQ(pt.num_kept, summary.num_registration + static_cast<int>(k));
    if (k > 0) {
      // Nested least squares: more parameters never fit the training
      // data worse (up to the solver's tolerance).
      EXPECT_LE(pt.training_rms_m,
                summary.curve[k - 1].training_rms_m * (1 + 1e-6));
    }
    if (pt.ok && pt.held_out_rms_m < best) {
      best = pt.held_out_rms_m;
      argmin = pt.num_kept;
    }
  }
  EXPECT_EQ(summary.best_num_kept, argmin);
  EXPECT_EQ(summary.free.size(), argmin);
  EXPECT_EQ(static_cast<int>(summary.dropped.size()), p - argmin);
  // Three real errors among ~20 link parameters: the rest is noise, and
  // cross-validation drops some of it.
  EXPECT_LT(argmin, p);
  EXPECT_GT(argmin, summary.num_registration);
  // Deterministic.
  RobotModel again = problem.model;
  ModelSelectionSummary summary2;
  options.num_threads = 2;  // the same result on two threads
  SelectModel(again, problem.start, problem.training, {}, options, &summary2);
  ASSERT_EQ(summary2.curve.size(), summary.curve.size());
  for (size_t k = 0; k < summary.curve.size(); ++k) {
    EXPECT_EQ(summary2.curve[k].ok, summary.curve[k].ok);
    if (summary.curve[k].ok) {
      EXPECT_EQ(summary2.curve[k].held_out_rms_m,
                summary.curve[k].held_out_rms_m);
    }
  }
  // The chosen model predicts new poses no worse than the full one.
  chosen = WithFreeSet(problem.model, summary.free);
  IdentificationSummary full, kept;
  Identify(problem.model, problem.training, problem.start, {}, &full);
  Identify(chosen, problem.training, problem.start, {}, &kept);
  Eigen::VectorXd e_full, e_kept;
  std::string error;
  ASSERT_TRUE(MeasurementErrors(problem.model, full.parameters,
                                problem.validation, 1.0, &e_full, &error));
  ASSERT_TRUE(MeasurementErrors(chosen, kept.parameters, problem.validation,
                                1.0, &e_kept, &error));
  EXPECT_LT(e_kept.norm(), e_full.norm());
}

TEST(ModelSelectionTest, ValidationFileAndNoneAndTooFewPoses) {
  SparseErrors problem = MakeSparseErrors(30);
  const int p = problem.model.num_free();
  ModelSelectionOptions options;
  options.method = ModelSelectionMethod::kValidation;
  RobotModel chosen = problem.model;
  ModelSelectionSummary summary;
  SelectModel(chosen, problem.start, problem.training, problem.validation,
              options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.num_held_out, 60);
  // The first point of the curve is the registration-only fit, its
  // held-out error after refitting the registration to the validation
  // poses: the nominal geometry's registration-only error there.
  RegistrationFitSummary baseline;
  FitRegistration(problem.model, problem.model.nominal, problem.validation, {},
                  &baseline);
  ASSERT_EQ(baseline.termination_type, TerminationType::kConvergence);
  EXPECT_NEAR(summary.curve[0].held_out_rms_m, baseline.rms_m,
              1e-6 * baseline.rms_m);
  EXPECT_LT(summary.best_num_kept, p);
  // none keeps every parameter and fits nothing.
  options.method = ModelSelectionMethod::kNone;
  chosen = problem.model;
  SelectModel(chosen, problem.start, problem.training, {}, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kConvergence);
  EXPECT_EQ(summary.best_num_kept, p);
  EXPECT_TRUE(summary.curve.empty());
  EXPECT_EQ(summary.free.size(), p);
  // More folds than poses: refused, saying so.
  options.method = ModelSelectionMethod::kCrossValidation;
  options.num_folds = 31;
  SelectModel(chosen, problem.start, problem.training, {}, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_NE(summary.message.find("31 folds need at least 31 distinct poses"),
            std::string::npos)
      << summary.message;
}

// 12 PUMA poses, every one of the 27 parameters carrying a real error:
// the 5 folds' training parts have 27-30 rows, too few for the larger
// models, which fail on some fold. The choice falls on a smaller count
// without any evidence that the larger ones predict worse; the message
// says which counts were not tested.
TEST(ModelSelectionTest, CountsThatCouldNotBeTestedAreNamed) {
  const std::vector<Measurement> data = PumaMeasurements(12, 5e-4, 7);
  RobotModel chosen = Puma560PaperModel();
  const int p = chosen.num_free();
  ModelSelectionOptions options;
  ModelSelectionSummary summary;
  SelectModel(chosen, chosen.nominal, data, {}, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  ASSERT_FALSE(summary.curve.back().ok);
  EXPECT_LT(summary.best_num_kept, p);
  EXPECT_NE(summary.message.find("not tested"), std::string::npos)
      << summary.message;
  EXPECT_NE(summary.message.find(std::to_string(p) + ")"), std::string::npos)
      << summary.message;
  // Enough poses: every count tested, no such note.
  chosen = Puma560PaperModel();
  SelectModel(chosen, chosen.nominal, PumaMeasurements(40, 5e-4, 7), {},
              options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence);
  EXPECT_EQ(summary.message.find("not tested"), std::string::npos)
      << summary.message;
}

// The rules that choose the count from one curve (model_selection.h): the
// same curve for every rule; "within one SE" is the paired excess of the
// held-out MSE over the minimum's against its standard error; each rule's
// choice crosses its own threshold (the point it keeps passes, the next
// one in its direction does not).
TEST(ModelSelectionTest, EachRuleChoosesByItsThreshold) {
  const std::vector<Measurement> data = PumaMeasurements(30, 0.01, 1);
  std::map<SelectionRule, ModelSelectionSummary> by_rule;
  for (SelectionRule rule :
       {SelectionRule::kMinimum, SelectionRule::kFewestWithinOneSe,
        SelectionRule::kMostWithinOneSe, SelectionRule::kFTest}) {
    RobotModel chosen = Puma560PaperModel();
    ModelSelectionOptions options;
    options.rule = rule;
    options.num_threads = 2;
    ModelSelectionSummary& summary = by_rule[rule];
    SelectModel(chosen, chosen.nominal, data, {}, options, &summary);
    ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
        << summary.message;
    EXPECT_EQ(summary.free.size(), summary.best_num_kept);
    EXPECT_NE(summary.message.find(std::string("rule ") +
                                   SelectionRuleToString(rule)),
              std::string::npos)
        << summary.message;
  }
  const ModelSelectionSummary& min = by_rule[SelectionRule::kMinimum];
  const std::vector<ModelSelectionPoint>& curve = min.curve;
  const int first = curve.front().num_kept;
  int argmin = -1;
  for (size_t k = 0; k < curve.size(); ++k) {
    ASSERT_TRUE(curve[k].ok);
    if (argmin < 0 || curve[k].held_out_rms_m < curve[argmin].held_out_rms_m) {
      argmin = static_cast<int>(k);
    }
  }
  EXPECT_EQ(min.best_num_kept, first + argmin);
  EXPECT_EQ(min.minimum_num_kept, first + argmin);
  const double mse_min = std::pow(curve[argmin].held_out_rms_m, 2);
  for (size_t k = 0; k < curve.size(); ++k) {
    const ModelSelectionPoint& pt = curve[k];
    // The excess is MSE_k - MSE_min; paired, its SE is 0 at the minimum.
    EXPECT_NEAR(pt.excess_m2, pt.held_out_rms_m * pt.held_out_rms_m - mse_min,
                1e-9 * mse_min);
    EXPECT_EQ(pt.within_one_se, pt.excess_m2 <= pt.excess_se_m2);
    EXPECT_GT(pt.held_out_se_m, 0.0);
    EXPECT_LT(pt.held_out_se_m, pt.held_out_rms_m);
    // Every rule sees the same curve.
    for (const auto& [rule, s] : by_rule) {
      EXPECT_EQ(s.curve[k].held_out_rms_m, pt.held_out_rms_m);
    }
  }
  EXPECT_EQ(curve[argmin].excess_se_m2, 0.0);
  EXPECT_TRUE(curve[argmin].within_one_se);
  const int most =
      by_rule[SelectionRule::kMostWithinOneSe].best_num_kept - first;
  const int fewest =
      by_rule[SelectionRule::kFewestWithinOneSe].best_num_kept - first;
  EXPECT_GE(most, argmin);
  EXPECT_LE(fewest, argmin);
  EXPECT_TRUE(curve[most].within_one_se);
  EXPECT_TRUE(curve[fewest].within_one_se);
  for (size_t k = most + 1; k < curve.size(); ++k) {
    EXPECT_FALSE(curve[k].within_one_se) << k;
  }
  for (int k = 0; k < fewest; ++k) EXPECT_FALSE(curve[k].within_one_se) << k;
  // Every one of the paper's 27 parameters carries a real error: the
  // noisy minimum drops some (25 here), the most within one SE keeps all.
  EXPECT_LT(min.best_num_kept, 27);
  EXPECT_EQ(by_rule[SelectionRule::kMostWithinOneSe].best_num_kept, 27);
  // The F test: the last point is the fit of all (p = 1); the choice is the
  // first count at or above the 1 % level.
  const int f = by_rule[SelectionRule::kFTest].best_num_kept - first;
  EXPECT_EQ(curve.back().f_test_p_value, 1.0);
  EXPECT_GE(curve[f].f_test_p_value, 0.01);
  for (int k = 0; k < f; ++k) EXPECT_LT(curve[k].f_test_p_value, 0.01) << k;
  EXPECT_LT(f + 1, static_cast<int>(curve.size()));
}

// A pose measurement with sigma_m and no sigma_rad (FIGAROH's file with a
// sigma_m column): the message read "measurement 0 has no standard
// deviation for some of its rows while other measurements state one".
TEST(WeightedIdentificationTest, PoseWithOnlyItsPositionSigmaSaysWhichHalf) {
  RobotModel m = Ur10e().model;
  for (int i = 0; i < 6; ++i) m.SetFree(i, true);  // the base
  std::vector<Measurement> data(3);
  for (int i = 0; i < 3; ++i) {
    data[i].type = MeasurementType::kPose;
    data[i].joints = Eigen::VectorXd::Constant(6, 0.3 * i);
  }
  data[0].sigma_m.setConstant(1e-3);
  IdentificationSummary s;
  Identify(m, data, m.nominal, {}, &s);
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);
  EXPECT_NE(s.message.find("measurement 0 (a pose) states the position's "
                           "standard deviation but not the rotation's "
                           "(sigma_rad)"),
            std::string::npos)
      << s.message;
  data[0].sigma_m.setZero();
  data[0].sigma_rad = 1e-3;
  Identify(m, data, m.nominal, {}, &s);
  EXPECT_NE(s.message.find("states the rotation's standard deviation but "
                           "not the position's"),
            std::string::npos)
      << s.message;
}

TEST(EstimateWarningsTest, EachThresholdIsCrossed) {
  const RobotModel m = Puma560PaperModel();
  const std::vector<int> free = m.FreeParameterIndices();
  const int p = static_cast<int>(free.size());
  IdentificationSummary s;
  s.names = m.FreeParameterNames();
  s.estimates = ExtractFree(m, m.nominal);
  s.standard_deviations = Eigen::VectorXd::Constant(p, 1e-5);
  s.correlation = Eigen::MatrixXd::Identity(p, p);
  EXPECT_TRUE(EstimateWarnings(m, s, {}).empty());
  // One length and one angle of the links, just above and just below.
  int length = -1, angle = -1;
  for (int k = 0; k < p; ++k) {
    const int block = m.BlockOf(free[k]);
    if (block == 0 || m.is_marker_block(block)) continue;
    const std::string unit = m.ParameterUnit(free[k]);
    if (unit == "m" && length < 0) length = k;
    if (unit == "rad" && angle < 0) angle = k;
  }
  ASSERT_GE(length, 0);
  ASSERT_GE(angle, 0);
  s.standard_deviations[length] = 0.0099;
  s.standard_deviations[angle] = 0.099;
  s.correlation(length, angle) = s.correlation(angle, length) = 0.989;
  s.estimates[length] += 4.9 * 0.0099;
  EXPECT_TRUE(EstimateWarnings(m, s, {}).empty());
  s.standard_deviations[length] = 0.0101;
  s.standard_deviations[angle] = 0.101;
  s.correlation(length, angle) = s.correlation(angle, length) = -0.991;
  s.estimates[angle] += 5.1 * 0.101;
  const std::vector<std::string> w = EstimateWarnings(m, s, {});
  ASSERT_EQ(w.size(), 4u);
  // Std lines in free-parameter order.
  const int first = std::min(length, angle);
  const std::string length_line = s.names[length] + " has std 0.0101 m > 0.01";
  const std::string angle_line = s.names[angle] + " has std 0.101 rad > 0.1";
  EXPECT_EQ(w[0].find(first == length ? length_line : angle_line), 0u) << w[0];
  EXPECT_EQ(w[1].find(first == length ? angle_line : length_line), 0u) << w[1];
  EXPECT_NE(w[2].find("are correlated -0.991"), std::string::npos) << w[2];
  EXPECT_NE(w[2].find(s.names[length]), std::string::npos);
  EXPECT_NE(w[2].find(s.names[angle]), std::string::npos);
  EXPECT_EQ(w[3].find("1 link parameter moved from nominal by more than 5 mm "
                      "/ 10 mrad and 5 std (is the nominal model the right "
                      "one?): " +
                      s.names[angle] + " 0.515 rad (515 mrad, 5.1 std)"),
            0u)
      << w[3];
}

// Parameters of one weak direction are one line, not one per pair: a group
// of parameters linked by pairs beyond the threshold is named once (on
// FIGAROH's UR10e with every identifiable parameter, B.x, elbow_joint.x,
// wrist_1_joint.x, wrist_2_joint.z, tool.y and tool.z gave eleven lines).
TEST(EstimateWarningsTest, CorrelatedGroupIsOneLine) {
  const RobotModel m = Puma560PaperModel();
  const int p = m.num_free();
  IdentificationSummary s;
  s.names = m.FreeParameterNames();
  s.estimates = ExtractFree(m, m.nominal);
  s.standard_deviations = Eigen::VectorXd::Constant(p, 1e-5);
  s.correlation = Eigen::MatrixXd::Identity(p, p);
  auto set = [&](int a, int b, double c) {
    s.correlation(a, b) = s.correlation(b, a) = c;
  };
  // 2-5 and 5-9 beyond (a chain), 2-9 not; 11-12 a pair of its own.
  set(2, 5, 0.995);
  set(5, 9, -0.9991);
  set(2, 9, 0.98);
  set(11, 12, 0.993);
  const std::vector<std::string> w = EstimateWarnings(m, s, {});
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0], s.names[2] + ", " + s.names[5] + " and " + s.names[9] +
                      " are correlated beyond 0.99 in 2 of their pairs (up "
                      "to -0.9991): the measurements separate only "
                      "combinations of them");
  EXPECT_EQ(w[1], s.names[11] + " and " + s.names[12] +
                      " are correlated 0.993: the measurements separate only "
                      "their combination");
}

TEST(PostureGroupTest, RepeatedNewAndOutOfRange) {
  const RobotModel m = Puma560PaperModel();
  Eigen::MatrixXd train(3, 6);
  train << 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,  //
      0.5, 0.5, 0.5, 0.5, 0.5, 0.5,       //
      1.0, -0.5, 1.0, -0.5, 1.0, -0.5;
  Eigen::MatrixXd test(5, 6);
  test << 0.5, 0.5, 0.5, 0.5, 0.5, 0.491,  // within 0.01 rad: repeated
      0.5, 0.5, 0.5, 0.5, 0.5, 0.489,      // just beyond: new
      0.2, 0.1, 0.3, 0.2, 0.4, 0.1,        // inside the ranges: new
      1.1, 0.0, 0.0, 0.0, 0.0, 0.0,        // joint 1 beyond 1.0: out
      0.0, 0.6, 0.0, 0.0, 0.0, 0.0;        // joint 2 beyond 0.5: out
  const std::vector<PostureGroup> g =
      ClassifyPostures(m, MeasurementPlan(train), MeasurementPlan(test));
  ASSERT_EQ(g.size(), 5u);
  EXPECT_EQ(g[0], PostureGroup::kRepeated);
  EXPECT_EQ(g[1], PostureGroup::kNew);
  EXPECT_EQ(g[2], PostureGroup::kNew);
  EXPECT_EQ(g[3], PostureGroup::kOutOfRange);
  EXPECT_EQ(g[4], PostureGroup::kOutOfRange);
  EXPECT_STREQ(PostureGroupName(PostureGroup::kOutOfRange), "out_of_range");
  // A distance takes the worse group of its two poses.
  Measurement d;
  d.type = MeasurementType::kDistance;
  d.joints = train.row(1).transpose();
  d.joints2 = test.row(2).transpose();
  Measurement far = d;
  far.joints2 = test.row(3).transpose();
  const std::vector<PostureGroup> gd =
      ClassifyPostures(m, MeasurementPlan(train), {d, far});
  EXPECT_EQ(gd[0], PostureGroup::kNew);
  EXPECT_EQ(gd[1], PostureGroup::kOutOfRange);
}

}  // namespace
}  // namespace activecal
