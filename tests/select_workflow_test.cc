// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/select_workflow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "activecal/calibration/cell_planning.h"
#include "activecal/core/measurement.h"
#include "activecal/core/puma560.h"

namespace activecal {
namespace {

int CountLines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

// A quick design: 12 poses of the 3-level lattice, greedily.
SelectOptions GreedyOnTheLattice() {
  SelectOptions o;
  o.levels = 3;
  o.design.algorithm = DesignAlgorithm::kGreedy;
  o.design.num_poses = 12;
  return o;
}

// Select's message for options it refuses.
std::string FailureOf(const RobotModel& model, const SelectOptions& o) {
  SelectSummary s;
  EXPECT_FALSE(Select(model, o, &s));
  EXPECT_EQ(s.termination_type, TerminationType::kFailure);
  return s.message;
}

// The nominal model's position of marker 0 at `q`: a measurement made.
Measurement PositionAt(const RobotModel& model, const Eigen::VectorXd& q) {
  Measurement like;
  like.joints = q;
  return PredictMeasurement(model, model.nominal, like);
}

TEST(SelectWorkflowTest, PoolNamesRoundTrip) {
  for (SelectPool p : {SelectPool::kLattice, SelectPool::kSobol,
                       SelectPool::kRandom, SelectPool::kMeasurable}) {
    SelectPool back = SelectPool::kCsv;
    ASSERT_TRUE(StringToSelectPool(SelectPoolToString(p), &back));
    EXPECT_EQ(back, p);
  }
  SelectPool p = SelectPool::kSobol;
  EXPECT_FALSE(StringToSelectPool("csv", &p));  // a CSV pool has a path
  EXPECT_FALSE(StringToSelectPool("halton", &p));
  EXPECT_EQ(p, SelectPool::kSobol);
}

TEST(SelectWorkflowTest, MakeLatticePoolChecksThePoolAndNotesTheLattice) {
  const RobotModel model = Puma560PaperModel();
  JointLattice lattice;
  std::string notes = "before\n", error;
  ASSERT_TRUE(MakeLatticePool(model, nullptr, 3, MeasurementType::kPosition,
                              "--", &lattice, &notes, &error))
      << error;
  EXPECT_EQ(lattice.size(), 729);  // 3^6
  std::string expected = "before\n";
  for (const std::string& note : lattice.OneTurnNotes(model)) {
    expected += "note: " + note + "\n";
  }
  EXPECT_EQ(notes, expected);
  EXPECT_TRUE(error.empty());
  // Refused: the option named, with the prefix given.
  EXPECT_FALSE(MakeLatticePool(model, nullptr, 1, MeasurementType::kPosition,
                               "", &lattice, &notes, &error));
  EXPECT_EQ(error.rfind("levels=1: ", 0), 0u) << error;
  EXPECT_FALSE(MakeLatticePool(model, nullptr, 100000,
                               MeasurementType::kPosition, "--", &lattice,
                               &notes, &error));
  EXPECT_EQ(error.rfind("--levels=100000: lattice: ", 0), 0u) << error;
  EXPECT_EQ(notes, expected);  // no notes on a failure
}

TEST(SelectWorkflowTest, LatticeDesignWithItsOutputs) {
  const RobotModel model = Puma560PaperModel();
  SelectOptions o = GreedyOnTheLattice();
  int stages = 0;
  o.progress = [&stages](const std::string&) {
    ++stages;
    return ProgressCallback();
  };
  SelectSummary s;
  ASSERT_TRUE(Select(model, o, &s)) << s.message;
  EXPECT_TRUE(s.IsSolutionUsable());
  EXPECT_EQ(s.pool_joints.rows(), 729);
  ASSERT_EQ(s.design.selection.design.size(), 12u);
  EXPECT_EQ(s.chosen.joints.rows(), 12);
  EXPECT_EQ(CountLines(s.poses_csv), 13);  // the header and 12 poses
  // The table: its header, then one line of levels per pose.
  EXPECT_NE(s.report.find("  #      index    levels (joint 1..n)\n"),
            std::string::npos)
      << s.report;
  EXPECT_NE(s.report.find("predicted task RMS"), std::string::npos);
  EXPECT_EQ(s.json["pool"], "lattice");
  EXPECT_EQ(s.json["levels"], 3);
  EXPECT_EQ(s.json["num_poses"], 12);
  EXPECT_EQ(s.json["criterion"], "d");
  EXPECT_EQ(s.json["measurement"], "position");
  EXPECT_EQ(s.json["pose_indices"].size(), 12u);
  EXPECT_FALSE(s.json.contains("cell"));
  EXPECT_FALSE(s.json.contains("tour"));
  EXPECT_TRUE(s.curve_csv.empty());  // no target
  EXPECT_EQ(s.ResultLine("prog").rfind("prog: 12 poses of 729 (greedy), ", 0),
            0u)
      << s.ResultLine("prog");
  EXPECT_GE(stages, 1);  // at least the Jacobians

  // A target: the curve, the JSON's curve.
  o.design.criterion = DesignCriterion::kTaskRms;
  o.design.target_rms_m = 1.0;
  o.order_shortest = true;  // no cell: the moves are not checked
  ASSERT_TRUE(Select(model, o, &s)) << s.message;
  EXPECT_EQ(s.curve_csv.rfind("num_poses,predicted_task_rms_m\n", 0), 0u);
  EXPECT_TRUE(s.json.contains("predicted_task_rms_by_size_m"));
  EXPECT_EQ(s.json["tour"]["moves_checked"], false);
  EXPECT_EQ(s.json["tour"]["moves_not_checked"], "no --cell");
}

TEST(SelectWorkflowTest, FailuresNameTheFlags) {
  const RobotModel model = Puma560PaperModel();
  SelectOptions o;
  SelectSummary s;
  // As flags or, spelt as the Python keywords, without the dashes.
  for (OptionSpelling spelling :
       {OptionSpelling::kFlags, OptionSpelling::kKeywords}) {
    const std::string dashes = spelling == OptionSpelling::kFlags ? "--" : "";
    o = SelectOptions();
    o.option_spelling = spelling;
    o.levels = 3;
    o.design.num_poses = 1000;
    EXPECT_FALSE(Select(model, o, &s));
    EXPECT_EQ(s.message, dashes +
                             "num_poses must be in [1, 729] (the pool "
                             "size), got 1000");
    o.design.num_poses = 12;
    o.levels = 1;
    EXPECT_FALSE(Select(model, o, &s));
    EXPECT_EQ(s.message.rfind(dashes + "levels=1: ", 0), 0u) << s.message;
  }
  o = SelectOptions();
  o.pool = SelectPool::kMeasurable;
  EXPECT_FALSE(Select(model, o, &s));
  EXPECT_EQ(s.message,
            "--pool=measurable needs --cell (the device and the targets to "
            "sample for)");
  o = SelectOptions();
  o.pool = SelectPool::kCsv;
  o.pool_csv = "/nonexistent/pool.csv";
  EXPECT_FALSE(Select(model, o, &s));
  EXPECT_EQ(s.message.rfind("--pool_csv: ", 0), 0u) << s.message;
  o = SelectOptions();
  o.levels = 3;
  o.design.criterion = DesignCriterion::kTaskRms;  // eae has no task version
  EXPECT_FALSE(Select(model, o, &s));
  EXPECT_EQ(s.message,
            "--criterion=task_rms: --algorithm must be fedorov, greedy or "
            "approx, got 'eae'");
  EXPECT_EQ(s.termination_type, TerminationType::kFailure);
}

TEST(SelectWorkflowTest, PoolOptionsAreCheckedBeforeThePoolIsMade) {
  const RobotModel model = Puma560PaperModel();
  std::string error;
  SelectOptions o;
  EXPECT_TRUE(o.IsValid(model, &error)) << error;
  o.pool = SelectPool::kSobol;
  o.pool_csv = "pool.csv";
  EXPECT_FALSE(o.IsValid(model, &error));
  EXPECT_EQ(error, "--pool=sobol and --pool_csv: choose one");
  // A size is for a drawn pool only, even the default size given.
  o = SelectOptions();
  o.pool_size = defaults::kPoolSize;
  EXPECT_FALSE(o.IsValid(model, &error));
  EXPECT_EQ(error,
            "--pool_size sizes a --pool=sobol, random or measurable pool; "
            "the lattice has --levels poses per joint: give --pool or drop "
            "--pool_size");
  o.pool_csv = "pool.csv";
  EXPECT_FALSE(o.IsValid(model, &error));
  EXPECT_NE(error.find("; --pool_csv has its rows: "), std::string::npos)
      << error;
  o = SelectOptions();
  o.pool = SelectPool::kRandom;
  o.pool_size = 100000000000;
  EXPECT_FALSE(o.IsValid(model, &error));
  EXPECT_EQ(error.rfind("--pool_size: ", 0), 0u) << error;
  o.pool_size = 100;
  EXPECT_TRUE(o.IsValid(model, &error)) << error;
  o.max_draws = 0;
  EXPECT_FALSE(o.IsValid(model, &error));
  EXPECT_EQ(error,
            "--max_draws caps the draws of --pool=measurable, got "
            "--pool=random");
  // Select refuses the same, before any pool is made.
  SelectSummary s;
  EXPECT_FALSE(Select(model, o, &s));
  EXPECT_EQ(s.message, error);
  EXPECT_TRUE(s.report.empty()) << s.report;
}

TEST(SelectWorkflowTest, PoolTaskAndMeasuredGivenInMemory) {
  const RobotModel model = Puma560PaperModel();
  SelectOptions o = GreedyOnTheLattice();
  SelectSummary lattice;
  ASSERT_TRUE(Select(model, o, &lattice)) << lattice.message;
  // The lattice's poses given as the pool, labelled: the same design, its
  // labels the pool's.
  o.pool = SelectPool::kPoses;
  o.pool_poses.joints = lattice.pool_joints;
  {
    SelectSummary unlabelled;
    EXPECT_TRUE(Select(model, o, &unlabelled)) << unlabelled.message;
    EXPECT_EQ(o.pool_poses.joints.rows(), 729);
    EXPECT_EQ(unlabelled.design.selection.design,
              lattice.design.selection.design);
  }
  for (int64_t i = 0; i < o.pool_poses.joints.rows(); ++i) {
    o.pool_poses.pose_indices.push_back(1000 + i);
  }
  SelectSummary s;
  ASSERT_TRUE(Select(model, o, &s)) << s.message;
  EXPECT_EQ(s.design.selection.design, lattice.design.selection.design);
  ASSERT_EQ(s.chosen.pose_indices.size(), 12u);
  EXPECT_EQ(s.chosen.pose_indices[0], 1000 + s.design.selection.design[0]);
  EXPECT_EQ(s.json["pool"], "poses");
  EXPECT_FALSE(s.json.contains("levels"));
  EXPECT_TRUE(s.lattice_notes.empty());
  EXPECT_FALSE(s.pool.filtered);  // no cell
  EXPECT_EQ(s.json["num_task_poses"], 729);

  // The task: 40 poses given; the measured poses counted.
  o.design.criterion = DesignCriterion::kTaskRms;
  o.design.algorithm = DesignAlgorithm::kFedorov;
  o.design.restarts = 2;
  o.task_joints = lattice.pool_joints.topRows(40);
  for (int k = 0; k < 3; ++k) {
    o.measured.push_back(
        PositionAt(model, lattice.pool_joints.row(k).transpose()));
  }
  ASSERT_TRUE(Select(model, o, &s)) << s.message;
  EXPECT_EQ(s.json["num_task_poses"], 40);
  EXPECT_EQ(s.json["num_measured"], 3);
  EXPECT_NE(s.report.find(", 3 measured poses counted"), std::string::npos)
      << s.report;

  // Measured poses need the task criterion; the labels are checked.
  o.design.criterion = DesignCriterion::kDet;
  EXPECT_EQ(FailureOf(model, o),
            "--measured_csv needs --criterion=task_rms (the D-criterion "
            "algorithms take no prior information)");
  o.measured.clear();
  o.pool_poses.pose_indices.assign(3, 7);
  EXPECT_EQ(FailureOf(model, o),
            "pool_indices: expected 729 values (one per pool pose), got 3");
  o.pool_poses.pose_indices.assign(729, 7);
  EXPECT_EQ(FailureOf(model, o).rfind("pool_indices: pose_indices[1] = 7", 0),
            0u);
  o.pool = SelectPool::kLattice;  // poses given for another pool
  EXPECT_EQ(FailureOf(model, o),
            "pool_poses give the poses of pool=poses, got pool=lattice");
}

TEST(SelectWorkflowTest, MessagesSpeltAsTheKeywords) {
  const RobotModel model = Puma560PaperModel();
  SelectOptions o;
  o.option_spelling = OptionSpelling::kKeywords;
  o.levels = 3;
  o.design.num_poses = 12;
  SelectSummary s;
  o.design.criterion = DesignCriterion::kTaskRms;  // eae has no task version
  EXPECT_EQ(FailureOf(model, o),
            "criterion=task_rms: algorithm must be fedorov, greedy or "
            "approx, got 'eae'");
  o.design.algorithm = DesignAlgorithm::kGreedy;
  o.measured.push_back(PositionAt(model, Eigen::VectorXd::Zero(6)));
  o.design.criterion = DesignCriterion::kDet;
  EXPECT_EQ(FailureOf(model, o),
            "measured needs criterion='task_rms' (the D-criterion "
            "algorithms take no prior information)");
  o.measured.clear();
  o.pool = SelectPool::kRandom;
  o.pool_size = 100000000000;
  EXPECT_EQ(FailureOf(model, o).rfind("pool_size: ", 0), 0u);
  // A tour without a cell: its moves not checked, for want of cell=.
  o = GreedyOnTheLattice();
  o.option_spelling = OptionSpelling::kKeywords;
  o.order_shortest = true;
  ASSERT_TRUE(Select(model, o, &s)) << s.message;
  EXPECT_EQ(s.json["tour"]["moves_not_checked"], "no cell=");
}

TEST(SelectWorkflowTest, TourJsonNamesTheBlockedMovesByTheRun) {
  TourSummary tour;
  tour.time_before_s = 12.5;
  tour.time_after_s = 8.25;
  tour.velocities = {1.0, 2.0};
  tour.blocked_moves = {1};
  tour.blocked_reasons = {"obstacle table (wrist_3_link)"};
  tour.blocked_before = 3;
  const nlohmann::json checked = {{"moves_checked", true}};
  nlohmann::json t = TourJson(tour, 2.0, {40, 41, 42}, checked, "");
  EXPECT_EQ(t["motion_time_before_s"], 12.5);
  EXPECT_EQ(t["motion_time_after_s"], 8.25);
  EXPECT_EQ(t["resolution_deg"], 2.0);
  EXPECT_EQ(t["blocked_moves"], 1);
  EXPECT_EQ(t["blocked_moves_before"], 3);
  EXPECT_EQ(t["moves_checked"], true);
  ASSERT_EQ(t["blocked"].size(), 1u);
  EXPECT_EQ(t["blocked"][0]["from_pose_index"], 41);
  EXPECT_EQ(t["blocked"][0]["to_pose_index"], 42);
  EXPECT_EQ(t["blocked"][0]["reason"], "obstacle table (wrist_3_link)");
  EXPECT_FALSE(t.contains("velocity_note"));
  t = TourJson(tour, 1.0, {40, 41, 42}, checked, "joints 1 have no limit");
  EXPECT_EQ(t["velocity_note"], "joints 1 have no limit");
}

}  // namespace
}  // namespace activecal
