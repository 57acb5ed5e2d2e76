// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// RunMonteCarloStudy (calibration/monte_carlo_study.h): the design from a
// poses CSV, the report, JSON and result line, and the refusals.

#include "activecal/calibration/monte_carlo_study.h"

#include <gtest/gtest.h>

#include <fstream>

#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"

namespace activecal {
namespace {

// 30 distinct random poses of the PUMA's 5-level lattice as a poses CSV.
std::string WritePumaPoses(const std::string& name) {
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(Puma560PaperModel(), 5, &lattice, &error));
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream out(path);
  out.precision(17);
  out << "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad\n";
  Random random(7);
  for (int64_t i : random.SampleWithoutReplacement(lattice.size(), 30)) {
    const Eigen::VectorXd q = lattice.JointValues(i);
    for (int j = 0; j < q.size(); ++j) out << (j ? "," : "") << q[j];
    out << "\n";
  }
  return path;
}

TEST(MonteCarloStudyTest, DesignFromAPosesCsv) {
  MonteCarloStudyOptions options;
  options.poses_csv = WritePumaPoses("mc_study_poses.csv");
  options.num_trials = 60;
  options.noise_m = 1e-3;
  options.num_threads = 2;
  options.program_name = "prog";
  std::vector<std::string> stages;
  options.progress = [&stages](const std::string& stage) {
    stages.push_back(stage);
    return ProgressCallback();
  };
  MonteCarloStudySummary s;
  ASSERT_TRUE(RunMonteCarloStudy(Puma560PaperModel(), Puma560TrueParameters(),
                                 options, &s))
      << s.message;
  // No pool without the default design.
  EXPECT_EQ(stages, std::vector<std::string>{"identifications"});
  EXPECT_EQ(s.num_poses, 30);
  EXPECT_EQ(s.monte_carlo.num_trials, 60);
  EXPECT_EQ(s.report.rfind("parameter ", 0), 0u) << s.report;
  EXPECT_NE(s.report.find("\n30 poses, 0.001 m noise\n"), std::string::npos);
  EXPECT_EQ(s.json["trials"], 60);
  EXPECT_EQ(s.json["num_poses"], 30);
  EXPECT_EQ(s.json["parameters"].size(), 27u);
  EXPECT_EQ(s.json["robot"], Puma560PaperModel().name);
  EXPECT_EQ(s.result_line.rfind("prog: 60 trials (", 0), 0u) << s.result_line;
}

TEST(MonteCarloStudyTest, Refusals) {
  MonteCarloStudySummary s;
  EXPECT_FALSE(RunMonteCarloStudy(Puma560PaperModel(), Eigen::VectorXd(),
                                  MonteCarloStudyOptions(), &s));
  EXPECT_EQ(s.message,
            "--robot has no true values to simulate from (add 'true:' "
            "entries, docs/formats.md)");
  MonteCarloStudyOptions options;
  options.poses_csv = ::testing::TempDir() + "/no_such_poses.csv";
  EXPECT_FALSE(RunMonteCarloStudy(Puma560PaperModel(), Puma560TrueParameters(),
                                  options, &s));
  EXPECT_EQ(s.message.rfind("--poses_csv: ", 0), 0u) << s.message;
  options.poses_csv = WritePumaPoses("mc_study_poses2.csv");
  options.num_trials = 1;
  EXPECT_FALSE(RunMonteCarloStudy(Puma560PaperModel(), Puma560TrueParameters(),
                                  options, &s));
  EXPECT_EQ(s.message, "num_trials must be >= 3, got 1");
}

}  // namespace
}  // namespace activecal
