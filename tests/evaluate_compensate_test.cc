// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The workflows of activecal_evaluate and activecal_compensate
// (calibration/evaluate.h, calibration/compensate.h).

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "activecal/calibration/compensate.h"
#include "activecal/calibration/evaluate.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/simulation.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "test_util.h"

namespace activecal {
namespace {

RobotDescription Puma() {
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(LoadRobot(std::string(ACTIVECAL_DATA_DIR) + "/puma560.yaml",
                        RobotLoadOptions(), &robot, &error))
      << error;
  return robot;
}

// `n` configurations spread inside the joint ranges.
Eigen::MatrixXd Configurations(const RobotModel& model, int n) {
  Eigen::MatrixXd q(n, model.num_joints());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j) {
      const Link& link = model.links[j];
      const double t = (i + 1.0 + 0.3 * j) / (n + 2.0);
      q(i, j) = link.joint_min + t * (link.joint_max - link.joint_min);
    }
  }
  return q;
}

std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(CompensateTest, SameModelKeepsTheProgramAndMakesTheOutputs) {
  const RobotDescription robot = Puma();
  PoseList program;
  program.joints = Configurations(robot.model, 3);
  program.pose_indices = {7, 8, 9};
  CompensateOptions options;
  options.poses_csv =
      WriteFile("compensate_program.csv", PosesCsvText(robot.model, program));
  options.nominal_path = std::string(ACTIVECAL_DATA_DIR) + "/puma560.yaml";
  options.out = "out.csv";
  options.json_out = "out.json";
  options.program = "test";
  CompensateSummary summary;
  Compensate(robot, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  ASSERT_EQ(summary.compensation.results.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT((summary.compensation.results[i].joints -
               program.joints.row(i).transpose())
                  .norm(),
              1e-6);
  }
  EXPECT_EQ(summary.labels, program.pose_indices);
  EXPECT_TRUE(summary.has_correction);
  EXPECT_LT(summary.correction.max_position_m, 1e-6);
  ASSERT_EQ(summary.outputs.size(), 2u);
  EXPECT_EQ(summary.outputs[0].path, "out.csv");
  EXPECT_EQ(summary.outputs[1].path, "out.json");
  const nlohmann::json j = nlohmann::json::parse(summary.outputs[1].text);
  EXPECT_EQ(j["num_converged"], 3);
  EXPECT_EQ(j["targets"][2]["pose_index"], 9);
  EXPECT_NE(summary.report.find("wrote 3 compensated targets to out.csv"),
            std::string::npos);
  EXPECT_EQ(summary.result_line.rfind("test: 3 of 3 targets converged", 0), 0u);
  EXPECT_TRUE(summary.not_converged.empty());
}

TEST(CompensateTest, BadInputIsAUserFailureWithNoOutputs) {
  const RobotDescription robot = Puma();
  CompensateOptions options;
  options.out = "out.csv";
  CompensateSummary summary;
  Compensate(robot, options, &summary);  // no program
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(summary.message.rfind("give exactly one of --poses_csv", 0), 0u);
  options.poses_csv = "program.csv";
  Compensate(robot, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(summary.message.rfind("--poses_csv needs --nominal", 0), 0u);
  options.marker = "no such marker";
  Compensate(robot, options, &summary);
  EXPECT_EQ(summary.message.rfind("--marker: 'no such marker'", 0), 0u);
  EXPECT_TRUE(summary.outputs.empty());
}

TEST(CompensateTest, InMemoryProgramAndTargetsNeedNoFiles) {
  const RobotDescription robot = Puma();
  CompensateOptions options;
  options.in_memory = true;
  options.marker.clear();  // compensation.ik.marker as given
  options.nominal_model = &robot.model;
  options.joint_program = Configurations(robot.model, 2);
  CompensateSummary summary;
  Compensate(robot, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.labels, (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(summary.starts, options.joint_program);
  EXPECT_TRUE(summary.has_correction);
  EXPECT_TRUE(summary.outputs.empty());  // no out, no json_out

  // Cartesian targets: the points the program reaches, no nominal.
  options.nominal_model = nullptr;
  options.targets.points.resize(2, 3);
  for (int i = 0; i < 2; ++i) {
    options.targets.points.row(i) =
        MeasuredPoint(robot.model, robot.model.nominal,
                      options.joint_program.row(i).transpose())
            .transpose();
  }
  options.targets.pose_indices = {5};  // the second one numbered by its row
  options.targets.start_joints = options.joint_program;
  Compensate(robot, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.labels, (std::vector<int64_t>{5, 1}));
  EXPECT_FALSE(summary.has_correction);

  // With a nominal file (the size of the correction) the in-memory targets
  // are still what is compensated (the reviewer: the joint branch ran on an
  // empty joint_program and reported success).
  options.nominal_path = std::string(ACTIVECAL_DATA_DIR) + "/puma560.yaml";
  Compensate(robot, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.labels, (std::vector<int64_t>{5, 1}));
  EXPECT_EQ(summary.compensation.results.size(), 2u);
  EXPECT_TRUE(summary.has_correction);
  options.nominal_path.clear();

  // Shapes the file readers would refuse: one line each, no solve.
  CompensateOptions bad = options;
  bad.targets.points.resize(2, 2);
  Compensate(robot, bad, &summary);
  EXPECT_EQ(summary.message,
            "targets.points: expected (n >= 1, 3) points, got (2, 2)");
  bad = options;
  bad.targets.start_joints.resize(2, 5);
  Compensate(robot, bad, &summary);
  EXPECT_EQ(summary.message,
            "targets.start_joints: expected (2, 6) or none, got (2, 5)");
  bad = options;
  bad.compensation.ik.match = IkMatch::kPose;
  Compensate(robot, bad, &summary);
  EXPECT_EQ(summary.message,
            "match=pose needs the target orientations "
            "(targets.rotation_vectors)");
  bad = options;
  bad.nominal_model = &robot.model;
  bad.joint_program.resize(3, 4);
  Compensate(robot, bad, &summary);
  EXPECT_EQ(summary.message,
            "joint_program: expected (n >= 1, 6) joint values, got (3, 4)");

  // In memory and a file: not exactly one program.
  options.poses_csv = "program.csv";
  Compensate(robot, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(summary.message.rfind("give exactly one of --poses_csv", 0), 0u);
}

TEST(CompensateTest, JointWeightsAndTheUrdfNote) {
  std::vector<double> w;
  std::string error;
  ASSERT_TRUE(ParseJointWeights("10,10,1.5", &w, &error)) << error;
  EXPECT_EQ(w, (std::vector<double>{10, 10, 1.5}));
  ASSERT_TRUE(ParseJointWeights("", &w, &error));
  EXPECT_TRUE(w.empty());
  EXPECT_FALSE(ParseJointWeights("1,x", &w, &error));
  EXPECT_EQ(error,
            "--joint_weights: 'x' is not a number (comma-separated weights, "
            "one per joint)");
  EXPECT_FALSE(ParseJointWeights("1,,2", &w, &error));
  EXPECT_EQ(error.rfind("--joint_weights: '' is not", 0), 0u);
  EXPECT_EQ(UrdfWithoutFramesNote("r.yaml", "", "tool0"), "");
  EXPECT_EQ(UrdfWithoutFramesNote("r.urdf", "f.yaml", "tool0"), "");
  const std::string note = UrdfWithoutFramesNote("r.urdf", "", "tool0");
  EXPECT_EQ(note.rfind("activecal_compensate: note: --robot=r.urdf has no "
                       "--frames: ",
                       0),
            0u);
  EXPECT_NE(note.find("the tip link 'tool0', with no offset"),
            std::string::npos);
  EXPECT_EQ(note.back(), '\n');
  CompensateOptions options;
  EXPECT_FALSE(options.HasOneProgram(&error));
  options.targets_csv = "t.csv";
  EXPECT_TRUE(options.HasOneProgram(&error));
}

std::vector<Measurement> Simulated(const RobotModel& model, int n) {
  const Eigen::MatrixXd q = Configurations(model, n);
  std::vector<Measurement> plan(n), out;
  for (int i = 0; i < n; ++i) plan[i].joints = q.row(i).transpose();
  std::string error;
  EXPECT_TRUE(SimulateMeasurements(model, model.nominal, plan,
                                   SimulationNoise(), 1, &out, &error))
      << error;
  return out;
}

TEST(EvaluateTest, ExactMeasurementsHaveNoErrorBeforeOrAfter) {
  const RobotDescription robot = Puma();
  const std::vector<Measurement> measurements = Simulated(robot.model, 12);
  EvaluateOptions options;
  options.measurements_path = "m.csv";
  options.json_out = "e.json";
  options.program = "test";
  EvaluateSummary summary;
  Evaluate(robot, measurements, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.after.num_measurements, 12);
  EXPECT_LT(summary.after.position.rms, 1e-9);
  EXPECT_EQ(summary.kind, BeforeBaseline::kRefit);  // auto, no training
  ASSERT_TRUE(summary.have_before) << summary.baseline.message;
  EXPECT_LT(summary.before.position.rms, 1e-6);
  ASSERT_EQ(summary.outputs.size(), 1u);
  const nlohmann::json j = nlohmann::json::parse(summary.outputs[0].text);
  EXPECT_EQ(j["measurements"], "m.csv");
  EXPECT_EQ(j["before"]["kind"], "refit");
  EXPECT_EQ(j["errors"].size(), 12u);
  EXPECT_NE(summary.report.find("before (--robot refitted)"),
            std::string::npos);
  EXPECT_EQ(summary.result_line.rfind("test: 12 measurements, position RMS", 0),
            0u);

  options.before = BeforeBaseline::kNone;
  Evaluate(robot, measurements, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence);
  EXPECT_FALSE(summary.have_before);
  EXPECT_TRUE(
      nlohmann::json::parse(summary.outputs[0].text)["before"].is_null());
}

TEST(EvaluateTest, BadOptionsAreUserFailures) {
  const RobotDescription robot = Puma();
  const std::vector<Measurement> measurements = Simulated(robot.model, 12);
  EvaluateOptions options;
  options.before = BeforeBaseline::kTraining;  // without training
  EvaluateSummary summary;
  Evaluate(robot, measurements, options, &summary);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(summary.message.rfind("--before=training needs --training", 0), 0u);
  options.before = BeforeBaseline::kAuto;
  options.rotation_weight = -1;
  Evaluate(robot, measurements, options, &summary);
  EXPECT_EQ(summary.message.rfind("--rotation_weight: ", 0), 0u);
  EXPECT_TRUE(summary.report.empty());
}

TEST(EvaluateTest, BeforeAfterPositionErrorsLeaveOutDistanceRows) {
  EvaluateSummary summary;
  std::vector<std::vector<double>> rows;
  std::string error;
  summary.kind = BeforeBaseline::kNone;
  EXPECT_FALSE(BeforeAfterPositionErrorsMm({}, summary, &rows, &error));
  EXPECT_EQ(error, "no 'before' to compare with (--before=none)");
  summary.kind = BeforeBaseline::kRefit;
  summary.baseline.message = "the fit failed";
  EXPECT_FALSE(BeforeAfterPositionErrorsMm({}, summary, &rows, &error));
  EXPECT_EQ(error, "no 'before' to compare with: the fit failed");

  std::vector<Measurement> measurements(3);
  measurements[1].type = MeasurementType::kDistance;
  summary.have_before = true;
  summary.after.position.count = 0;
  EXPECT_FALSE(
      BeforeAfterPositionErrorsMm(measurements, summary, &rows, &error));
  EXPECT_NE(error.find("distances only"), std::string::npos);
  summary.after.position.count = 2;
  summary.before.position_errors = {Eigen::Vector3d(0.003, 0.004, 0),
                                    Eigen::Vector3d(1, 0, 0),
                                    Eigen::Vector3d(0, 0, 0.002)};
  summary.after.position_errors = {Eigen::Vector3d(0.001, 0, 0),
                                   Eigen::Vector3d(1, 0, 0),
                                   Eigen::Vector3d(0, 0, 0)};
  ASSERT_TRUE(
      BeforeAfterPositionErrorsMm(measurements, summary, &rows, &error));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_NEAR(rows[0][0], 5.0, 1e-12);
  EXPECT_NEAR(rows[0][1], 1.0, 1e-12);
  EXPECT_NEAR(rows[1][0], 2.0, 1e-12);
  EXPECT_NEAR(rows[1][1], 0.0, 1e-12);
  // A summary of other measurements (one error short): refused, no rows.
  summary.after.position_errors.pop_back();
  EXPECT_FALSE(
      BeforeAfterPositionErrorsMm(measurements, summary, &rows, &error));
  EXPECT_EQ(error,
            "the errors before (3) and after (2) are not one per "
            "measurement (3)");
  EXPECT_TRUE(rows.empty());
}

TEST(EvaluateTest, HistogramScriptAndNoFramesNote) {
  const std::string script = PositionErrorHistogramGnuplot({{3.0, 1.5}});
  EXPECT_EQ(script.rfind("w = 0.10000000000000001\nbin(x) = ", 0), 0u)
      << script;
  EXPECT_NE(script.find("title 'after'\n"), std::string::npos);
  EXPECT_EQ(PositionErrorHistogramGnuplot({}).rfind("w = 1\n", 0), 0u);
  // A PUMA's base is DH, not a 'frame': no note.
  const RobotDescription robot = Puma();
  EXPECT_EQ(NoFramesNote(robot.model, false), "");
  RobotModel frame = robot.model;
  frame.base.convention = LinkConvention::kFrame;
  frame.nominal.head(6).setZero();
  EXPECT_EQ(NoFramesNote(frame, false).rfind("note: no --frames: ", 0), 0u);
  EXPECT_EQ(NoFramesNote(frame, true), "");
}

TEST(EvaluateTest, EnumNamesRoundTrip) {
  for (BeforeBaseline b : {BeforeBaseline::kAuto, BeforeBaseline::kTraining,
                           BeforeBaseline::kRefit, BeforeBaseline::kNone}) {
    BeforeBaseline back;
    ASSERT_TRUE(StringToBeforeBaseline(BeforeBaselineToString(b), &back));
    EXPECT_EQ(back, b);
  }
  BeforeBaseline b;
  EXPECT_FALSE(StringToBeforeBaseline("bogus", &b));
  testing::ExpectEnumParsing(StringToIso9283Registration, "file",
                             Iso9283Registration::kFile, "bogus");
}

}  // namespace
}  // namespace activecal
