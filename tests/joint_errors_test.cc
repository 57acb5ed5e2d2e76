// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Joint error terms: gravity torques, the residual's Jacobian, the URDF
// inertials, the joint fit with the geometry and the choice of terms by
// held-out error (a term kept when present, none when absent).

#include "activecal/core/joint_errors.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/random.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/term_selection.h"
#include "activecal/io/urdf_inertials.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/residuals/joint_error_jacobian.h"
#include "activecal/residuals/joint_error_residual.h"
#include "test_util.h"

namespace activecal {
namespace {

const std::string kUr10 = std::string(ACTIVECAL_DATA_DIR) + "/ur10.urdf";

struct Ur10 {
  RobotModel model;
  GravityModel gravity;
};

Ur10 LoadUr10() {
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(LoadUrdfRobot(kUr10, chain, &robot, &error)) << error;
  Ur10 out;
  out.model = robot.model;
  EXPECT_TRUE(LoadUrdfInertials(kUr10, chain, &out.gravity, &error)) << error;
  return out;
}

Eigen::VectorXd SymmetricRandomJoints(const RobotModel& m, Random* random) {
  Eigen::VectorXd q(m.num_joints());
  for (int j = 0; j < m.num_joints(); ++j)
    q[j] = -2.5 + 5.0 * random->Uniform();
  return q;
}

TEST(UrdfInertials, ReadsTheShippedMassesIntoJointFrames) {
  const Ur10 ur = LoadUr10();
  ASSERT_EQ(ur.gravity.bodies.size(), 6u);
  EXPECT_EQ(ur.gravity.bodies[1].name, "upper_arm_link");
  EXPECT_EQ(ur.gravity.bodies[1].joint, 1);
  EXPECT_DOUBLE_EQ(ur.gravity.bodies[1].mass_kg, 12.7);
  EXPECT_NEAR(ur.gravity.bodies[1].com_m.x(), -0.306, 1e-12);
  double total = 0;
  for (const BodyInertial& b : ur.gravity.bodies) total += b.mass_kg;
  EXPECT_NEAR(total, 28.435, 1e-9);
}

TEST(UrdfInertials, NamesTheLinksWithoutMass) {
  const std::string xml = testing::TestDataText("massless_arm.urdf");
  GravityModel g;
  std::string error;
  EXPECT_FALSE(ParseUrdfInertials(xml, "r.urdf", {}, &g, &error));
  EXPECT_EQ(error,
            "r.urdf: compliance needs link masses: no <inertial> with a mass "
            "> 0 on links b, c (add them from the robot's datasheet)");
}

// Gravity's work sum_b m_b g . c_b (frames from the robot's base).
double Work(const RobotModel& m, const Eigen::VectorXd& p,
            const GravityModel& g, const Eigen::VectorXd& q) {
  const std::vector<const double*> blocks = BlockPointers(m, p.data());
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity(), Ri;
  Eigen::Vector3d t = Eigen::Vector3d::Zero(), ti;
  double work = 0;
  for (int i = 0; i < m.num_joints(); ++i) {
    LinkTransform(m.links[i], blocks[i + 1], q[i], &Ri, &ti);
    t += R * ti;
    R = R * Ri;
    for (const BodyInertial& b : g.bodies) {
      if (b.joint == i) work += b.mass_kg * g.gravity.dot(R * b.com_m + t);
    }
  }
  t += R * m.tip.translation;
  R = R * m.tip.rotation;
  return work + g.payload_kg * g.gravity.dot(R * g.payload_com_m + t);
}

// The torques are the derivatives of the work with respect to each joint's
// motion (its offset), by central differences; a tilted gravity too.
TEST(GravityTorques, AreTheDerivativesOfGravitysWork) {
  Ur10 ur = LoadUr10();
  ur.gravity.payload_kg = 2.5;
  ur.gravity.payload_com_m = Eigen::Vector3d(0.01, -0.02, 0.08);
  const RobotModel& m = ur.model;
  Random random(3);
  for (int trial = 0; trial < 6; ++trial) {
    if (trial == 3) ur.gravity.gravity = Eigen::Vector3d(1.0, -2.0, -9.5);
    const Eigen::VectorXd q = SymmetricRandomJoints(m, &random);
    const Eigen::VectorXd tau = GravityTorques(m, m.nominal, ur.gravity, q);
    for (int i = 0; i < m.num_joints(); ++i) {
      const int k = m.block_offset(i + 1) + MotionOffsetEntry(m.links[i]);
      const double h = 1e-5;
      Eigen::VectorXd up = m.nominal, down = m.nominal;
      up[k] += h;
      down[k] -= h;
      const double numeric =
          (Work(m, up, ur.gravity, q) - Work(m, down, ur.gravity, q)) / (2 * h);
      EXPECT_NEAR(tau[i], numeric, 1e-7 * (1 + std::abs(numeric)))
          << "joint " << i;
    }
    // Upright, the vertical first axis carries exactly no torque.
    if (trial < 3) {
      EXPECT_EQ(tau[0], 0.0);
    } else {
      EXPECT_GT(std::abs(tau[0]), 1e-3);
    }
  }
}

TEST(JointErrorResidual, JacobianMatchesCentralDifferences) {
  const Ur10 ur = LoadUr10();
  RobotModel m = WithFreeSet(ur.model, FreeSet(ur.model));
  JointErrorModel errors = ComplianceTerms(m, ur.gravity);
  errors.Append(HarmonicTerms(m, 2));
  Random random(5);
  for (int t = 0; t < errors.size(); ++t) {
    errors.values[t] = 1e-4 * (random.Uniform() - 0.5);
  }
  Eigen::VectorXd p = m.nominal;
  for (int k = 0; k < p.size(); ++k) p[k] += 1e-3 * (random.Uniform() - 0.5);
  Measurement meas;
  meas.type = MeasurementType::kPose;
  meas.joints = SymmetricRandomJoints(m, &random);
  meas.position = Eigen::Vector3d(0.3, 0.2, 0.9);
  meas.rotation = Eigen::Vector3d(0.1, -0.4, 0.2);
  const std::vector<Eigen::VectorXd> features =
      MeasurementTermFeatures(m, m.nominal, errors, {meas});
  // Every parameter free: the geometric blocks and the terms.
  for (int i = 0; i < m.num_parameters(); ++i) m.SetFree(i, true);
  Eigen::MatrixXd J;
  std::string error;
  ASSERT_TRUE(JointErrorJacobian(m, p, errors, {meas}, features, 0.5, &J,
                                 nullptr, &error))
      << error;
  ASSERT_EQ(J.cols(), m.num_parameters() + errors.size());
  auto residual = [&](const Eigen::VectorXd& x, const JointErrorModel& e) {
    Eigen::MatrixXd unused;
    Eigen::VectorXd r;
    EXPECT_TRUE(JointErrorJacobian(m, x, e, {meas}, features, 0.5, nullptr, &r,
                                   &error));
    return r;
  };
  const double h = 1e-7;
  for (int c = 0; c < J.cols(); ++c) {
    Eigen::VectorXd up = p, down = p;
    JointErrorModel eu = errors, ed = errors;
    if (c < m.num_parameters()) {
      up[c] += h;
      down[c] -= h;
    } else {
      eu.values[c - m.num_parameters()] += h;
      ed.values[c - m.num_parameters()] -= h;
    }
    const Eigen::VectorXd numeric =
        (residual(up, eu) - residual(down, ed)) / (2 * h);
    EXPECT_LT((J.col(c) - numeric).norm(), 1e-6 * (1 + numeric.norm()))
        << "column " << c;
  }
  // The prediction with the errors is the geometric one at
  // ParametersAtPose.
  const Eigen::VectorXd at = ParametersAtPose(m, p, errors, features[0]);
  const Measurement pred = PredictMeasurement(m, at, meas);
  const Eigen::VectorXd r = residual(p, errors);
  EXPECT_LT((r.head(3) - (pred.position - meas.position)).norm(), 1e-12);
}

std::vector<Measurement> Plan(const RobotModel& m, int n, uint64_t seed) {
  Random random(seed);
  Eigen::MatrixXd joints(n, m.num_joints());
  for (int i = 0; i < n; ++i) joints.row(i) = SymmetricRandomJoints(m, &random);
  return MeasurementPlan(joints, MeasurementType::kPosition);
}

TEST(JointErrorFit, RecoversComplianceWithinThreeStd) {
  const Ur10 ur = LoadUr10();
  const RobotModel& m = ur.model;
  JointErrorModel truth = ComplianceTerms(m, ur.gravity);
  // 2e-6 rad/(N m) on the shoulder, 4e-6 on the elbow (UR10-like).
  truth.values << 0, 2e-6, 4e-6, 1e-5, 0, 0;
  std::vector<Measurement> data;
  std::string error;
  Eigen::VectorXd true_parameters = m.nominal;
  true_parameters.segment(m.block_offset(m.marker_block(0)), 3) =
      Eigen::Vector3d(0.05, 0.02, 0.1);
  ASSERT_TRUE(SimulateWithJointErrors(m, true_parameters, m.nominal, truth,
                                      Plan(m, 60, 11), {2e-5, 0}, 7, &data,
                                      &error))
      << error;
  const RobotModel fitted = testing::UrdfOffsetsModel(m);
  IdentificationOptions options;
  JointErrorModel guess = truth;
  guess.values.setZero();
  std::vector<std::string> dropped;
  {
    Eigen::MatrixXd J;
    ASSERT_TRUE(JointErrorJacobian(
        fitted, m.nominal, guess, data,
        MeasurementTermFeatures(fitted, m.nominal, guess, data), 1.0, &J,
        nullptr, &error));
    const std::vector<int> keep =
        IdentifiableTerms(fitted, guess, J, 1e-10, &dropped);
    guess = guess.Subset(keep);
    truth = truth.Subset(keep);
  }
  // The vertical shoulder_pan axis and wrist 3 (its centre of mass on its
  // axis) carry no torque.
  ASSERT_EQ(dropped.size(), 2u);
  EXPECT_EQ(dropped[0],
            "shoulder_pan_joint.compliance: has no effect on these "
            "measurements");
  EXPECT_EQ(dropped[1],
            "wrist_3_joint.compliance: has no effect on these "
            "measurements");
  options.joint_errors = guess;
  IdentificationSummary summary;
  Identify(fitted, data, m.nominal, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  ASSERT_EQ(summary.term_standard_deviations.size(), guess.size());
  for (int t = 0; t < guess.size(); ++t) {
    const double sd = summary.term_standard_deviations[t];
    EXPECT_GT(sd, 0);
    EXPECT_LT(std::abs(summary.joint_errors.values[t] - truth.values[t]),
              3 * sd)
        << summary.term_names[t];
  }
  // The elbow's compliance is seen to better than a fifth of itself.
  EXPECT_EQ(summary.term_names[1], "elbow_joint.compliance");
  EXPECT_LT(summary.term_standard_deviations[1], 0.2 * 4e-6);
  EXPECT_NEAR(summary.sigma_m, 2e-5, 0.3e-5);
}

// The rule keeps compliance when the data have it and neither family when
// they have none (and periodic errors only when present).
TEST(TermSelection, KeepsATermExactlyWhenItIsThere) {
  const Ur10 ur = LoadUr10();
  const RobotModel& m = ur.model;
  const RobotModel fitted = testing::UrdfOffsetsModel(m);
  Eigen::VectorXd truth = m.nominal;
  truth.segment(m.block_offset(m.marker_block(0)), 3) =
      Eigen::Vector3d(0.05, 0.02, 0.1);
  const std::vector<TermFamily> families = {
      {"compliance", ComplianceTerms(m, ur.gravity)},
      {"periodic", HarmonicTerms(m, 1)}};
  JointErrorModel compliance = ComplianceTerms(m, ur.gravity);
  compliance.values << 0, 2e-6, 4e-6, 1e-5, 1e-5, 0;
  JointErrorModel periodic = HarmonicTerms(m, 1);
  for (int t = 0; t < periodic.size(); ++t) {
    periodic.values[t] = (t % 2 ? 4e-5 : -3e-5);
  }
  struct Case {
    JointErrorModel effects;
    std::vector<std::string> kept;
  };
  std::vector<Case> cases = {{JointErrorModel(), {}},
                             {compliance, {"compliance"}},
                             {periodic, {"periodic"}}};
  for (size_t c = 0; c < cases.size(); ++c) {
    std::vector<Measurement> data;
    std::string error;
    ASSERT_TRUE(SimulateWithJointErrors(m, truth, m.nominal, cases[c].effects,
                                        Plan(m, 50, 20 + c), {2e-5, 0}, 30 + c,
                                        &data, &error))
        << error;
    TermSelectionOptions options;
    options.num_folds = 4;
    TermSelectionSummary summary;
    SelectTerms(fitted, m.nominal, data, families, options, &summary);
    ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
        << summary.message;
    EXPECT_EQ(summary.kept, cases[c].kept) << "case " << c << "\n"
                                           << summary.BriefReport();
    // Every candidate's held-out error is reported, the chosen one marked.
    ASSERT_GE(summary.candidates.size(), 3u);
    EXPECT_EQ(summary.candidates[0].name, "geometric");
    EXPECT_TRUE(summary.candidates[summary.chosen].chosen);
    for (const TermCandidate& cand : summary.candidates) {
      EXPECT_TRUE(cand.ok);
      EXPECT_GT(cand.held_out_rms_m, 0);
    }
  }
}

TEST(JointErrorFit, RefusesDistancesAndComplianceWithoutMasses) {
  const Ur10 ur = LoadUr10();
  const RobotModel fitted = testing::UrdfOffsetsModel(ur.model);
  IdentificationOptions options;
  options.joint_errors = ComplianceTerms(ur.model, GravityModel());
  IdentificationSummary summary;
  Identify(fitted, Plan(ur.model, 10, 1), ur.model.nominal, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(summary.message,
            "joint error terms: compliance needs the links' masses "
            "(inertials) or a payload");
  options.joint_errors = HarmonicTerms(ur.model, 1);
  std::vector<Measurement> data = Plan(ur.model, 10, 1);
  data[3].type = MeasurementType::kDistance;
  data[3].joints2 = data[4].joints;
  data[3].distance = 0.5;
  Identify(fitted, data, ur.model.nominal, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(summary.message,
            "measurement 3: a distance between two poses cannot be used with "
            "joint error terms (compliance, harmonics); use position or pose "
            "measurements");
}

}  // namespace
}  // namespace activecal
