// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The learned residual (estimation/learned_residual.h): the regression
// recovers a known smooth function and nothing from noise, is the same for
// a seed on any thread count, and the rule keeps it exactly when the robot
// has a smooth error the geometry does not model.

#include "activecal/estimation/learned_residual.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "activecal/core/joint_errors.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/identification.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_inertials.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/kinematics/corrected_compensation.h"
#include "test_util.h"

namespace activecal {
namespace {

// Uniform in the joint ranges, cut to [-2.5, 2.5] rad.
Eigen::VectorXd ClampedRandomJoints(const RobotModel& m, Random* random) {
  Eigen::VectorXd q(m.num_joints());
  for (int j = 0; j < m.num_joints(); ++j) {
    const double lo = std::max(m.links[j].joint_min, -2.5);
    const double hi = std::min(m.links[j].joint_max, 2.5);
    q[j] = lo + (hi - lo) * random->Uniform();
  }
  return q;
}

// A smooth error of the measured point (m, robot base frame), 0.1 mm.
Eigen::Vector3d Smooth(const Eigen::VectorXd& q) {
  return 1e-4 * Eigen::Vector3d(std::sin(q[0]) * std::cos(q[1]),
                                std::cos(q[1] + q[2]),
                                std::sin(q[2]) * std::sin(q[0] - q[3]));
}

// Position measurements of `model` at its nominal values plus
// scale * Smooth(q) (in the base frame) plus Gaussian noise.
std::vector<Measurement> Data(const RobotModel& model, int n, double scale,
                              double noise, uint64_t seed) {
  Random random(seed);
  const Eigen::Matrix3d rb = BaseRotation(model, model.nominal);
  std::vector<Measurement> out;
  for (int i = 0; i < n; ++i) {
    Measurement m;
    m.joints = ClampedRandomJoints(model, &random);
    m.position = MeasuredPoint(model, model.nominal, m.joints) +
                 rb * (scale * Smooth(m.joints));
    for (int k = 0; k < 3; ++k) m.position[k] += noise * random.Gaussian();
    out.push_back(m);
  }
  return out;
}

// RMS over new poses of correction - scale * Smooth.
double PredictionError(const RobotModel& model, const LearnedCorrection& c,
                       double scale, double* truth_rms) {
  Random random(99);
  double e = 0, t = 0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const Eigen::VectorXd q = ClampedRandomJoints(model, &random);
    e += (c.Correction(q, 0) - scale * Smooth(q)).squaredNorm();
    t += (scale * Smooth(q)).squaredNorm();
  }
  if (truth_rms) *truth_rms = std::sqrt(t / n);
  return std::sqrt(e / n);
}

// A correction fitted with `options` to the data of the model at its
// nominal values: success where the fit converged, else its message.
::testing::AssertionResult Fits(const RobotModel& model,
                                const std::vector<Measurement>& data,
                                const LearnedResidualOptions& options,
                                LearnedResidualSummary* summary) {
  FitLearnedResidual(model, model.nominal, data, options, summary);
  if (summary->termination_type == TerminationType::kConvergence) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << summary->message;
}

// Fits with mode on and num_features features: its correction in
// *correction.
::testing::AssertionResult FitsOn(const RobotModel& model,
                                  const std::vector<Measurement>& data,
                                  int num_features,
                                  LearnedCorrection* correction) {
  LearnedResidualOptions options;
  options.mode = LearnedResidualMode::kOn;
  options.num_features = num_features;
  LearnedResidualSummary summary;
  ::testing::AssertionResult fits = Fits(model, data, options, &summary);
  *correction = summary.correction;
  return fits;
}

TEST(LearnedResidual, RecoversAKnownSmoothFunction) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = Data(model, 800, 1.0, 5e-6, 3);
  LearnedResidualOptions options;
  LearnedResidualSummary summary;
  ASSERT_TRUE(Fits(model, data, options, &summary));
  EXPECT_TRUE(summary.kept) << summary.BriefReport();
  double truth = 0;
  const double error = PredictionError(model, summary.correction, 1.0, &truth);
  // On new poses the correction explains most of the function.
  EXPECT_LT(error, 0.4 * truth) << error / truth << "\n"
                                << summary.BriefReport();
  EXPECT_LT(summary.held_out_rms_hybrid_m,
            0.5 * summary.held_out_rms_parametric_m);
  EXPECT_EQ(summary.grid.size(),
            options.length_scales.size() * options.ridges.size());
  EXPECT_EQ(summary.correction.num_features(), 300);
  EXPECT_EQ(summary.num_measurements, 800);
  std::string why;
  EXPECT_TRUE(summary.correction.Validate(&model, &why)) << why;
}

TEST(LearnedResidual, ZeroFunctionGivesANearZeroCorrection) {
  const RobotModel model = Puma560PaperModel();
  const double noise = 1e-5;
  const std::vector<Measurement> data = Data(model, 400, 0.0, noise, 4);
  LearnedResidualOptions options;
  LearnedResidualSummary summary;
  ASSERT_TRUE(Fits(model, data, options, &summary));
  EXPECT_FALSE(summary.kept) << summary.BriefReport();
  // The noise is not learned: predictions well below it, and the largest
  // ridge of the grid chosen.
  const double error = PredictionError(model, summary.correction, 0.0, nullptr);
  EXPECT_LT(error, 0.5 * noise) << summary.BriefReport();
  EXPECT_EQ(summary.ridge, options.ridges.back());
  EXPECT_LT(summary.correction.weights.cwiseAbs().maxCoeff(), noise);
}

TEST(LearnedResidual, SameSeedSameResultOnOneAndTwoThreads) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = Data(model, 200, 1.0, 1e-5, 5);
  LearnedResidualOptions options;
  options.num_features = 100;
  LearnedResidualSummary one, two, other_seed;
  options.num_threads = 1;
  FitLearnedResidual(model, model.nominal, data, options, &one);
  options.num_threads = 2;
  FitLearnedResidual(model, model.nominal, data, options, &two);
  ASSERT_EQ(one.termination_type, TerminationType::kConvergence);
  ASSERT_EQ(two.termination_type, TerminationType::kConvergence);
  EXPECT_EQ(one.correction.frequencies, two.correction.frequencies);
  EXPECT_EQ(one.correction.phases, two.correction.phases);
  EXPECT_EQ(one.correction.weights, two.correction.weights);
  EXPECT_EQ(one.correction.bias, two.correction.bias);
  EXPECT_EQ(one.held_out_rms_hybrid_m, two.held_out_rms_hybrid_m);
  EXPECT_EQ(one.gain_se_m2, two.gain_se_m2);
  for (size_t k = 0; k < one.grid.size(); ++k) {
    EXPECT_EQ(one.grid[k].held_out_rms_m, two.grid[k].held_out_rms_m);
  }
  // Another seed draws other features.
  options.seed = 2;
  FitLearnedResidual(model, model.nominal, data, options, &other_seed);
  EXPECT_NE(one.correction.phases, other_seed.correction.phases);
}

TEST(LearnedResidual, OffFitsNothingAndBadOptionsAreNamed) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = Data(model, 20, 1.0, 1e-5, 6);
  LearnedResidualOptions options;
  options.mode = LearnedResidualMode::kOff;
  LearnedResidualSummary summary;
  FitLearnedResidual(model, model.nominal, data, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kConvergence);
  EXPECT_FALSE(summary.kept);
  EXPECT_TRUE(summary.correction.empty());
  options.mode = LearnedResidualMode::kAuto;
  options.num_folds = 2;
  FitLearnedResidual(model, model.nominal, data, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(summary.message,
            "learned residual: num_folds must be >= 3 (nested "
            "cross-validation), got 2");
  testing::ExpectEnumParsing(StringToLearnedResidualMode, "auto",
                             LearnedResidualMode::kAuto, "yes");
}

// The hybrid prediction moves each point by its correction in the base
// frame, and a distance is between the corrected points.
TEST(LearnedResidual, CorrectedPredictionUsesTheBaseFrame) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = Data(model, 200, 1.0, 1e-6, 8);
  LearnedCorrection c;
  ASSERT_TRUE(FitsOn(model, data, 50, &c));
  Measurement m = data[0];
  const Measurement plain = PredictMeasurement(model, model.nominal, m);
  const Measurement hybrid =
      PredictCorrectedMeasurement(model, model.nominal, c, m);
  const Eigen::Matrix3d rb = BaseRotation(model, model.nominal);
  EXPECT_LT((hybrid.position - plain.position - rb * c.Correction(m.joints, 0))
                .norm(),
            1e-15);
  m.type = MeasurementType::kDistance;
  m.joints2 = data[1].joints;
  const Measurement d = PredictCorrectedMeasurement(model, model.nominal, c, m);
  const Eigen::Vector3d a = MeasuredPoint(model, model.nominal, m.joints) +
                            rb * c.Correction(m.joints, 0);
  const Eigen::Vector3d b = MeasuredPoint(model, model.nominal, m.joints2) +
                            rb * c.Correction(m.joints2, 0);
  EXPECT_NEAR(d.distance, (a - b).norm(), 1e-15);
  EXPECT_EQ(
      PredictCorrectedMeasurement(model, model.nominal, LearnedCorrection(), m)
          .distance,
      PredictMeasurement(model, model.nominal, m).distance);
}

// The rule on simulated UR10s: one whose joints bend under gravity (an
// error the geometric fit cannot express) keeps the correction and
// predicts held-out poses better; purely geometric ones (errors the fit
// removes, and noise) do not keep it, over several seeds.
TEST(LearnedResidual, KeptExactlyWhenASmoothNonGeometricErrorIsThere) {
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(testing::LoadShippedUr("ur10.urdf", &robot, &error)) << error;
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  GravityModel gravity;
  ASSERT_TRUE(LoadUrdfInertials(std::string(ACTIVECAL_DATA_DIR) + "/ur10.urdf",
                                chain, &gravity, &error))
      << error;
  const RobotModel& m = robot.model;
  // Free: base frame, the marker's point, the offsets of joints 2-5.
  const RobotModel fitted = testing::UrdfOffsetsModel(m);
  Eigen::VectorXd truth = m.nominal;
  truth.segment(m.block_offset(m.marker_block(0)), 3) =
      Eigen::Vector3d(0.05, 0.02, 0.1);
  for (int b = 2; b <= 5; ++b) truth[m.block_offset(b) + kUrdfOffset] = 3e-4;
  JointErrorModel compliance = ComplianceTerms(m, gravity);
  compliance.values << 0, 2e-6, 4e-6, 1e-5, 1e-5, 0;
  enum Effect { kNone, kBias, kCompliance };
  struct Case {
    Effect effect;
    int poses;
    uint64_t seed;
  };
  const std::vector<Case> cases = {{kNone, 250, 0},
                                   {kNone, 250, 1},
                                   {kNone, 250, 2},
                                   {kBias, 250, 4},
                                   {kCompliance, 600, 5}};
  for (const Case& c : cases) {
    Random random(100 + c.seed);
    Eigen::MatrixXd joints(c.poses, 6);
    for (int i = 0; i < joints.rows(); ++i) {
      joints.row(i) = ClampedRandomJoints(m, &random);
    }
    std::vector<Measurement> data;
    ASSERT_TRUE(SimulateWithJointErrors(
        m, truth, m.nominal,
        c.effect == kCompliance ? compliance : JointErrorModel(),
        MeasurementPlan(joints), {2e-5, 0}, 200 + c.seed, &data, &error))
        << error;
    if (c.effect == kBias) {
      // A smooth joint-dependent error of the point (0.1 mm, base frame).
      const Eigen::Matrix3d rb = BaseRotation(m, truth);
      for (Measurement& d : data) d.position += rb * Smooth(d.joints);
    }
    IdentificationOptions fit_options;
    IdentificationSummary fit;
    Identify(fitted, data, m.nominal, fit_options, &fit);
    ASSERT_EQ(fit.termination_type, TerminationType::kConvergence)
        << fit.message;
    LearnedResidualOptions options;
    options.seed = 1 + c.seed;
    LearnedResidualSummary summary;
    FitLearnedResidual(fitted, fit.parameters, data, options, &summary);
    ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
        << summary.message;
    EXPECT_EQ(summary.kept, c.effect != kNone) << "case " << c.seed << "\n"
                                               << summary.BriefReport();
    if (c.effect != kNone) {
      EXPECT_LT(
          summary.held_out_rms_hybrid_m,
          (c.effect == kBias ? 0.8 : 0.99) * summary.held_out_rms_parametric_m)
          << summary.BriefReport();
    }
    std::printf("case %d: %s", static_cast<int>(c.seed),
                summary.BriefReport().c_str());
  }
}

// The robot file holds the correction: written and read back, the same
// predictions (to the last bit: every number in its shortest exact form);
// a bad entry is one line naming the field and its place.
TEST(LearnedResidualFile, RoundTripPredictsTheSame) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = Data(model, 150, 1.0, 1e-5, 9);
  LearnedCorrection fitted;
  ASSERT_TRUE(FitsOn(model, data, 40, &fitted));
  RobotFileOptions file;
  file.learned_correction = &fitted;
  const std::string text = RobotFileText(model, model.nominal, file);
  RobotDescription back;
  std::string error;
  ASSERT_TRUE(ParseRobotDescription(text, "cal.yaml", &back, &error)) << error;
  const LearnedCorrection& c = back.learned_correction;
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(c.num_features(), 40);
  EXPECT_EQ(c.seed, fitted.seed);
  EXPECT_EQ(c.num_training, 150);
  EXPECT_EQ(c.held_out_rms_hybrid_m, fitted.held_out_rms_hybrid_m);
  Random random(5);
  for (int i = 0; i < 50; ++i) {
    const Eigen::VectorXd q = ClampedRandomJoints(model, &random);
    EXPECT_LE(
        (c.Correction(q, 0) - fitted.Correction(q, 0)).cwiseAbs().maxCoeff(),
        1e-12);
  }
  // Written again, the same text.
  file.learned_correction = &c;
  EXPECT_EQ(RobotFileText(back.model, back.model.nominal, file), text);
  // Without a correction nothing is written.
  EXPECT_EQ(RobotFileText(model, model.nominal).find("learned_residual"),
            std::string::npos);

  // A bad number, a short row, an unknown input: one line each.
  auto fails = [&](const std::string& from, const std::string& to) {
    std::string bad = text;
    const size_t at = bad.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    bad.replace(at, from.size(), to);
    RobotDescription r;
    std::string why;
    EXPECT_FALSE(ParseRobotDescription(bad, "cal.yaml", &r, &why));
    EXPECT_EQ(why.find('\n'), std::string::npos) << why;
    return why;
  };
  const std::string bias = "bias: [";
  EXPECT_NE(fails(bias, bias + "abc, ").find("learned_residual.bias"),
            std::string::npos);
  const std::string inputs = "inputs: [periodic";
  EXPECT_NE(
      fails(inputs, "inputs: [wavy")
          .find("learned_residual.inputs[0]: expected periodic or linear, "
                "got 'wavy'"),
      std::string::npos);
  const std::string phases = "phases: [";
  const std::string why = fails(phases, phases + "0.5, ");
  EXPECT_NE(why.find("learned_residual.phases: expected a list of 40 "
                     "numbers (one per feature), got 41"),
            std::string::npos)
      << why;
  EXPECT_EQ(why.rfind("cal.yaml:", 0), 0u) << why;
}

// Evaluation and compensation with the hybrid model: EvaluateCorrectedModel
// is EvaluateModel with the corrected points (an empty correction: the same
// numbers); compensated joints put the corrected point on the target.
TEST(LearnedResidualUse, EvaluationAndCompensationApplyTheCorrection) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = Data(model, 200, 3.0, 1e-6, 21);
  LearnedCorrection c;
  ASSERT_TRUE(FitsOn(model, data, 100, &c));

  EvaluationSummary plain, empty, hybrid;
  ASSERT_TRUE(EvaluateModel(model, model.nominal, data, &plain));
  ASSERT_TRUE(EvaluateCorrectedModel(model, model.nominal, LearnedCorrection(),
                                     data, &empty));
  ASSERT_TRUE(EvaluateCorrectedModel(model, model.nominal, c, data, &hybrid));
  EXPECT_EQ(empty.position.rms, plain.position.rms);
  EXPECT_LT(hybrid.position.rms, 0.6 * plain.position.rms);
  const Eigen::Matrix3d rb = BaseRotation(model, model.nominal);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d expected =
        MeasuredPoint(model, model.nominal, data[i].joints) +
        rb * c.Correction(data[i].joints, 0) - data[i].position;
    EXPECT_LE((hybrid.position_errors[i] - expected).norm(), 1e-15);
  }

  // Targets: the corrected points of known joints; compensation from a
  // nearby start reaches them on the hybrid model.
  Random random(8);
  std::vector<IkTarget> targets;
  Eigen::MatrixXd starts(20, model.num_joints());
  for (int i = 0; i < 20; ++i) {
    const Eigen::VectorXd q = ClampedRandomJoints(model, &random) * 0.8;
    IkTarget t;
    t.point = MeasuredPoint(model, model.nominal, q) + rb * c.Correction(q, 0);
    targets.push_back(t);
    starts.row(i) = q.transpose();
    for (int j = 0; j < model.num_joints(); ++j) starts(i, j) += 0.01;
  }
  CompensationOptions compensation;
  compensation.num_threads = 2;
  CompensationSummary summary;
  CompensateTargets(model, model.nominal, targets, starts, Eigen::VectorXd(),
                    compensation, &summary);
  ASSERT_EQ(summary.num_converged, 20);
  // The parametric solution reaches the point with the geometry alone, so
  // the hybrid model misses it by the correction there.
  double missed = 0;
  for (int i = 0; i < 20; ++i) {
    const Eigen::VectorXd& q = summary.results[i].joints;
    missed = std::max(missed, (MeasuredPoint(model, model.nominal, q) +
                               rb * c.Correction(q, 0) - targets[i].point)
                                  .norm());
  }
  EXPECT_GT(missed, 1e-5);
  const CorrectionRounds rounds =
      ApplyLearnedCorrection(model, model.nominal, c, compensation, &summary);
  EXPECT_GE(rounds.rounds, 2);
  EXPECT_LE(rounds.last_change_m, compensation.ik.position_tolerance_m);
  EXPECT_EQ(summary.num_converged, 20) << summary.message;
  for (int i = 0; i < 20; ++i) {
    const Eigen::VectorXd& q = summary.results[i].joints;
    const double e = (MeasuredPoint(model, model.nominal, q) +
                      rb * c.Correction(q, 0) - targets[i].point)
                         .norm();
    EXPECT_LE(e, 1e-9) << i;
    EXPECT_NEAR(summary.results[i].position_error_m, e, 1e-15);
    EXPECT_EQ(summary.targets[i].point, targets[i].point);
  }
  EXPECT_LE(summary.max_position_error_m, 1e-9);
  EXPECT_GT(summary.max_joint_change, 0.0);
  // No correction: nothing changes.
  CompensationSummary same = summary;
  EXPECT_EQ(ApplyLearnedCorrection(model, model.nominal, LearnedCorrection(),
                                   compensation, &same)
                .rounds,
            0);
  EXPECT_EQ(same.results[3].joints, summary.results[3].joints);
}

}  // namespace
}  // namespace activecal
