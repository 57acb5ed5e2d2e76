// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// ReproducePaperExample and MakePaperPool (calibration/paper_example.h):
// the Section V run's files, report and numbers, and its refusals.

#include "activecal/calibration/paper_example.h"

#include <gtest/gtest.h>

#include "activecal/core/puma560.h"

namespace activecal {
namespace {

nlohmann::json WithoutTiming(nlohmann::json j) {
  j.erase("timing");
  for (const char* key : {"random", "eae"}) j[key].erase("seconds");
  return j;
}

TEST(PaperExampleTest, MakePaperPoolIsTheFiveLevelLattice) {
  PaperPool paper;
  std::string error;
  ASSERT_TRUE(MakePaperPool(Puma560PaperModel(), 2, nullptr, &paper, &error))
      << error;
  EXPECT_EQ(paper.pool.size(), 15625);
  EXPECT_EQ(paper.joints.rows(), 15625);
  EXPECT_EQ(paper.lattice.size(), 15625);
  EXPECT_TRUE(paper.notes.empty());
}

TEST(PaperExampleTest, RefusesARobotWithoutTrueValues) {
  PaperExampleSummary summary;
  EXPECT_FALSE(ReproducePaperExample(Puma560PaperModel(), Eigen::VectorXd(),
                                     PaperExampleOptions(), &summary));
  EXPECT_EQ(summary.termination_type, TerminationType::kFailure);
  EXPECT_NE(summary.message.find("reproduces the paper's PUMA 560"),
            std::string::npos)
      << summary.message;
  EXPECT_TRUE(summary.report.empty());
  EXPECT_TRUE(summary.files.empty());
}

TEST(PaperExampleTest, ShortRunWritesTheFilesAndBeatsRandomDesigns) {
  PaperExampleOptions options;
  options.random_designs = 50;
  options.certificate = false;
  options.num_threads = 2;
  options.out_dir = "somewhere";
  options.program_name = "prog";
  int stages = 0;
  options.progress = [&stages](const std::string& stage) {
    EXPECT_EQ(stage, "Jacobians of the pool poses");
    ++stages;
    return ProgressCallback();
  };
  PaperExampleSummary s;
  ASSERT_TRUE(ReproducePaperExample(Puma560PaperModel(),
                                    Puma560TrueParameters(), options, &s))
      << s.message;
  EXPECT_EQ(stages, 1);
  EXPECT_EQ(s.termination_type, TerminationType::kConvergence);
  std::vector<std::string> names;
  for (const auto& [name, text] : s.files) {
    names.push_back(name);
    EXPECT_FALSE(text.empty()) << name;
  }
  EXPECT_EQ(names, (std::vector<std::string>{
                       "random_designs.csv", "eae_history.csv", "eae_poses.csv",
                       "eae_initial_poses.csv", "random_best_poses.csv",
                       "identification.csv"}));
  // 50 random designs: one line each and the header.
  EXPECT_EQ(
      std::count(s.files[0].second.begin(), s.files[0].second.end(), '\n'), 51);
  EXPECT_EQ(s.num_parameters, 27);
  EXPECT_GT(s.eae_oi, s.random_oi);
  EXPECT_GT(s.oid_ratio_log10, 0);
  EXPECT_GE(s.num_within_2_std, 20);
  EXPECT_EQ(
      s.report.rfind("Sun & Hollerbach, Section V, reproduced (seed 1)", 0),
      0u);
  EXPECT_NE(s.report.find("Files for the figures are in somewhere/\n"),
            std::string::npos);
  EXPECT_EQ(s.result_line.rfind("prog: exchange-add-exchange OI ", 0), 0u);
  EXPECT_NE(s.result_line.find("; files in somewhere/"), std::string::npos);
  EXPECT_EQ(s.json["pool_size"], 15625);
  EXPECT_EQ(s.json["identification"]["parameters"].size(), 27u);
  EXPECT_FALSE(s.json.contains("fedorov"));

  // The results do not depend on the thread count.
  options.num_threads = 1;
  PaperExampleSummary again;
  ASSERT_TRUE(ReproducePaperExample(Puma560PaperModel(),
                                    Puma560TrueParameters(), options, &again));
  EXPECT_EQ(WithoutTiming(again.json), WithoutTiming(s.json));
  EXPECT_EQ(again.files, s.files);
}

}  // namespace
}  // namespace activecal
