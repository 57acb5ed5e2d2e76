// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_sim_cell's set-up (calibration/simulated_cell_setup.h): a bad
// --parameter_set, a robot without true values and a bad cell named in the
// message; `offsets` and `full` reduce the free set (the file's set kept
// without --parameter_set); the perturbation moves only the free
// parameters, the same for a seed and otherwise for another; a cell's
// targets become the markers; and the truth file's text read back by the
// robot file reader gives the nominal values, the free set and the truth
// to the last bit.

#include "activecal/calibration/simulated_cell_setup.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/io/robot_file.h"
#include "activecal/io/robot_loader.h"

namespace activecal {
namespace {

const std::string kData = ACTIVECAL_DATA_DIR;

RobotDescription Load(const std::string& path) {
  RobotLoadOptions options;
  if (IsUrdfPath(path)) options.chain.tip_link = "tool0";
  RobotDescription robot;
  std::string error;
  EXPECT_TRUE(LoadRobot(path, options, &robot, &error)) << error;
  return robot;
}

SimulatedCellSetupOptions Options(const std::string& robot_path,
                                  const std::string& parameter_set) {
  SimulatedCellSetupOptions options;
  options.robot_path = robot_path;
  if (IsUrdfPath(robot_path)) options.chain.tip_link = "tool0";
  options.parameter_set = parameter_set;
  return options;
}

TEST(SimulatedCellSetupTest, BadParameterSetIsNamed) {
  const std::string path = kData + "/puma560.yaml";
  RobotDescription robot = Load(path);
  SimulatedCellSetup setup;
  EXPECT_FALSE(SetUpSimulatedCell(Options(path, "most"), &robot, &setup));
  EXPECT_FALSE(setup.ok);
  EXPECT_EQ(setup.message,
            "--parameter_set must be registration, offsets, full or file, "
            "got 'most'");
  EXPECT_EQ(setup.truth.size(), 0);
}

TEST(SimulatedCellSetupTest, NoTrueValuesAndBadCellAreNamed) {
  // A URDF has no true values: without a perturbation there is no truth.
  const std::string urdf = kData + "/ur10.urdf";
  RobotDescription robot = Load(urdf);
  ASSERT_EQ(robot.true_parameters.size(), 0);
  SimulatedCellSetup setup;
  EXPECT_FALSE(SetUpSimulatedCell(Options(urdf, ""), &robot, &setup));
  EXPECT_EQ(setup.message,
            "--robot has no true values: add 'true:' entries "
            "(docs/formats.md) or perturb it (--perturb_m, --perturb_rad)");
  // The lattice's reduction ran before: its log is kept.
  EXPECT_NE(setup.log.find("--parameter_set=full: "), std::string::npos)
      << setup.log;

  SimulatedCellSetupOptions options = Options(urdf, "");
  options.cell_path = kData + "/cells/no_such_cell.yaml";
  robot = Load(urdf);
  EXPECT_FALSE(SetUpSimulatedCell(options, &robot, &setup));
  EXPECT_EQ(setup.message.rfind("--cell: ", 0), 0u) << setup.message;
  EXPECT_NE(setup.message.find("no_such_cell.yaml"), std::string::npos)
      << setup.message;
}

TEST(SimulatedCellSetupTest, ParameterSetReducesTheFreeSet) {
  const std::string path = kData + "/puma560.yaml";
  const RobotDescription loaded = Load(path);
  const int file_free = loaded.model.num_free();
  ASSERT_GT(file_free, 0);

  // No --parameter_set on a robot file: its free lists, unreduced; the
  // truth its true: entries.
  RobotDescription robot = loaded;
  SimulatedCellSetup setup;
  ASSERT_TRUE(SetUpSimulatedCell(Options(path, ""), &robot, &setup))
      << setup.message;
  EXPECT_TRUE(setup.ok);
  EXPECT_EQ(robot.model.FreeParameterNames(),
            loaded.model.FreeParameterNames());
  EXPECT_TRUE(setup.log.empty()) << setup.log;
  EXPECT_EQ(setup.truth, loaded.true_parameters);

  // offsets: fewer free than the file's, every one of them a free one of
  // the full set.
  robot = loaded;
  ASSERT_TRUE(SetUpSimulatedCell(Options(path, "offsets"), &robot, &setup))
      << setup.message;
  const int offsets_free = robot.model.num_free();
  EXPECT_GT(offsets_free, 0);
  EXPECT_LT(offsets_free, file_free);
  const std::vector<std::string> offsets = robot.model.FreeParameterNames();

  RobotDescription full = loaded;
  SimulatedCellSetup full_setup;
  ASSERT_TRUE(SetUpSimulatedCell(Options(path, "full"), &full, &full_setup))
      << full_setup.message;
  EXPECT_GT(full.model.num_free(), offsets_free);
  const std::vector<std::string> full_names = full.model.FreeParameterNames();
  for (const std::string& name : offsets) {
    EXPECT_NE(std::find(full_names.begin(), full_names.end(), name),
              full_names.end())
        << name;
  }
  // The full set is more than the lattice separates: some held, one line
  // each with its reason.
  EXPECT_NE(full_setup.log.find("  --parameter_set=full: "), std::string::npos)
      << full_setup.log;
  EXPECT_NE(full_setup.log.find(" held fixed: "), std::string::npos);
  EXPECT_EQ(full_setup.log.back(), '\n');
}

TEST(SimulatedCellSetupTest, PerturbationFollowsTheSeed) {
  const std::string urdf = kData + "/ur10.urdf";
  auto truth = [&](uint64_t seed, RobotModel* model) {
    RobotDescription robot = Load(urdf);
    SimulatedCellSetupOptions options = Options(urdf, "");
    options.cell.perturb_m = 1e-3;
    options.cell.perturb_rad = 1e-3;
    options.cell.seed = seed;
    SimulatedCellSetup setup;
    EXPECT_TRUE(SetUpSimulatedCell(options, &robot, &setup)) << setup.message;
    if (model != nullptr) *model = robot.model;
    return setup.truth;
  };
  RobotModel model;
  const Eigen::VectorXd a = truth(2, &model);
  ASSERT_EQ(a.size(), model.num_parameters());
  EXPECT_EQ(truth(2, nullptr), a);  // the same seed: the same truth
  const Eigen::VectorXd b = truth(3, nullptr);
  ASSERT_EQ(b.size(), a.size());
  EXPECT_GT((b - a).norm(), 1e-6);  // another seed: another truth
  // Only free parameters moved (the lengths and angles: most of them), each
  // by a few sigma at most.
  int moved = 0;
  for (int i = 0; i < model.num_parameters(); ++i) {
    if (!model.IsFree(i)) {
      EXPECT_EQ(a[i], model.nominal[i]) << model.ParameterNames()[i];
    } else {
      EXPECT_LT(std::abs(a[i] - model.nominal[i]), 6e-3)
          << model.ParameterNames()[i];
      if (a[i] != model.nominal[i]) ++moved;
    }
  }
  EXPECT_GT(moved, model.num_free() / 2);
}

TEST(SimulatedCellSetupTest, CellTargetsBecomeTheMarkers) {
  const std::string urdf = kData + "/ur10e.urdf";
  RobotDescription robot = Load(urdf);
  SimulatedCellSetupOptions options = Options(urdf, "offsets");
  options.cell_path = kData + "/cells/ur10e_table.yaml";
  options.cell.perturb_m = 1e-3;
  SimulatedCellSetup setup;
  ASSERT_TRUE(SetUpSimulatedCell(options, &robot, &setup)) << setup.message;
  ASSERT_NE(setup.cell.checker, nullptr);
  ASSERT_EQ(robot.model.num_markers(), 1);
  EXPECT_EQ(robot.model.markers[0].name, "smr");
  EXPECT_EQ(setup.truth.size(), robot.model.num_parameters());
  // The marker's nominal point is the target's (0, 0, 0.06 in tool0).
  const int z = robot.model.ParameterIndex("smr.z");
  ASSERT_GE(z, 0);
  EXPECT_DOUBLE_EQ(robot.model.nominal[z], 0.06);
}

TEST(SimulatedCellSetupTest, TruthTextReadsBackToTheTruth) {
  const std::string urdf = kData + "/ur10.urdf";
  RobotDescription robot = Load(urdf);
  SimulatedCellSetupOptions options = Options(urdf, "");
  options.cell.perturb_m = 1e-3;
  options.cell.perturb_rad = 1e-3;
  options.cell.seed = 7;
  SimulatedCellSetup setup;
  ASSERT_TRUE(SetUpSimulatedCell(options, &robot, &setup)) << setup.message;
  const std::string text = SimulatedCellTruthText(robot.model, setup.truth, 7);
  EXPECT_EQ(text.rfind("# The robot of activecal_sim_cell --seed=7 (nominal "
                       "values and the cell's true values)\n",
                       0),
            0u)
      << text.substr(0, 200);
  RobotDescription read;
  std::string error;
  ASSERT_TRUE(ParseRobotDescription(text, "truth.yaml", &read, &error))
      << error;
  ASSERT_EQ(read.model.num_parameters(), robot.model.num_parameters());
  EXPECT_EQ(read.model.nominal, robot.model.nominal);
  EXPECT_EQ(read.true_parameters, setup.truth);
  EXPECT_EQ(read.model.FreeParameterNames(), robot.model.FreeParameterNames());
  EXPECT_NE(read.true_parameters, read.model.nominal);
}

}  // namespace
}  // namespace activecal
