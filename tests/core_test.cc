// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/simulation.h"
#include "test_util.h"

namespace activecal {
namespace {

using Eigen::AngleAxisd;
using Eigen::Vector3d;

// A one-link model: identity base, one link of the given convention.
RobotModel OneLink(LinkConvention convention, JointType type) {
  RobotModel m;
  m.name = "one";
  m.base.convention = LinkConvention::kStandardDH;
  m.base.joint_type = JointType::kFixed;
  Link l;
  l.convention = convention;
  l.joint_type = type;
  l.joint_min = -10;
  l.joint_max = 10;
  m.links.push_back(l);
  m.nominal = Eigen::VectorXd::Zero(m.num_parameters());
  m.nominal[6 + kGain] = 1.0;
  m.nominal[kGain] = 1.0;
  return m;
}

TEST(KinematicsTest, StandardDhLinkMatchesHandComputation) {
  RobotModel m = OneLink(LinkConvention::kStandardDH, JointType::kRevolute);
  Eigen::VectorXd p = m.nominal;
  p[6 + kAlpha] = M_PI / 2;
  p[6 + kA] = 1.0;
  p[6 + kD] = 0.5;
  p[12 + 2] = 0.2;  // tool z
  for (double th : {0.0, 0.3, -1.2, 2.9}) {
    const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, th);
    const Vector3d expected(std::cos(th) + 0.2 * std::sin(th),
                            std::sin(th) - 0.2 * std::cos(th), 0.5);
    EXPECT_TRUE(MeasuredPoint(m, p, q).isApprox(expected, 1e-14))
        << "theta " << th;
  }
}

TEST(KinematicsTest, HayatiLinkMatchesHandComputation) {
  RobotModel m = OneLink(LinkConvention::kHayati, JointType::kRevolute);
  Eigen::VectorXd p = m.nominal;
  const double a = 0.7, al = 0.3, be = -0.4, ga = 0.1;
  p[6 + kGamma] = ga;
  p[6 + kAlpha] = al;
  p[6 + kA] = a;
  p[6 + kBeta] = be;
  p[12 + 2] = 1.0;  // tool z
  const double q = 0.8, th = q + ga;
  // Ry(beta) (0,0,1) = (sb, 0, cb); Rx(alpha) of that; Rz(theta); + Tx(a).
  const Vector3d y(std::sin(be), 0, std::cos(be));
  const Vector3d x(y[0], std::cos(al) * y[1] - std::sin(al) * y[2],
                   std::sin(al) * y[1] + std::cos(al) * y[2]);
  const Vector3d expected(
      std::cos(th) * x[0] - std::sin(th) * x[1] + a * std::cos(th),
      std::sin(th) * x[0] + std::cos(th) * x[1] + a * std::sin(th), x[2]);
  EXPECT_TRUE(MeasuredPoint(m, p, Eigen::VectorXd::Constant(1, q))
                  .isApprox(expected, 1e-14));
}

TEST(KinematicsTest, ModifiedDhPrismaticLinkWithGain) {
  RobotModel m = OneLink(LinkConvention::kModifiedDH, JointType::kPrismatic);
  Eigen::VectorXd p = m.nominal;
  const double a = 0.2, al = 0.6, th = 0.4, d0 = 0.1, gain = 1.1, q = 0.3;
  p[6 + kGamma] = th;
  p[6 + kAlpha] = al;
  p[6 + kA] = a;
  p[6 + kD] = d0;
  p[6 + kGain] = gain;
  p[12 + 0] = 1.0;  // tool x
  const double d = d0 + gain * q;
  const Vector3d expected(a + std::cos(th),
                          std::cos(al) * std::sin(th) - std::sin(al) * d,
                          std::sin(al) * std::sin(th) + std::cos(al) * d);
  EXPECT_TRUE(MeasuredPoint(m, p, Eigen::VectorXd::Constant(1, q))
                  .isApprox(expected, 1e-14));
}

// The PUMA chain composed independently from Eigen's elementary transforms.
Vector3d PumaByElementaryTransforms(const Eigen::VectorXd& p,
                                    const Eigen::VectorXd& q) {
  auto Rz = [](double a) {
    return Eigen::Affine3d(AngleAxisd(a, Vector3d::UnitZ()));
  };
  auto Rx = [](double a) {
    return Eigen::Affine3d(AngleAxisd(a, Vector3d::UnitX()));
  };
  auto Ry = [](double a) {
    return Eigen::Affine3d(AngleAxisd(a, Vector3d::UnitY()));
  };
  auto T = [](double x, double y, double z) {
    return Eigen::Affine3d(Eigen::Translation3d(x, y, z));
  };
  auto at = [&](int block, int k) { return p[6 * block + k]; };
  Eigen::Affine3d X = Rz(at(0, kGamma)) * T(at(0, kA), 0, 0) *
                      Rx(at(0, kAlpha)) * Ry(at(0, kBeta));
  for (int i = 1; i <= 6; ++i) {
    const double th = q[i - 1] + at(i, kGamma);
    if (i == 2) {
      X = X * Rz(th) * T(at(i, kA), 0, 0) * Rx(at(i, kAlpha)) *
          Ry(at(i, kBeta));
    } else {
      X = X * Rz(th) * T(0, 0, at(i, kD)) * T(at(i, kA), 0, 0) *
          Rx(at(i, kAlpha));
    }
  }
  return X.translation();
}

TEST(KinematicsTest, PumaMatchesElementaryTransforms) {
  const RobotModel m = Puma560PaperModel();
  Random random(7);
  for (const Eigen::VectorXd& p : {m.nominal, Puma560TrueParameters()}) {
    EXPECT_TRUE(
        MeasuredPoint(m, p, Eigen::VectorXd::Zero(6))
            .isApprox(PumaByElementaryTransforms(p, Eigen::VectorXd::Zero(6)),
                      1e-13));
    for (int k = 0; k < 20; ++k) {
      const Eigen::VectorXd q = testing::RandomJoints(m, &random);
      EXPECT_TRUE(MeasuredPoint(m, p, q).isApprox(
          PumaByElementaryTransforms(p, q), 1e-13));
    }
  }
}

TEST(KinematicsTest, PumaZeroConfigurationTrueValues) {
  // With the true values and q = 0, worked out by hand: the arm lies in the
  // base's rotated frame; the base puts it 20 m from the device along y
  // (gamma = pi/2), tilted by alpha = beta = pi/100.
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd p = Puma560TrueParameters();
  const Vector3d point = MeasuredPoint(m, p, Eigen::VectorXd::Zero(6));
  // Translation of the base alone is (0, 20, 0); the arm adds < 1.5 m.
  EXPECT_NEAR(point[0], 0.0, 1.5);
  EXPECT_NEAR(point[1], 20.0, 1.5);
  EXPECT_TRUE(point.isApprox(
      PumaByElementaryTransforms(p, Eigen::VectorXd::Zero(6)), 1e-14));
}

TEST(KinematicsTest, SingleJointRotationRotatesPointAboutAxis) {
  // Turning joint 1 alone rotates the measured point about joint 1's axis:
  // its distance to the axis stays the same.
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd p = Puma560TrueParameters();
  // Frame 0 of joint 1 is the base frame: its z axis is the joint axis.
  Eigen::Matrix3d Rb;
  Vector3d tb;
  LinkTransform<double>(m.base, p.data(), 0.0, &Rb, &tb);
  const Vector3d axis = Rb.col(2);
  auto dist = [&](const Vector3d& x) {
    const Vector3d r = x - tb;
    return (r - r.dot(axis) * axis).norm();
  };
  const Vector3d x0 = MeasuredPoint(m, p, Eigen::VectorXd::Zero(6));
  for (double q1 : {0.5, -1.0, 1.2}) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
    q[0] = q1;
    const Vector3d x = MeasuredPoint(m, p, q);
    EXPECT_NEAR(dist(x), dist(x0), 1e-12);
    EXPECT_NEAR((x - tb).dot(axis), (x0 - tb).dot(axis), 1e-12);
    // And by the angle q1.
    const Vector3d a = (x0 - tb) - (x0 - tb).dot(axis) * axis;
    const Vector3d b = (x - tb) - (x - tb).dot(axis) * axis;
    EXPECT_NEAR(std::atan2(a.cross(b).dot(axis), a.dot(b)), q1, 1e-12);
  }
}

TEST(RobotModelTest, PumaHas27FreeParametersInPaperOrder) {
  const RobotModel m = Puma560PaperModel();
  std::string error;
  ASSERT_TRUE(m.Validate(&error)) << error;
  const std::vector<std::string> names = m.FreeParameterNames();
  ASSERT_EQ(names.size(), 27u);
  EXPECT_EQ(names[0], "B.gamma");
  EXPECT_EQ(names[3], "B.beta");
  EXPECT_EQ(names[4], "L1.gamma");
  EXPECT_EQ(names[11], "L2.beta");
  EXPECT_EQ(names[24], "L6.gamma");
  EXPECT_EQ(names[25], "L6.a");
  EXPECT_EQ(names[26], "L6.d");
}

TEST(RobotModelTest, RejectsBadModelsWithMessages) {
  std::string error;
  RobotModel m = Puma560PaperModel();
  m.nominal[3] = std::nan("");
  EXPECT_FALSE(m.Validate(&error));
  EXPECT_NE(error.find("B.d"), std::string::npos) << error;

  m = Puma560PaperModel();
  m.links[0].free[kBeta] = true;
  EXPECT_FALSE(m.Validate(&error));
  EXPECT_NE(error.find("Hayati"), std::string::npos) << error;

  m = Puma560PaperModel();
  m.nominal.conservativeResize(10);
  EXPECT_FALSE(m.Validate(&error));
  EXPECT_NE(error.find("expected 48"), std::string::npos) << error;
}

TEST(RobotModelTest, ChecksJointValues) {
  const RobotModel m = Puma560PaperModel();
  std::string error;
  EXPECT_TRUE(m.CheckJointValues(Eigen::VectorXd::Zero(6), &error));
  EXPECT_FALSE(m.CheckJointValues(Eigen::VectorXd::Zero(5), &error));
  EXPECT_NE(error.find("expected 6 joint values, got 5"), std::string::npos);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  q[2] = std::nan("");
  EXPECT_FALSE(m.CheckJointValues(q, &error));
  EXPECT_NE(error.find("joint 3"), std::string::npos) << error;
  q[2] = 0;
  q[3] = 2.0;  // > 100 degrees
  EXPECT_FALSE(m.CheckJointValues(q, &error));
  EXPECT_NE(error.find("outside its range"), std::string::npos) << error;
}

TEST(LatticeTest, PaperIndexScheme) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  ASSERT_TRUE(JointLattice::Create(m, 5, &lattice, &error)) << error;
  EXPECT_EQ(lattice.size(), 15625);
  EXPECT_EQ(lattice.Index({0, 3, 0, 4, 1, 2}), 1982);
  EXPECT_EQ(lattice.Levels(1982), (std::vector<int>{0, 3, 0, 4, 1, 2}));
  for (int64_t i : {0, 1, 777, 15624}) {
    EXPECT_EQ(lattice.Index(lattice.Levels(i)), i);
  }
  const Eigen::VectorXd q = lattice.JointValues(1982);
  EXPECT_DOUBLE_EQ(q[0], -250 * M_PI / 180);
  EXPECT_NEAR(q[1], (-110 + 3 * 70) * M_PI / 180, 1e-15);
  EXPECT_DOUBLE_EQ(q[3], 100 * M_PI / 180);
  EXPECT_NEAR(q[5], (-176 + 2 * 133) * M_PI / 180, 1e-15);
  EXPECT_TRUE(m.CheckJointValues(lattice.JointValues(15624), &error));
}

TEST(LatticeTest, RejectsBadLevels) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  EXPECT_FALSE(JointLattice::Create(m, 1, &lattice, &error));
  EXPECT_NE(error.find("at least 2 levels"), std::string::npos) << error;
  EXPECT_FALSE(
      JointLattice::Create(m, std::vector<int>{5, 5}, &lattice, &error));
  EXPECT_NE(error.find("expected 6"), std::string::npos) << error;
}

TEST(LatticeTest, AFullTurnRangeIsSampledOverOneTurn) {
  // Limits of +-360 deg: with both ends, 3 levels would be -360, 0 and 360
  // deg, one angle. The joint is sampled over one turn instead: -360, -240,
  // -120 deg, three different poses; the PUMA's joint 6 (532 deg, no repeat
  // at 5 levels) keeps both ends.
  RobotModel m = Puma560PaperModel();
  m.links[0].joint_min = -2 * M_PI;
  m.links[0].joint_max = 2 * M_PI;
  JointLattice lattice;
  std::string error;
  ASSERT_TRUE(JointLattice::Create(m, 3, &lattice, &error)) << error;
  EXPECT_TRUE(lattice.one_turn(0));
  EXPECT_FALSE(lattice.one_turn(5));
  EXPECT_DOUBLE_EQ(lattice.Angle(0, 0), -2 * M_PI);
  EXPECT_DOUBLE_EQ(lattice.Angle(0, 1), -2 * M_PI + 2 * M_PI / 3);
  EXPECT_DOUBLE_EQ(lattice.Angle(0, 2), -2 * M_PI + 4 * M_PI / 3);
  for (int levels : {2, 3, 4, 5, 6, 8}) {
    ASSERT_TRUE(JointLattice::Create(m, levels, &lattice, &error)) << error;
    for (int a = 0; a < levels; ++a) {
      EXPECT_GE(lattice.Angle(0, a), m.links[0].joint_min);
      EXPECT_LE(lattice.Angle(0, a), m.links[0].joint_max);
      for (int b = a + 1; b < levels; ++b) {
        EXPECT_GT(std::abs(std::remainder(
                      lattice.Angle(0, b) - lattice.Angle(0, a), 2 * M_PI)),
                  1e-6)
            << levels << " levels: " << a << ", " << b;
      }
    }
  }
  ASSERT_TRUE(JointLattice::Create(m, 5, &lattice, &error));
  EXPECT_EQ(lattice.Angle(5, 4), m.links[5].joint_max);  // both ends kept
  // A range of 350 deg keeps both ends.
  m.links[0].joint_max = -2 * M_PI + 350 * M_PI / 180;
  ASSERT_TRUE(JointLattice::Create(m, 3, &lattice, &error)) << error;
  EXPECT_FALSE(lattice.one_turn(0));
  EXPECT_EQ(lattice.Angle(0, 2), m.links[0].joint_max);
}

TEST(SimulationTest, DistanceBetweenCoincidingPointsIsRefused) {
  // Joint 6 one turn apart: different joint values, the same point.
  const RobotModel m = Puma560PaperModel();
  Measurement d;
  d.type = MeasurementType::kDistance;
  d.joints = Eigen::VectorXd::Zero(6);
  d.joints[5] = -1.0;
  d.joints2 = d.joints;
  d.joints2[5] = -1.0 + 2 * M_PI;
  std::vector<Measurement> out;
  std::string error;
  EXPECT_FALSE(SimulateMeasurements(m, Puma560TrueParameters(), {d}, {}, 1,
                                    &out, &error));
  EXPECT_NE(error.find("measurement 0: its two poses put the measured point "
                       "at the same place"),
            std::string::npos)
      << error;
}

TEST(RandomTest, ReproducibleAndDistinctSamples) {
  Random a(42), b(42);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.Uniform(), b.Uniform());
  Random c(3);
  for (int k : {5, 600, 999}) {
    std::vector<int64_t> s = c.SampleWithoutReplacement(1000, k);
    std::sort(s.begin(), s.end());
    EXPECT_EQ(std::unique(s.begin(), s.end()), s.end());
    EXPECT_GE(s.front(), 0);
    EXPECT_LT(s.back(), 1000);
  }
  // Gaussian moments over many draws.
  Random g(11);
  double sum = 0, sq = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = g.Gaussian();
    sum += x;
    sq += x * x;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sq / n, 1.0, 0.02);
}

TEST(SimulationTest, NoiseFreeMatchesKinematicsAndSeedReproduces) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  Eigen::MatrixXd joints = Eigen::MatrixXd::Zero(3, 6);
  joints(1, 0) = 0.5;
  joints(2, 4) = -1.0;
  std::vector<Measurement> clean, noisy1, noisy2;
  std::string error;
  ASSERT_TRUE(SimulateMeasurements(m, truth, MeasurementPlan(joints),
                                   {0.0, 0.0}, 1, &clean, &error));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(clean[i].position,
              MeasuredPoint(m, truth, joints.row(i).transpose()));
  }
  ASSERT_TRUE(SimulateMeasurements(m, truth, MeasurementPlan(joints),
                                   {0.01, 0.0}, 5, &noisy1, &error));
  ASSERT_TRUE(SimulateMeasurements(m, truth, MeasurementPlan(joints),
                                   {0.01, 0.0}, 5, &noisy2, &error));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(noisy1[i].position, noisy2[i].position);
    EXPECT_LT((noisy1[i].position - clean[i].position).norm(), 0.1);
  }
  joints(0, 3) = std::nan("");
  EXPECT_FALSE(SimulateMeasurements(m, truth, MeasurementPlan(joints),
                                    {0.01, 0.0}, 5, &noisy1, &error));
  EXPECT_NE(error.find("measurement 0"), std::string::npos) << error;
  EXPECT_FALSE(SimulateMeasurements(m, truth,
                                    MeasurementPlan(joints.leftCols(4)),
                                    {0.01, 0.0}, 5, &noisy1, &error));
}

}  // namespace
}  // namespace activecal
