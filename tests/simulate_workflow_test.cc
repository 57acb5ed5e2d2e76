// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// SimulationPlan (core/simulation.h) and SimulateAtPoses
// (calibration/simulate_workflow.h): the plans, the measurements at the
// truth, the files' texts and the refusals.

#include "activecal/calibration/simulate_workflow.h"

#include <gtest/gtest.h>

#include <fstream>

#include "activecal/core/puma560.h"

namespace activecal {
namespace {

Eigen::MatrixXd ThreePoses() {
  Eigen::MatrixXd joints(3, 6);
  joints << 0.1, -0.5, 0.3, 0.2, 0.4, 0.0,  //
      0.7, -0.2, 0.9, -0.4, 0.1, 1.0,       //
      -0.6, -1.0, 0.5, 0.8, -0.3, 2.0;
  return joints;
}

std::string WritePoses(const std::string& name, const Eigen::MatrixXd& q) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream out(path);
  out.precision(17);
  out << "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad\n";
  for (int i = 0; i < q.rows(); ++i) {
    for (int j = 0; j < q.cols(); ++j) out << (j ? "," : "") << q(i, j);
    out << "\n";
  }
  return path;
}

RobotDescription Puma(bool with_truth) {
  RobotDescription robot;
  robot.model = Puma560PaperModel();
  if (with_truth) robot.true_parameters = Puma560TrueParameters();
  return robot;
}

TEST(SimulationPlanTest, PointsAndDistances) {
  const Eigen::MatrixXd joints = ThreePoses();
  std::vector<Measurement> plan;
  int identical = 7;
  ASSERT_TRUE(
      SimulationPlan(joints, MeasurementType::kPose, &plan, &identical));
  ASSERT_EQ(plan.size(), 3u);
  EXPECT_EQ(plan[2].type, MeasurementType::kPose);
  EXPECT_EQ(plan[2].joints, joints.row(2).transpose());
  ASSERT_TRUE(
      SimulationPlan(joints, MeasurementType::kDistance, &plan, &identical));
  ASSERT_EQ(plan.size(), 2u);
  EXPECT_EQ(plan[1].joints, joints.row(1).transpose());
  EXPECT_EQ(plan[1].joints2, joints.row(2).transpose());
  Eigen::MatrixXd same = joints;
  same.row(2) = same.row(1);
  EXPECT_FALSE(
      SimulationPlan(same, MeasurementType::kDistance, &plan, &identical));
  EXPECT_EQ(identical, 1);
  EXPECT_TRUE(plan.empty());
  EXPECT_FALSE(SimulationPlan(joints.topRows(1), MeasurementType::kDistance,
                              &plan, &identical));
  EXPECT_EQ(identical, -1);
}

TEST(SimulateWorkflowTest, NoiselessMeasurementsAreThePredictions) {
  SimulateOptions options;
  options.poses_csv = WritePoses("sim_poses.csv", ThreePoses());
  options.noise = {0.0, 0.0};
  options.out = "m.csv";
  options.true_model = true;
  options.true_model_out = "t.yaml";
  SimulateSummary s;
  const RobotDescription robot = Puma(true);
  ASSERT_TRUE(SimulateAtPoses(robot, options, &s)) << s.message;
  ASSERT_EQ(s.measurements.size(), 3u);
  for (const Measurement& m : s.measurements) {
    const Measurement p =
        PredictMeasurement(robot.model, robot.true_parameters, m);
    EXPECT_LT((m.position - p.position).norm(), 1e-12);
  }
  EXPECT_EQ(s.truth, robot.true_parameters);
  EXPECT_TRUE(s.report.empty());
  EXPECT_FALSE(s.measurements_csv.empty());
  EXPECT_NE(s.true_model_text.find("The robot activecal_simulate measured"),
            std::string::npos);
  EXPECT_EQ(s.written_report, "wrote the true model (27 free parameters) to " +
                                  std::string("t.yaml\n"));
  EXPECT_EQ(s.result_line,
            "activecal_simulate: wrote 3 position measurements "
            "of '" +
                robot.model.name + "' to m.csv");
}

TEST(SimulateWorkflowTest, PerturbedNominalValues) {
  SimulateOptions options;
  options.poses_csv = WritePoses("sim_poses_p.csv", ThreePoses());
  options.perturb_m = 1e-3;
  options.type = MeasurementType::kDistance;
  SimulateSummary s;
  const RobotDescription robot = Puma(false);
  ASSERT_TRUE(SimulateAtPoses(robot, options, &s)) << s.message;
  EXPECT_EQ(s.measurements.size(), 2u);
  EXPECT_GT((s.truth - robot.model.nominal).norm(), 0);
}

TEST(SimulateWorkflowTest, Refusals) {
  SimulateOptions options;
  options.poses_csv = WritePoses("sim_poses_r.csv", ThreePoses());
  options.robot_path = "r.urdf";
  SimulateSummary s;
  EXPECT_FALSE(SimulateAtPoses(Puma(false), options, &s));
  EXPECT_EQ(s.message.rfind("--robot 'r.urdf' has no true values", 0), 0u);
  Eigen::MatrixXd same = ThreePoses();
  same.row(2) = same.row(1);
  options.poses_csv = WritePoses("sim_poses_same.csv", same);
  options.type = MeasurementType::kDistance;
  EXPECT_FALSE(SimulateAtPoses(Puma(true), options, &s));
  EXPECT_EQ(s.message, "--type=distance: poses 2 and 3 of " +
                           options.poses_csv +
                           " (data rows) are identical: a distance between "
                           "them measures nothing; remove one");
  options.poses_csv = ::testing::TempDir() + "/no_such.csv";
  EXPECT_FALSE(SimulateAtPoses(Puma(true), options, &s));
  EXPECT_EQ(s.message.rfind("--poses_csv: ", 0), 0u) << s.message;
}

}  // namespace
}  // namespace activecal
