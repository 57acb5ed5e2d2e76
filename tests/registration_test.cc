// Closed-form registration of the base frame, and an identification that
// needs no initial guess of the device's frame: 20 random frames 400 mm and
// 90 degrees away from the robot.

#include "activecal/core/registration.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/core/urdf_robot.h"
#include "activecal/residuals/identification.h"
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
  a.resize(2);
  b.resize(2);
  EXPECT_FALSE(RigidTransformBetween(a, b, &R_fit, &t_fit, &error));
  EXPECT_NE(error.find("at least 3"), std::string::npos) << error;
}

TEST(RegistrationTest, UnknownFrameConvergesFromTwentyRandomFrames) {
  RobotDescription robot;
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  std::string error;
  ASSERT_TRUE(LoadUrdfRobot(std::string(ACTIVECAL_DATA_DIR) + "/ur10.urdf",
                            chain, &robot, &error))
      << error;
  RobotModel model = robot.model;
  ApplyParameterSet(ParameterSet::kRegistration, false, &model);
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

}  // namespace
}  // namespace activecal

namespace activecal {
namespace {

TEST(ParameterSetTest, SetsFreeWhatTheyName) {
  RobotDescription robot;
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  std::string error;
  ASSERT_TRUE(LoadUrdfRobot(std::string(ACTIVECAL_DATA_DIR) + "/ur10.urdf",
                            chain, &robot, &error))
      << error;
  RobotModel m = robot.model;
  ApplyParameterSet(ParameterSet::kRegistration, false, &m);
  EXPECT_EQ(m.num_free(), 6 + 3);
  ApplyParameterSet(ParameterSet::kRegistration, true, &m);
  EXPECT_EQ(m.num_free(), 6 + 6);
  ApplyParameterSet(ParameterSet::kOffsets, false, &m);
  EXPECT_EQ(m.num_free(), 6 + 6 + 3);
  EXPECT_TRUE(m.IsFree(m.ParameterIndex("wrist_3_joint.offset")));
  EXPECT_FALSE(m.IsFree(m.ParameterIndex("wrist_3_joint.gain")));
  ApplyParameterSet(ParameterSet::kFull, false, &m);
  EXPECT_EQ(m.num_free(), 6 + 6 * 7 + 3);
  // 'file' keeps the flags; a DH model gets the DH parameters.
  const RobotModel before = m;
  ApplyParameterSet(ParameterSet::kFile, false, &m);
  EXPECT_EQ(m.FreeParameterIndices(), before.FreeParameterIndices());
  RobotModel puma = Puma560PaperModel();
  ApplyParameterSet(ParameterSet::kOffsets, false, &puma);
  // The Hayati base keeps its flags; offsets are the six gammas.
  EXPECT_EQ(puma.num_free(), 4 + 6 + 3);
  ApplyParameterSet(ParameterSet::kFull, false, &puma);
  EXPECT_TRUE(puma.IsFree(puma.ParameterIndex("L2.beta")));
  EXPECT_FALSE(puma.IsFree(puma.ParameterIndex("L3.beta")));
  EXPECT_FALSE(puma.IsFree(puma.ParameterIndex("L3.gain")));
  ParameterSet set;
  EXPECT_TRUE(ParseParameterSet("offsets", &set));
  EXPECT_EQ(set, ParameterSet::kOffsets);
  EXPECT_FALSE(ParseParameterSet("all", &set));
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

}  // namespace
}  // namespace activecal
