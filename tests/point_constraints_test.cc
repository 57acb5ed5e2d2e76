// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Fixed points without a tracker (core/point_constraints.h): the point
// row's residual and its Jacobian, what the reduction holds with points
// only (the base frame, the scale) and with a known distance, and a fit on
// a simulated 7-axis arm against its truth.

#include "activecal/core/point_constraints.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <set>

#include "activecal/core/kinematics.h"
#include "activecal/core/point_simulation.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/io/points_file.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/residuals/measurement_residual.h"
#include "constraint_test_util.h"

namespace activecal {
namespace {

// `per_point` configurations at each of `num_points` sockets the robot at
// `truth` reaches (point_simulation.h), placements off by `placement_m` per
// axis.
std::vector<Measurement> PointRows(const RobotModel& model,
                                   const Eigen::VectorXd& truth, int num_points,
                                   int per_point, double placement_m,
                                   uint64_t seed,
                                   std::vector<Eigen::Vector3d>* points) {
  PointSimulationOptions options;
  options.num_points = num_points;
  options.per_point = per_point;
  options.placement_m = placement_m;
  std::vector<Measurement> rows;
  std::string error;
  EXPECT_TRUE(SimulatePointMeasurements(model, truth, options, seed, &rows,
                                        points, &error))
      << error;
  return rows;
}

TEST(PointConstraintsTest, ResidualJacobianMatchesCentralDifferences) {
  const RobotModel model = LoadShippedWithBall("kuka_iiwa14.urdf", "flange");
  Measurement m;
  m.type = MeasurementType::kPoint;
  m.point = "hole_0";
  m.joints = Eigen::VectorXd::LinSpaced(model.num_joints(), -0.7, 0.9);
  const std::unique_ptr<ceres::CostFunction> cost = ResidualOf(model, m);
  ASSERT_EQ(cost->parameter_block_sizes().size(),
            static_cast<size_t>(model.num_blocks() + 1));
  Eigen::VectorXd x = model.nominal;
  Eigen::Vector3d c(0.3, -0.2, 0.5);
  std::vector<double*> blocks = BlocksWith(model, &x, {c.data()});
  std::vector<double*> jac_ptrs;
  const std::vector<std::vector<double>> jac =
      JacobianStorage(*cost, &jac_ptrs);
  double r[3];
  ASSERT_TRUE(cost->Evaluate(blocks.data(), r, jac_ptrs.data()));
  // The residual: predicted point - c.
  const Eigen::Vector3d p = MeasuredPoint(model, x, m.joints);
  EXPECT_NEAR((Eigen::Map<Eigen::Vector3d>(r) - (p - c)).norm(), 0, 1e-15);
  constexpr double h = 1e-6;
  double max_error = 0.0;
  for (size_t b = 0; b < blocks.size(); ++b) {
    const int size = cost->parameter_block_sizes()[b];
    for (int j = 0; j < size; ++j) {
      const double keep = blocks[b][j];
      double rp[3], rm[3];
      blocks[b][j] = keep + h;
      ASSERT_TRUE(cost->Evaluate(blocks.data(), rp, nullptr));
      blocks[b][j] = keep - h;
      ASSERT_TRUE(cost->Evaluate(blocks.data(), rm, nullptr));
      blocks[b][j] = keep;
      for (int k = 0; k < 3; ++k) {
        const double numeric = (rp[k] - rm[k]) / (2 * h);
        max_error =
            std::max(max_error, std::abs(numeric - jac[b][k * size + j]));
      }
    }
  }
  EXPECT_LT(max_error, 1e-8);
  // The point's own block: -I.
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(jac.back()[k * 3 + j], k == j ? -1.0 : 0.0);
    }
  }
}

TEST(PointConstraintsTest, KnownDistanceResidualAndJacobian) {
  const RobotModel model = LoadShippedWithBall("ur10e.urdf", "tool0");
  Measurement m;
  m.type = MeasurementType::kPointDistance;
  m.point = "a";
  m.point2 = "b";
  m.distance = 0.05;
  const std::unique_ptr<ceres::CostFunction> cost = ResidualOf(model, m);
  Eigen::VectorXd x = model.nominal;
  Eigen::Vector3d a(0.1, 0.2, 0.3), b(0.13, 0.24, 0.3);
  const std::vector<double*> blocks =
      BlocksWith(model, &x, {a.data(), b.data()});
  std::vector<double*> jac(blocks.size(), nullptr);
  double ja[3], jb[3];
  jac[model.num_blocks()] = ja;
  jac[model.num_blocks() + 1] = jb;
  double r;
  ASSERT_TRUE(cost->Evaluate(blocks.data(), &r, jac.data()));
  EXPECT_NEAR(r, 0.05 - 0.05, 1e-15);  // |(0.03, 0.04, 0)| = 0.05
  EXPECT_NEAR(ja[0], -0.6, 1e-12);
  EXPECT_NEAR(jb[1], 0.8, 1e-12);
}

TEST(PointConstraintsTest, BadLabelsAreNamed) {
  Measurement one;
  one.type = MeasurementType::kPoint;
  one.point = "lonely";
  one.joints = Eigen::VectorXd::Zero(6);
  std::string error;
  EXPECT_FALSE(CheckPointLabels({one}, &error));
  EXPECT_NE(error.find("point 'lonely' has one row only"), std::string::npos)
      << error;
  Measurement d;
  d.type = MeasurementType::kPointDistance;
  d.point = "lonely";
  d.point2 = "missing";
  d.distance = 0.05;
  EXPECT_FALSE(CheckPointLabels({one, one, d}, &error));
  EXPECT_NE(error.find("'missing', which no point row reaches"),
            std::string::npos)
      << error;
  EXPECT_TRUE(CheckPointLabels({one, one}, &error));
}

// What theory says points alone cannot determine, on a 6- and a 7-axis
// arm: the base frame with the points (6: held, "no effect" once the
// points' coordinates are eliminated), and the scale (1 length); nothing
// else beyond what position rows at the same configurations hold. A known
// distance gives the scale back.
TEST(PointConstraintsTest, ReductionHoldsBaseAndScale) {
  struct Arm {
    const char* file;
    const char* tip;
  };
  for (const Arm& arm :
       {Arm{"ur10e.urdf", "tool0"}, Arm{"kuka_iiwa14.urdf", "flange"}}) {
    SCOPED_TRACE(arm.file);
    const RobotModel model = LoadShippedWithBall(arm.file, arm.tip);
    std::vector<Eigen::Vector3d> truth_points;
    const std::vector<Measurement> rows =
        PointRows(model, model.nominal, 3, 20, 0.0, 7, &truth_points);
    std::vector<Measurement> positions = rows;
    for (Measurement& m : positions) m.type = MeasurementType::kPosition;

    auto reduce = [&](const std::vector<Measurement>& data, FreeSet* free) {
      return HeldOfFullSet(model, data, free);
    };
    FreeSet free_pos, free_pts, free_dist;
    const std::vector<HeldParameter> held_pos = reduce(positions, &free_pos);
    const std::vector<HeldParameter> held_pts = reduce(rows, &free_pts);
    const std::set<std::string> pos = HeldNameSet(held_pos);
    // Beyond the position rows' holds: the base's 6 and one length.
    const std::string length =
        ExpectBaseAndOneLengthHeldBeyond(model, pos, held_pts);
    ASSERT_FALSE(length.empty());
    EXPECT_EQ(free_pts.size(), free_pos.size() - 7);

    // A known distance between two of the points: the scale is
    // identifiable, the length kept again.
    std::vector<Measurement> with_distance = rows;
    Measurement d;
    d.type = MeasurementType::kPointDistance;
    d.point = "hole_0";
    d.point2 = "hole_1";
    d.distance = (truth_points[0] - truth_points[1]).norm();
    with_distance.push_back(d);
    const std::set<std::string> dist =
        HeldNameSet(reduce(with_distance, &free_dist));
    EXPECT_EQ(dist.count(length), 0u) << length;
    EXPECT_EQ(free_dist.size(), free_pts.size() + 1);
  }
}

// The fit on a simulated 7-axis arm: true errors of 0.5 mm / 0.5 mrad on
// the parameters the points determine, 3 points x 25 configurations,
// placements repeatable to 0.02 mm. Converges; every identified parameter
// and point within 4 standard deviations of the truth.
TEST(PointConstraintsTest, FitOnSimulatedArmRecoversTruth) {
  const RobotModel model = LoadShippedWithBall("kuka_iiwa14.urdf", "flange");
  std::vector<Eigen::Vector3d> points;
  // The held set, from configurations of the nominal arm (structural).
  const std::vector<Measurement> plan =
      PointRows(model, model.nominal, 3, 25, 0.0, 11, &points);
  Eigen::VectorXd start = model.nominal;
  FreeSet free;
  std::vector<HeldParameter> held;
  std::string error;
  ASSERT_TRUE(ReduceParameterSet(model, ParameterSet::kFull, plan, 1.0, &start,
                                 &free, &held, &error))
      << error;
  const RobotModel fitted = WithFreeSet(model, free);
  // The truth: the held parameters at their start values (the gauge the
  // fit reports in), the others moved.
  Eigen::VectorXd truth;
  ASSERT_TRUE(
      PerturbParameters(fitted, start, 0.5e-3, 0.5e-3, 3, &truth, &error))
      << error;
  const std::vector<Measurement> rows =
      PointRows(model, truth, 3, 25, 2e-5, 12, &points);
  IdentificationSummary summary;
  Identify(fitted, rows, start, IdentificationOptions(), &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_LT(summary.rms_m, 5e-5);
  EXPECT_GT(summary.initial_rms_m, 10 * summary.rms_m);
  const Eigen::VectorXd true_free = ExtractFree(fitted, truth);
  double worst = 0.0;
  for (int i = 0; i < summary.estimates.size(); ++i) {
    worst = std::max(worst, std::abs(summary.estimates[i] - true_free[i]) /
                                summary.standard_deviations[i]);
  }
  EXPECT_LT(worst, 4.0);
  ASSERT_EQ(summary.point_labels.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(summary.point_labels[k], "hole_" + std::to_string(k));
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(std::abs(summary.point_coordinates[3 * k + a] - points[k][a]),
                4 * summary.point_standard_deviations[3 * k + a])
          << k << " " << a;
    }
  }
  // The uncalibrated start misses the points by far more.
  EXPECT_GT(summary.initial_rms_m, 1e-4);
}

// The points file: metres and millimetres, sigma, the entry's line; an
// entry between a point and itself, or given twice, is refused.
TEST(PointConstraintsTest, PointsFileReadsDistances) {
  std::vector<Measurement> d;
  std::vector<int> lines;
  std::string error;
  ASSERT_TRUE(ParsePointsFile(
      "# sockets\ndistances:\n  - {from: a, to: b, distance_m: 0.05}\n"
      "  - {from: b, to: c, distance_mm: 80, sigma_mm: 0.01}\n",
      "p.yaml", &d, &lines, &error))
      << error;
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].type, MeasurementType::kPointDistance);
  EXPECT_EQ(d[0].point, "a");
  EXPECT_EQ(d[0].point2, "b");
  EXPECT_EQ(d[0].distance, 0.05);
  EXPECT_EQ(d[0].sigma_m[0], 0.0);
  EXPECT_DOUBLE_EQ(d[1].distance, 0.08);
  EXPECT_DOUBLE_EQ(d[1].sigma_m[0], 1e-5);
  EXPECT_EQ(lines, (std::vector<int>{3, 4}));
  EXPECT_FALSE(
      ParsePointsFile("distances:\n  - {from: a, to: a, distance_m: 1}\n",
                      "p.yaml", &d, &lines, &error));
  EXPECT_NE(error.find("p.yaml:2:5: distances[0]: a distance between point "
                       "'a' and itself"),
            std::string::npos)
      << error;
  EXPECT_FALSE(
      ParsePointsFile("distances:\n  - {from: a, to: b, distance_m: 1}\n"
                      "  - {from: b, to: a, distance_m: 1}\n",
                      "p.yaml", &d, &lines, &error));
  EXPECT_NE(error.find("p.yaml:3:5: distances[1]: the distance between 'b' "
                       "and 'a' is given twice"),
            std::string::npos)
      << error;
  EXPECT_FALSE(ParsePointsFile("distances:\n  - {from: a, to: b}\n", "p.yaml",
                               &d, &lines, &error));
  EXPECT_NE(error.find("distance_m (or distance_mm) missing"),
            std::string::npos)
      << error;
}

// Evaluation refits the points: each row's error is about the mean of its
// label's predicted points, the known distance's error that of the means.
TEST(PointConstraintsTest, EvaluationRefitsThePoints) {
  const RobotModel model = LoadShippedWithBall("kuka_iiwa14.urdf", "flange");
  std::vector<Eigen::Vector3d> points;
  std::vector<Measurement> rows =
      PointRows(model, model.nominal, 2, 6, 1e-4, 5, &points);
  Measurement d;
  d.type = MeasurementType::kPointDistance;
  d.point = "hole_0";
  d.point2 = "hole_1";
  d.distance = (points[0] - points[1]).norm() + 1e-3;
  rows.push_back(d);
  EvaluationSummary s;
  ASSERT_TRUE(EvaluateModel(model, model.nominal, rows, &s)) << s.message;
  ASSERT_EQ(s.point_labels, (std::vector<std::string>{"hole_0", "hole_1"}));
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < 6; ++i)
    mean += MeasuredPoint(model, model.nominal, rows[i].joints);
  mean /= 6;
  EXPECT_LT((s.point_coordinates[0] - mean).norm(), 1e-12);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double squares = 0.0;
  double distances = 0.0;
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d e =
        MeasuredPoint(model, model.nominal, rows[i].joints) - mean;
    EXPECT_LT((s.position_errors[i] - e).norm(), 1e-12);
    sum += s.position_errors[i];
    squares += e.squaredNorm();
    distances += e.norm();
  }
  EXPECT_LT(sum.norm(), 1e-12);  // about the mean
  EXPECT_NEAR(s.point_spread[0].rms, std::sqrt(squares / 6), 1e-15);
  // The mean distance to the point's mean, as MUKCa reports it: below the
  // RMS unless every row is equally far.
  EXPECT_NEAR(s.point_spread[0].mean, distances / 6, 1e-15);
  EXPECT_LT(s.point_spread[0].mean, s.point_spread[0].rms);
  EXPECT_EQ(s.point_spread[1].count, 6);
  EXPECT_EQ(s.position.count, 12);
  // Placements off by 0.1 mm per axis: a spread of that order.
  EXPECT_GT(s.point_spread[0].rms, 3e-5);
  EXPECT_LT(s.point_spread[0].rms, 5e-4);
  ASSERT_EQ(s.distance.count, 1);
  EXPECT_NEAR(
      s.distance_errors_m[12],
      (s.point_coordinates[0] - s.point_coordinates[1]).norm() - d.distance,
      1e-15);
  EXPECT_LT(std::abs(s.distance_errors_m[12] + 1e-3), 3e-4);
}

}  // namespace
}  // namespace activecal
