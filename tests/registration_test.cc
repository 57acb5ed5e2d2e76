// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Closed-form registration of the base frame, and an identification that
// needs no initial guess of the device's frame: 20 random frames 400 mm and
// 90 degrees away from the robot.

#include "activecal/estimation/registration.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/residuals/jacobians.h"
#include "test_util.h"

namespace activecal {
namespace {

Eigen::Vector3d RandomUnit(Random* random) {
  Eigen::Vector3d v(random->Gaussian(), random->Gaussian(), random->Gaussian());
  return v.normalized();
}

TEST(RegistrationTest, RigidTransformRecoversAKnownFrame) {
  Random random(1);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(1.3, RandomUnit(&random)).toRotationMatrix();
  const Eigen::Vector3d t(0.4, -1.2, 0.7);
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 10; ++i) {
    a.emplace_back(random.Gaussian(), random.Gaussian(), random.Gaussian());
    b.push_back(R * a.back() + t);
  }
  Eigen::Matrix3d R_fit;
  Eigen::Vector3d t_fit;
  std::string error;
  ASSERT_TRUE(RigidTransformBetween(a, b, &R_fit, &t_fit, &error)) << error;
  EXPECT_LT((R_fit - R).norm(), 1e-12);
  EXPECT_LT((t_fit - t).norm(), 1e-12);
  // Points on a line cannot fix a frame; two points are too few.
  std::vector<Eigen::Vector3d> line, image;
  for (int i = 0; i < 5; ++i) {
    line.push_back(Eigen::Vector3d(1, 2, 3) * i);
    image.push_back(R * line.back() + t);
  }
  EXPECT_FALSE(RigidTransformBetween(line, image, &R_fit, &t_fit, &error));
  EXPECT_NE(error.find("lie on a line"), std::string::npos) << error;
  // Spread predictions, measured points all in one place.
  std::vector<Eigen::Vector3d> same(a.size(), Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(RigidTransformBetween(a, same, &R_fit, &t_fit, &error));
  EXPECT_NE(error.find("the measured points lie on a line"), std::string::npos)
      << error;
  a.resize(2);
  b.resize(2);
  EXPECT_FALSE(RigidTransformBetween(a, b, &R_fit, &t_fit, &error));
  EXPECT_NE(error.find("at least 3"), std::string::npos) << error;
}

TEST(RegistrationTest, UnknownFrameConvergesFromTwentyRandomFrames) {
  std::string error;
  RobotDescription robot;
  ASSERT_TRUE(testing::LoadShippedUr("ur10.urdf", &robot, &error)) << error;
  RobotModel model = robot.model;
  model = WithFreeSet(
      model, ParameterSetFreeSet(model, ParameterSet::kRegistration, false));
  ASSERT_EQ(model.num_free(), 9);
  // UR10 joint ranges are +-2 pi; plan poses in a sensible part of them.
  for (Link& l : model.links) {
    l.joint_min = std::max(l.joint_min, -2.5);
    l.joint_max = std::min(l.joint_max, 2.5);
  }
  Random random(2024);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd truth = model.nominal;
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(M_PI / 2, RandomUnit(&random)).toRotationMatrix();
    truth.head(3) = 0.4 * RandomUnit(&random);
    truth.segment(3, 3) = RotationToRpy(R);
    const int marker = model.block_offset(model.marker_block(0));
    truth.segment(marker, 3) << 0.03, -0.02, 0.12;
    std::vector<Measurement> plan(30);
    for (Measurement& m : plan)
      m.joints = testing::RandomJoints(model, &random);
    SimulationNoise noise;
    noise.position_m = 1e-4;
    std::vector<Measurement> measured;
    ASSERT_TRUE(SimulateMeasurements(model, truth, plan, noise, trial,
                                     &measured, &error))
        << error;
    // The stated guess: the marker at tool0's origin, the base unknown.
    Eigen::VectorXd initial = model.nominal;
    RegistrationSummary registration;
    ASSERT_TRUE(RegisterBaseFrame(model, measured, &initial, &registration))
        << registration.message;
    // The guess is 13 cm off at the marker: the registration is close, not
    // exact, and the fit does the rest.
    EXPECT_LT(registration.rms_m, 0.2) << "trial " << trial;
    IdentificationSummary summary;
    Identify(model, measured, initial, IdentificationOptions(), &summary);
    ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
        << "trial " << trial << ": " << summary.message;
    EXPECT_LT((summary.parameters.head(3) - truth.head(3)).norm(), 1e-3)
        << "trial " << trial;
    Eigen::Matrix3d R_fit = RpyRotation(
        summary.parameters[3], summary.parameters[4], summary.parameters[5]);
    EXPECT_LT(Eigen::AngleAxisd(R_fit.transpose() * R).angle(), 1e-3)
        << "trial " << trial;
    EXPECT_LT((summary.parameters.segment(marker, 3) - truth.segment(marker, 3))
                  .norm(),
              1e-3)
        << "trial " << trial;
    EXPECT_LT(summary.rms_m, 3e-4) << "trial " << trial;
  }
}

TEST(RegistrationTest, ADhBaseIsNotRegistered) {
  const RobotModel puma = Puma560PaperModel();
  Eigen::VectorXd p = puma.nominal;
  RegistrationSummary summary;
  EXPECT_FALSE(RegisterBaseFrame(puma, {}, &p, &summary));
  EXPECT_NE(summary.message.find("not a 6-DOF frame"), std::string::npos);
  EXPECT_EQ(p, puma.nominal);
}

TEST(ParameterSetTest, SetsFreeWhatTheyName) {
  std::string error;
  RobotDescription robot;
  ASSERT_TRUE(testing::LoadShippedUr("ur10.urdf", &robot, &error)) << error;
  RobotModel m = robot.model;
  m = WithFreeSet(m,
                  ParameterSetFreeSet(m, ParameterSet::kRegistration, false));
  EXPECT_EQ(m.num_free(), 6 + 3);
  m = WithFreeSet(m, ParameterSetFreeSet(m, ParameterSet::kRegistration, true));
  EXPECT_EQ(m.num_free(), 6 + 6);
  m = WithFreeSet(m, ParameterSetFreeSet(m, ParameterSet::kOffsets, false));
  EXPECT_EQ(m.num_free(), 6 + 6 + 3);
  EXPECT_TRUE(m.IsFree(m.ParameterIndex("wrist_3_joint.offset")));
  EXPECT_FALSE(m.IsFree(m.ParameterIndex("wrist_3_joint.gain")));
  m = WithFreeSet(m, ParameterSetFreeSet(m, ParameterSet::kFull, false));
  EXPECT_EQ(m.num_free(), 6 + 6 * 7 + 3);
  // 'file' keeps the flags; a DH model gets the DH parameters.
  const RobotModel before = m;
  m = WithFreeSet(m, ParameterSetFreeSet(m, ParameterSet::kFile, false));
  EXPECT_EQ(m.FreeParameterIndices(), before.FreeParameterIndices());
  RobotModel puma = Puma560PaperModel();
  puma = WithFreeSet(puma,
                     ParameterSetFreeSet(puma, ParameterSet::kOffsets, false));
  // The Hayati base keeps its flags; offsets are the six gammas.
  EXPECT_EQ(puma.num_free(), 4 + 6 + 3);
  puma =
      WithFreeSet(puma, ParameterSetFreeSet(puma, ParameterSet::kFull, false));
  EXPECT_TRUE(puma.IsFree(puma.ParameterIndex("L2.beta")));
  EXPECT_FALSE(puma.IsFree(puma.ParameterIndex("L3.beta")));
  EXPECT_FALSE(puma.IsFree(puma.ParameterIndex("L3.gain")));
  ParameterSet set;
  EXPECT_TRUE(StringToParameterSet("offsets", &set));
  EXPECT_EQ(set, ParameterSet::kOffsets);
  EXPECT_FALSE(StringToParameterSet("all", &set));
  // An option's parameter set: empty is the robot's default.
  error.clear();
  EXPECT_TRUE(ParseParameterSet("", true, &set, &error));
  EXPECT_EQ(set, ParameterSet::kFull);
  EXPECT_TRUE(ParseParameterSet("", false, &set, &error));
  EXPECT_EQ(set, ParameterSet::kFile);
  EXPECT_TRUE(ParseParameterSet("registration", true, &set, &error));
  EXPECT_EQ(set, ParameterSet::kRegistration);
  EXPECT_TRUE(error.empty());
  EXPECT_FALSE(ParseParameterSet("all", false, &set, &error));
  EXPECT_EQ(error,
            "parameter_set must be registration, offsets, full or file, got "
            "'all'");
}

TEST(ParameterSetTest, GenericPointMovesOnlyFreeMarkerParameters) {
  RobotModel m = testing::UrdfStyleModel();
  m.markers[1].free.fill(false);
  const Eigen::VectorXd g = GenericPoint(m, m.nominal);
  EXPECT_EQ(g, GenericPoint(m, m.nominal));  // deterministic
  for (int i = 0; i < m.num_parameters(); ++i) {
    const bool moves = m.IsFree(i) && m.BlockOf(i) == m.marker_block(0);
    if (moves) {
      EXPECT_NE(g[i], m.nominal[i]) << m.ParameterNames()[i];
      EXPECT_LT(std::abs(g[i] - m.nominal[i]), 6e-3);
    } else {
      EXPECT_EQ(g[i], m.nominal[i]) << m.ParameterNames()[i];
    }
  }
}

// testing::UrdfStyleModel() with only these base parameters free.
RobotModel BaseFreeOnly(const std::array<bool, kMaxBlockSize>& base_free) {
  RobotModel m = testing::UrdfStyleModel();
  for (Link& l : m.links) l.free.fill(false);
  m.markers[0].free.fill(false);
  m.markers[1].free.fill(false);
  m.base.free = base_free;
  return m;
}

TEST(ParameterReductionTest, DropsInPriorityOrderAndSaysWhy) {
  // Columns: a, b, 2a - b (a combination), 0 (no effect), c.
  const RobotModel m = BaseFreeOnly({true, true, true, true, true, false});
  Random random(3);
  Eigen::MatrixXd J(12, 5);
  for (int r = 0; r < 12; ++r) {
    J(r, 0) = random.Gaussian();
    J(r, 1) = random.Gaussian();
    J(r, 4) = random.Gaussian();
  }
  J.col(2) = 2 * J.col(0) - J.col(1);
  J.col(3).setZero();
  std::vector<HeldParameter> dropped;
  RobotModel reduced =
      WithFreeSet(m, ReduceToIdentifiable(m, J, 1e-7, &dropped));
  EXPECT_EQ(reduced.num_free(), 3);
  ASSERT_EQ(dropped.size(), 2u);
  EXPECT_EQ(dropped[0].name, "B.z");
  EXPECT_NE(dropped[0].reason.find("a combination of B.x, B.y"),
            std::string::npos)
      << dropped[0].reason;
  EXPECT_EQ(dropped[1].name, "B.rx");
  EXPECT_EQ(dropped[1].reason, "has no effect on these measurements");
  EXPECT_EQ(reduced.FreeParameterNames(),
            (std::vector<std::string>{"B.x", "B.y", "B.ry"}));
  // A weak but real direction stays: B.z is kept, and then B.ry, which
  // now closes the combination, is the one held.
  J.col(2) += 1e-4 * J.col(4);
  reduced = WithFreeSet(m, ReduceToIdentifiable(m, J, 1e-7, &dropped));
  EXPECT_EQ(reduced.num_free(), 3);
  EXPECT_EQ(reduced.FreeParameterNames(),
            (std::vector<std::string>{"B.x", "B.y", "B.z"}));
  ASSERT_EQ(dropped.size(), 2u);
  EXPECT_EQ(dropped[1].name, "B.ry");
  EXPECT_EQ(dropped[1].reason.rfind("a combination of B.z", 0), 0u)
      << dropped[1].reason;
}

// The parameter sets' tolerance, crossed: a column whose part outside the
// kept span is 0.9 kRedundancyTolerance of its length is held, 1.1 kept.
TEST(ParameterReductionTest, RedundancyToleranceIsCrossedExactly) {
  const RobotModel m = BaseFreeOnly({true, true, true, false, false, false});
  for (double factor : {0.9, 1.1}) {
    // Columns a, b and sqrt(1 - e^2) a + e c, a, b, c orthonormal: the
    // third is a unit column whose part outside span(a, b) is e.
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, 3);
    J(0, 0) = 1.0;
    J(1, 1) = 1.0;
    const double e = factor * kRedundancyTolerance;
    J(0, 2) = std::sqrt(1 - e * e);
    J(2, 2) = e;
    std::vector<HeldParameter> dropped;
    const int kept = WithFreeSet(m, ReduceToIdentifiable(
                                        m, J, kRedundancyTolerance, &dropped))
                         .num_free();
    if (factor < 1) {
      EXPECT_EQ(kept, 2);
      ASSERT_EQ(dropped.size(), 1u);
      EXPECT_EQ(dropped[0].name, "B.z");
      EXPECT_EQ(dropped[0].reason.rfind("a combination of B.x", 0), 0u)
          << dropped[0].reason;
    } else {
      EXPECT_EQ(kept, 3);
      EXPECT_TRUE(dropped.empty());
    }
  }
}

TEST(ParameterReductionTest, UrdfChainKeepsTheBaseFrameWhole) {
  std::string error;
  RobotDescription robot;
  ASSERT_TRUE(testing::LoadShippedUr("ur10e.urdf", &robot, &error)) << error;
  RobotModel model = robot.model;
  Random random(8);
  std::vector<Measurement> plan(40);
  for (Measurement& m : plan) {
    m.type = MeasurementType::kPosition;
    m.joints = Eigen::VectorXd(6);
    for (int j = 0; j < 6; ++j) m.joints[j] = 2.5 * (2 * random.Uniform() - 1);
  }
  Eigen::VectorXd point = model.nominal;
  std::vector<HeldParameter> dropped;
  ASSERT_TRUE(testing::ReduceModel(ParameterSet::kFull, plan, 1.0, &model,
                                   &point, &dropped, &error))
      << error;
  // Position measurements of one point on a 6R arm: base (6) and marker
  // point (3) stay; the first joint's origin and offset go to the base; the
  // last joint's offset turns the point about the last axis, which the
  // marker's own x and y do too.
  for (const char* name :
       {"B.x", "B.y", "B.z", "B.rx", "B.ry", "B.rz", "tool.x", "tool.y",
        "tool.z", "wrist_2_joint.offset"}) {
    EXPECT_TRUE(model.IsFree(model.ParameterIndex(name))) << name;
  }
  for (const char* name :
       {"shoulder_pan_joint.offset", "shoulder_pan_joint.x",
        "shoulder_pan_joint.rz", "wrist_3_joint.offset", "tool.rx"}) {
    EXPECT_FALSE(model.IsFree(model.ParameterIndex(name))) << name;
  }
  for (const HeldParameter& d : dropped) {
    if (d.name == "wrist_3_joint.offset") {
      EXPECT_NE(d.reason.find("tool.x"), std::string::npos) << d.reason;
    }
    if (d.name == "shoulder_pan_joint.offset") {
      EXPECT_NE(d.reason.find("B.rz"), std::string::npos) << d.reason;
    }
  }
  // What is left is identifiable at the point the analysis used.
  Eigen::MatrixXd J;
  ASSERT_TRUE(StackedJacobian(model, point, plan, 1.0, &J, &error)) << error;
  EXPECT_TRUE(AnalyzeIdentifiability(model, J).identifiable());
  // The marker moved off its guess by about 1 mm, nothing else did.
  const int tool = model.block_offset(model.marker_block(0));
  EXPECT_GT(point.segment(tool, 3).norm(), 1e-5);
  EXPECT_EQ(point.head(tool), robot.model.nominal.head(tool));
}

// A laser tracker's reflector on the flange axis of a UR10e, 80 mm out
// (its position given, so the fit starts on the axis and the truth is
// there): the full set was reduced at a point 1 mm off the axis, where
// wrist_2_joint.z, wrist_3_joint.rx and tool.z still look separable, and
// the fit then ended in "did not converge: Maximum number of iterations".
TEST(ParameterReductionTest, ReflectorOnTheFlangeAxisIsReducedWhereTheFitIs) {
  std::string error;
  RobotDescription robot;
  ASSERT_TRUE(testing::LoadShippedUr("ur10e.urdf", &robot, &error)) << error;
  RobotModel model = robot.model;
  const int tool = model.block_offset(model.marker_block(0));
  model.nominal.segment(tool, 3) << 0.0, 0.0, 0.08;
  Eigen::VectorXd truth = model.nominal;
  truth.head(6) << 2.1, -0.7, 0.3, 0.02, -0.03, 2.5;  // the tracker's frame
  Random random(21);
  for (int b = 1; b <= model.num_joints(); ++b) {
    for (int j = 0; j < 6; ++j) {  // origin x..rz: 0.5 mm, 0.5 mrad
      truth[model.block_offset(b) + j] += 5e-4 * random.Gaussian();
    }
  }
  std::vector<Measurement> plan(40);
  for (Measurement& m : plan) {
    m.type = MeasurementType::kPosition;
    m.joints = Eigen::VectorXd(6);
    for (int j = 0; j < 6; ++j) m.joints[j] = 2.8 * (2 * random.Uniform() - 1);
  }
  std::vector<Measurement> data;
  SimulationNoise noise;
  noise.position_m = 2e-5;
  ASSERT_TRUE(SimulateMeasurements(model, truth, plan, noise, 5, &data, &error))
      << error;
  Eigen::VectorXd start = model.nominal;
  RegistrationSummary registration;
  ASSERT_TRUE(RegisterBaseFrame(model, data, &start, &registration));
  std::vector<HeldParameter> dropped;
  ASSERT_TRUE(testing::ReduceModel(ParameterSet::kFull, data, 1.0, &model,
                                   &start, &dropped, &error))
      << error;
  // The stated reflector is where the fit starts: not moved off the axis.
  EXPECT_EQ(start.segment(tool, 3), model.nominal.segment(tool, 3));
  IdentificationSummary fit;
  Identify(model, data, start, IdentificationOptions(), &fit);
  ASSERT_EQ(fit.termination_type, TerminationType::kConvergence) << fit.message;
  EXPECT_LT(fit.rms_m, 5e-5);
}

}  // namespace
}  // namespace activecal
