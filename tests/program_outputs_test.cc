// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// What the programs print and write, made by the library: the calibration's
// choices (calibration_choices.h), a gnuplot figure for an option
// (report/gnuplot_figure.h), the progress line's timing and text
// (report/progress_line.h) and the closest name of a mistyped option
// (report/closest_name.h).

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "activecal/calibration/calibration_choices.h"
#include "activecal/calibration/calibration_setup.h"
#include "activecal/core/puma560.h"
#include "activecal/report/closest_name.h"
#include "activecal/report/gnuplot_figure.h"
#include "activecal/report/progress_line.h"

namespace activecal {
namespace {

TEST(ProgramOutputsTest, ChoicesSetInOrderWithTheFirstError) {
  const RobotModel model = Puma560PaperModel();
  CalibrationChoices choices;
  choices.model_selection = "cv";
  choices.selection_rule = "min";
  choices.selection_ranking = "jacobian";
  choices.robust_loss = "huber";
  choices.robust_scale_m = 0.003;
  choices.outlier_probability = 0.02;
  choices.rotation_weight = 0.5;
  choices.learned_residual = "auto";
  CalibrationOptions options;
  options.num_folds = 7;  // not a choice: left as it is
  // The first error of `choices` in `spelling`; empty when they are set.
  const auto first_error = [&](OptionSpelling spelling) {
    std::string error;
    return SetCalibrationChoices(model, choices, spelling, &options, &error)
               ? std::string()
               : error;
  };
  ASSERT_EQ(first_error(OptionSpelling::kFlags), "");
  EXPECT_EQ(options.model_selection, ModelSelectionMethod::kCrossValidation);
  EXPECT_EQ(options.selection_rule, SelectionRule::kMinimum);
  EXPECT_EQ(options.selection_ranking, ParameterRanking::kJacobian);
  EXPECT_EQ(options.identification.robust_loss, RobustLoss::kHuber);
  EXPECT_EQ(options.identification.robust_scale_m, 0.003);
  EXPECT_EQ(options.identification.outlier_probability, 0.02);
  EXPECT_EQ(options.identification.rotation_weight_m_per_rad, 0.5);
  EXPECT_EQ(options.learned_residual.mode, LearnedResidualMode::kAuto);
  EXPECT_TRUE(options.term_families.empty());
  EXPECT_EQ(options.num_folds, 7);
  // The first bad value named, in the caller's spelling.
  choices.selection_rule = "best";
  choices.robust_loss = "l1";
  EXPECT_EQ(first_error(OptionSpelling::kFlags),
            "--selection_rule must be 1se_most, min, 1se or ftest, got "
            "'best'");
  choices.selection_rule = "1se";
  EXPECT_EQ(first_error(OptionSpelling::kKeywords),
            "robust_loss must be none, huber or cauchy, got 'l1'");
  // The term families before the robust loss.
  choices.terms.harmonics = 9;
  EXPECT_EQ(first_error(OptionSpelling::kFlags).rfind("--harmonics", 0), 0u);
  choices.terms.harmonics = 1;
  choices.robust_loss = "cauchy";
  choices.rotation_weight = 0.0;
  choices.learned_residual = "sometimes";
  EXPECT_EQ(first_error(OptionSpelling::kFlags),
            "--rotation_weight must be finite and > 0 (m per rad), got "
            "0.000000");
  choices.rotation_weight = std::nan("");
  EXPECT_NE(first_error(OptionSpelling::kFlags), "");
  choices.rotation_weight = 1.0;
  EXPECT_EQ(first_error(OptionSpelling::kFlags),
            "--learned_residual must be off, on or auto, got 'sometimes'");
  choices.learned_residual = "off";
  ASSERT_EQ(first_error(OptionSpelling::kFlags), "");
  EXPECT_EQ(options.term_families.size(), 1u);  // the periodic family
}

TEST(ProgramOutputsTest, SimulationRefusesAPointsFile) {
  RobotDescription robot;
  robot.model = Puma560PaperModel();
  robot.true_parameters = Puma560TrueParameters();
  CalibrationSimulationOptions sim;
  sim.num_poses = 12;
  sim.points = true;
  std::vector<int64_t> poses;
  std::vector<Measurement> data;
  std::string notes, error;
  EXPECT_FALSE(SimulateCalibrationMeasurements(
      robot, sim, OptionSpelling::kFlags, &poses, &data, &notes, &error));
  EXPECT_EQ(error, "--points needs --measurements with type=point rows");
  EXPECT_FALSE(SimulateCalibrationMeasurements(
      robot, sim, OptionSpelling::kKeywords, &poses, &data, &notes, &error));
  EXPECT_EQ(error, "points needs measurements with type=point rows");
}

TEST(ProgramOutputsTest, GnuplotFigureOfAnOption) {
  OutputFile png{"stale", "x"};
  std::string note, error;
  const std::string path = ::testing::TempDir() + "program_outputs_fig.png";
  ASSERT_TRUE(MakeGnuplotFigure(
      GnuplotDataBlock("d", {{0, 0}, {1, 1}}) + "plot $d with lines", path,
      "--plot", &png, &note, &error))
      << error;
  if (!GnuplotAvailable()) {
    EXPECT_TRUE(png.path.empty());
    EXPECT_EQ(note, "  --plot: gnuplot is not installed; no plot\n");
    return;
  }
  EXPECT_EQ(png.path, path);
  EXPECT_EQ(png.text.substr(1, 3), "PNG");
  EXPECT_EQ(note, "  --plot: wrote " + path + "\n");
  EXPECT_FALSE(MakeGnuplotFigure("plot no_such_function(x)", path, "plot", &png,
                                 &note, &error));
  EXPECT_EQ(error.rfind("plot: gnuplot failed", 0), 0u) << error;
  EXPECT_TRUE(png.path.empty());
}

TEST(ProgramOutputsTest, ProgressLineAfterItsDelayThenThrottled) {
  const int64_t s = 1000000000;
  // In a file: nothing in the first 2 s, then a line every 2 s, the last
  // one once.
  ProgressLineClock file("prog: pool", /*tty=*/false, 2 * s, 0);
  EXPECT_EQ(file.Update(10, 100, s), "");
  EXPECT_FALSE(file.printed());
  EXPECT_EQ(file.Update(50, 100, 2 * s),
            "prog: pool: 50/100 (25/s, 2.0 s left)");
  EXPECT_TRUE(file.printed());
  EXPECT_EQ(file.Update(60, 100, 3 * s), "");
  EXPECT_EQ(file.Update(80, 100, 4 * s),
            "prog: pool: 80/100 (20/s, 1.0 s left)");
  EXPECT_EQ(file.Update(100, 100, 4 * s + s / 2),
            "prog: pool: 100/100 (4.5 s)");
  EXPECT_EQ(file.Update(100, 100, 5 * s), "");
  // No rate yet: the time so far.
  ProgressLineClock none("p: x", false, 0, 0);
  EXPECT_EQ(none.Update(0, 5, s / 2), "p: x: 0/5 (0.5 s so far)");
  // On a terminal: at most 5 lines a second, the last one every time.
  ProgressLineClock tty("p: x", /*tty=*/true, 2 * s, 0);
  EXPECT_NE(tty.Update(1, 10, 2 * s), "");
  EXPECT_EQ(tty.Update(2, 10, 2 * s + s / 10), "");
  EXPECT_NE(tty.Update(3, 10, 2 * s + s / 4), "");
  EXPECT_NE(tty.Update(10, 10, 2 * s + s / 4), "");
  EXPECT_NE(tty.Update(10, 10, 2 * s + s / 4), "");
}

TEST(ProgramOutputsTest, ProgressDelayFromText) {
  EXPECT_EQ(ProgressAfterNs(nullptr, 7), 7);
  EXPECT_EQ(ProgressAfterNs("", 7), 7);
  EXPECT_EQ(ProgressAfterNs("0", 7), 0);
  EXPECT_EQ(ProgressAfterNs("0.5", 7), 500000000);
  EXPECT_EQ(ProgressAfterNs("-1", 7), 7);
  EXPECT_EQ(ProgressAfterNs("2s", 7), 7);
  EXPECT_EQ(ProgressAfterNs("nan", 7), 7);
  EXPECT_EQ(ProgressAfterNs("1e7", 7), 7);
}

TEST(ProgramOutputsTest, ClosestNameOfAMistypedOption) {
  EXPECT_EQ(EditDistance("", "abc"), 3);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3);
  EXPECT_EQ(EditDistance("num_pose", "num_poses"), 1);
  const std::vector<std::string> names = {"num_poses", "noise_m", "seed",
                                          "help"};
  EXPECT_EQ(ClosestName("num_pose", names), "num_poses");
  EXPECT_EQ(ClosestName("sed", names), "seed");
  EXPECT_EQ(ClosestName("robot", names), "");  // nothing close
  EXPECT_EQ(ClosestName("seed", {}), "");
  // Ties: the first.
  EXPECT_EQ(ClosestName("ab", {"ax", "xb"}), "ax");
}

}  // namespace
}  // namespace activecal
