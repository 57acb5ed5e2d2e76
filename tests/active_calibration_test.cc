// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The active calibration workflow: a simulated run's report and poses, a
// session resumed to the same result, and what it refuses.

#include "activecal/calibration/active_calibration.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <sstream>
#include <string>
#include <vector>

#include "activecal/core/puma560.h"
#include "test_util.h"

namespace activecal {
namespace {

std::string ActiveTempDir(const std::string& name) {
  std::string tmpl = ::testing::TempDir() + "/activecal_" + name + "_XXXXXX";
  EXPECT_NE(mkdtemp(tmpl.data()), nullptr);
  return tmpl;
}

ActiveCalibrationOptions SmallRun() {
  ActiveCalibrationOptions options;
  options.loop.sigma_m = 1e-4;
  options.loop.target_rms_m = 1e-4;
  options.loop.max_rounds = 3;
  options.restarts = 1;
  options.levels = 3;
  return options;
}

TEST(ActiveCalibrationTest, ASimulatedRunReportsItsRoundsAndPoses) {
  const RobotModel model = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  const Eigen::MatrixXd joints = testing::PumaLatticeJoints(3);
  ActiveCalibrationOptions options = SmallRun();
  options.compare = true;
  int progress_lines = 0;
  options.progress = [&](const std::string& line) {
    EXPECT_EQ(
        line.rfind("round " + std::to_string(progress_lines) + " done: ", 0),
        0u)
        << line;
    ++progress_lines;
  };
  ActiveCalibrationSummary summary;
  ASSERT_TRUE(RunActiveCalibration(model, truth, joints, nullptr, nullptr,
                                   options, &summary))
      << summary.message;
  const ActiveLoopSummary& loop = summary.loop;
  ASSERT_FALSE(loop.rounds.empty());
  EXPECT_EQ(progress_lines, static_cast<int>(loop.rounds.size()));
  // The loop ran its 3 rounds without meeting the target (0.1 mm): it ended
  // well (loop_ok) but did not converge, each round predicting better.
  EXPECT_TRUE(summary.loop_ok) << summary.message;
  EXPECT_EQ(loop.termination_type, TerminationType::kNoConvergence)
      << loop.message;
  EXPECT_EQ(loop.message, "max_rounds reached before the target");
  ASSERT_EQ(loop.rounds.size(), 3u);
  EXPECT_GT(loop.rounds.back().predicted_task_rms_m, 1e-4);
  EXPECT_LT(loop.rounds.back().predicted_task_rms_m,
            loop.rounds.front().predicted_task_rms_m);
  EXPECT_TRUE(summary.warnings.empty()) << summary.warnings[0];
  const nlohmann::json& j = summary.report;
  EXPECT_EQ(j["measured_by"], "simulation");
  EXPECT_EQ(j["levels"], 3);
  EXPECT_EQ(j["rounds"].size(), loop.rounds.size());
  EXPECT_EQ(j["measured_pose_indices"].get<std::vector<int64_t>>(),
            loop.measured);
  EXPECT_TRUE(j["one_shot"].contains("random"));
  EXPECT_FALSE(j.contains("tour"));
  ASSERT_EQ(summary.measured_poses.joints.rows(),
            static_cast<Eigen::Index>(loop.measured.size()));
  for (size_t k = 0; k < loop.measured.size(); ++k) {
    EXPECT_EQ(summary.measured_poses.joints.row(k),
              joints.row(loop.measured[k]));
  }
  const std::string line = summary.ResultLine(1e-4);
  EXPECT_EQ(
      line.rfind(std::string(TerminationTypeToString(loop.termination_type)) +
                     " after " + std::to_string(loop.rounds.size()) + " round",
                 0),
      0u)
      << line;
  EXPECT_NE(line.find("(target 0.1 mm)"), std::string::npos) << line;
}

TEST(ActiveCalibrationTest, ASessionResumedGivesTheSameResult) {
  const RobotModel model = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  const Eigen::MatrixXd joints = testing::PumaLatticeJoints(3);
  ActiveCalibrationOptions options = SmallRun();
  options.loop.target_rms_m = 1e-9;  // never met: the rounds run out
  options.order_shortest = true;
  ActiveCalibrationSummary whole;
  ASSERT_TRUE(RunActiveCalibration(model, truth, joints, nullptr, nullptr,
                                   options, &whole))
      << whole.message;
  EXPECT_EQ(whole.report["order"], "shortest");

  // Two rounds kept in a session, then continued to the end.
  options.session_dir = ActiveTempDir("active_calibration");
  options.loop.max_rounds = 2;
  ActiveCalibrationSummary first;
  ASSERT_TRUE(RunActiveCalibration(model, truth, joints, nullptr, nullptr,
                                   options, &first))
      << first.message;
  ASSERT_EQ(first.loop.rounds.size(), 2u);
  options.loop.max_rounds = 3;
  options.resume = true;
  ActiveCalibrationSummary resumed;
  ASSERT_TRUE(RunActiveCalibration(model, truth, joints, nullptr, nullptr,
                                   options, &resumed))
      << resumed.message;
  EXPECT_EQ(resumed.loop.measured, whole.loop.measured);
  EXPECT_EQ(resumed.report["rounds"], whole.report["rounds"]);
  EXPECT_EQ(resumed.report["tour"]["batches"], 1);  // the third round's

  // A session continues only with the options it was made with.
  options.loop.seed = 4;
  ActiveCalibrationSummary refused;
  EXPECT_FALSE(RunActiveCalibration(model, truth, joints, nullptr, nullptr,
                                    options, &refused));
  EXPECT_NE(refused.message.find("was made with seed 1, this run has 4"),
            std::string::npos)
      << refused.message;
}

// A model that cannot fit the measurements (an error it holds fixed) is
// warned about per round, through options.warning and in the summary, not
// on the terminal.
TEST(ActiveCalibrationTest, AResidualAboveTheNoiseIsWarnedAboutNotPrinted) {
  RobotModel model = Puma560PaperModel();
  Eigen::VectorXd truth = Puma560TrueParameters();
  const Eigen::MatrixXd joints = testing::PumaLatticeJoints(3);
  // Link 2's length held at a value 2 mm off.
  const int fixed = 6 * 2 + kA;
  ASSERT_TRUE(model.IsFree(fixed));
  model.SetFree(fixed, false);
  truth[fixed] += 2e-3;
  ActiveCalibrationOptions options = SmallRun();
  options.loop.max_rounds = 2;
  std::vector<std::string> warned;
  options.warning = [&](const std::string& line) { warned.push_back(line); };
  ActiveCalibrationSummary summary;
  ::testing::internal::CaptureStderr();
  ASSERT_TRUE(RunActiveCalibration(model, truth, joints, nullptr, nullptr,
                                   options, &summary))
      << summary.message;
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  ASSERT_FALSE(summary.warnings.empty());
  EXPECT_EQ(warned, summary.warnings);
  size_t flagged = 0;
  for (const ActiveRound& round : summary.loop.rounds) {
    flagged += round.residuals_exceed_noise ? 1 : 0;
  }
  EXPECT_EQ(summary.warnings.size(), flagged);
  const std::string& first = summary.warnings[0];
  EXPECT_EQ(first.rfind("warning: round ", 0), 0u) << first;
  EXPECT_NE(first.find(" times --noise_m: the identified model does not fit "
                       "the measurements"),
            std::string::npos)
      << first;
  EXPECT_NE(first.back(), '\n');
}

TEST(ActiveCalibrationTest, ThePoolIsTheLatticeAndAReducedSetStartsAtItsPoint) {
  const RobotModel model = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  ActiveCalibrationOptions options;
  options.levels = 3;
  ActivePool pool;
  ASSERT_TRUE(MakeActivePool(model, Eigen::VectorXd(), nullptr, options, &pool))
      << pool.message;
  EXPECT_EQ(pool.joints, testing::PumaLatticeJoints(3));
  EXPECT_TRUE(pool.feasibility.verdicts.empty());
  EXPECT_EQ(pool.model.nominal, model.nominal);  // no truth: as given
  // The start between the truth and the nominal values.
  options.nominal_error_scale = 0.5;
  ASSERT_TRUE(MakeActivePool(model, truth, nullptr, options, &pool));
  EXPECT_TRUE(pool.model.nominal.isApprox(0.5 * (truth + model.nominal)));
  options.levels = 1;
  EXPECT_FALSE(MakeActivePool(model, truth, nullptr, options, &pool));
  EXPECT_EQ(pool.message.rfind("--levels=1: ", 0), 0u) << pool.message;

  // The registration set on the PUMA: fewer free parameters, each held one
  // named, the model started at the analysis point.
  options.levels = 3;
  ASSERT_TRUE(MakeActivePool(model, truth, nullptr, options, &pool));
  const Eigen::VectorXd start = pool.model.nominal;
  ASSERT_TRUE(ReduceForActivePool(ParameterSet::kRegistration, nullptr, &pool))
      << pool.message;
  EXPECT_LT(pool.model.num_free(), model.num_free());
  std::istringstream lines(pool.report);
  for (std::string line; std::getline(lines, line);) {
    EXPECT_EQ(line.rfind("  --parameter_set=registration: ", 0), 0u) << line;
    EXPECT_NE(line.find(" held fixed: "), std::string::npos) << line;
  }
  EXPECT_NE(pool.model.nominal, start);  // the reduction's point
}

TEST(ActiveCalibrationTest, TheRunIsCheckedAgainstWhatIsKnown) {
  ActiveCalibrationOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValidFor(/*truth_known=*/true, &error)) << error;
  EXPECT_FALSE(options.IsValidFor(/*truth_known=*/false, &error));
  EXPECT_EQ(error.rfind("--robot has no true values to simulate from", 0), 0u)
      << error;
  options.driver = "my_driver";
  EXPECT_TRUE(options.IsValidFor(/*truth_known=*/false, &error)) << error;
  options.nominal_error_scale = 2;
  EXPECT_FALSE(options.IsValidFor(/*truth_known=*/false, &error));
  EXPECT_EQ(error, "--nominal_error_scale needs the robot's true values");
  options.nominal_error_scale = -1;
  EXPECT_FALSE(options.IsValidFor(/*truth_known=*/true, &error));
  EXPECT_EQ(error, "--nominal_error_scale must be >= 0");
  options.nominal_error_scale = 1;
  options.compare = true;
  EXPECT_FALSE(options.IsValidFor(/*truth_known=*/true, &error));
  EXPECT_EQ(error.rfind("--compare simulates one-shot designs", 0), 0u)
      << error;
}

TEST(ActiveCalibrationTest, BadOptionsAreNamedAsTheFlags) {
  const RobotModel model = Puma560PaperModel();
  const Eigen::MatrixXd joints = testing::PumaLatticeJoints(3);
  ActiveCalibrationOptions options = SmallRun();
  options.loop.sigma_m = 0;
  ActiveCalibrationSummary summary;
  EXPECT_FALSE(RunActiveCalibration(model, Puma560TrueParameters(), joints,
                                    nullptr, nullptr, options, &summary));
  EXPECT_EQ(summary.message, "--noise_m must be > 0, got 0");

  // Nothing to simulate from.
  options = SmallRun();
  EXPECT_FALSE(RunActiveCalibration(model, Eigen::VectorXd(), joints, nullptr,
                                    nullptr, options, &summary));
  EXPECT_EQ(summary.message,
            "no true parameters to simulate from (or measure with a driver)");
}

}  // namespace
}  // namespace activecal
