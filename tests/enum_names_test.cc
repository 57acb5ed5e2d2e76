// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The enum name tables (core/enum_names.h): EnumToString and StringToEnum
// on a table, and the XToString/StringToX pairs the layers define with
// ACTIVECAL_ENUM_STRING_FUNCTIONS: every name as it was spelled before the
// tables, a round trip, a name that is not one.

#include "activecal/core/enum_names.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/evaluate.h"
#include "activecal/calibration/select_design.h"
#include "activecal/calibration/select_workflow.h"
#include "activecal/cell/cell_checker.h"
#include "activecal/cell/cell_file.h"
#include "activecal/cell/shape.h"
#include "activecal/core/enum_name_list.h"
#include "activecal/core/free_set.h"
#include "activecal/core/joint_errors.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/driver/protocol.h"
#include "activecal/driver/simulated_cell.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/learned_residual.h"
#include "activecal/estimation/model_selection.h"
#include "activecal/io/controller_programs.h"
#include "activecal/kinematics/inverse_kinematics.h"

namespace activecal {
namespace {

enum class Colour { kRed, kGreen, kBlue };
constexpr EnumName<Colour> kColourNames[] = {{Colour::kRed, "red"},
                                             {Colour::kGreen, "green"}};

TEST(EnumNamesTest, EnumToStringNamesTheValuesOfTheTable) {
  EXPECT_STREQ(EnumToString(kColourNames, Colour::kRed), "red");
  EXPECT_STREQ(EnumToString(kColourNames, Colour::kGreen), "green");
  // A value the table lacks.
  EXPECT_STREQ(EnumToString(kColourNames, Colour::kBlue), "unknown");
  EXPECT_STREQ(EnumToString(kColourNames, Colour::kBlue, "UNKNOWN"), "UNKNOWN");
}

TEST(EnumNamesTest, StringToEnumMatchesExactlyAndLeavesTheValueOnFailure) {
  Colour colour = Colour::kBlue;
  EXPECT_TRUE(StringToEnum(kColourNames, "green", &colour));
  EXPECT_EQ(colour, Colour::kGreen);
  EXPECT_TRUE(StringToEnum(kColourNames, "red", &colour));
  EXPECT_EQ(colour, Colour::kRed);
  for (const char* bad : {"Red", "RED", "re", "red ", "", "blue", "unknown"}) {
    colour = Colour::kBlue;
    EXPECT_FALSE(StringToEnum(kColourNames, bad, &colour)) << bad;
    EXPECT_EQ(colour, Colour::kBlue) << bad;
  }
}

// Each public pair: the names in the enum's order, each read back to its
// value, and a wrong name refused with the value untouched.
template <typename Enum>
void ExpectNames(const char* (*to_string)(Enum),
                 bool (*from_string)(const std::string&, Enum*),
                 const std::vector<Enum>& values,
                 std::initializer_list<const char*> names) {
  ASSERT_EQ(values.size(), names.size());
  auto name = names.begin();
  for (Enum value : values) {
    EXPECT_STREQ(to_string(value), *name);
    Enum read =
        *values.begin() == value ? *(values.end() - 1) : *values.begin();
    EXPECT_TRUE(from_string(*name, &read)) << *name;
    EXPECT_EQ(read, value) << *name;
    ++name;
  }
  Enum untouched = *values.begin();
  EXPECT_FALSE(from_string("no_such_name", &untouched));
  EXPECT_EQ(untouched, *values.begin());
  EXPECT_FALSE(from_string(std::string(*names.begin()) + "x", &untouched));
}

TEST(EnumNamesTest, TheLayersEnumsKeepTheirNames) {
  ExpectNames(ParameterSetToString, StringToParameterSet,
              {ParameterSet::kRegistration, ParameterSet::kOffsets,
               ParameterSet::kFull, ParameterSet::kFile},
              {"registration", "offsets", "full", "file"});
  ExpectNames(HoldStageToString, StringToHoldStage,
              {HoldStage::kParameterSet, HoldStage::kAutoFix,
               HoldStage::kModelSelection},
              {"parameter_set", "auto_fix", "model_selection"});
  ExpectNames(ProgramLanguageToString, StringToProgramLanguage,
              {ProgramLanguage::kUrScript, ProgramLanguage::kKrl,
               ProgramLanguage::kRapid},
              {"urscript", "krl", "rapid"});
  ExpectNames(RejectionReasonToString, StringToRejectionReason,
              {RejectionReason::kNone, RejectionReason::kJointMargin,
               RejectionReason::kOutOfRange, RejectionReason::kOutOfView,
               RejectionReason::kFacingAway, RejectionReason::kSelfCollision,
               RejectionReason::kObstacle, RejectionReason::kLineOfSight},
              {"none", "joint_margin", "out_of_range", "out_of_view",
               "facing_away", "self_collision", "obstacle", "line_of_sight"});
  ExpectNames(LearnedResidualModeToString, StringToLearnedResidualMode,
              {LearnedResidualMode::kOff, LearnedResidualMode::kOn,
               LearnedResidualMode::kAuto},
              {"off", "on", "auto"});
  ExpectNames(
      ModelSelectionMethodToString, StringToModelSelectionMethod,
      {ModelSelectionMethod::kNone, ModelSelectionMethod::kValidation,
       ModelSelectionMethod::kCrossValidation, ModelSelectionMethod::kAuto},
      {"none", "validation", "cv", "auto"});
  ExpectNames(ParameterRankingToString, StringToParameterRanking,
              {ParameterRanking::kSignificance, ParameterRanking::kJacobian},
              {"significance", "jacobian"});
  ExpectNames(SelectionRuleToString, StringToSelectionRule,
              {SelectionRule::kMinimum, SelectionRule::kFewestWithinOneSe,
               SelectionRule::kMostWithinOneSe, SelectionRule::kFTest},
              {"min", "1se", "1se_most", "ftest"});
  ExpectNames(RobustLossToString, StringToRobustLoss,
              {RobustLoss::kNone, RobustLoss::kHuber, RobustLoss::kCauchy},
              {"none", "huber", "cauchy"});
}

// Names without a reading back (the lists of core, estimation and
// kinematics), each value spelled out: a list out of the enum's order fails.
template <typename Enum>
void ExpectSpelling(const char* (*to_string)(Enum),
                    std::initializer_list<Enum> values,
                    std::initializer_list<const char*> names) {
  ASSERT_EQ(values.size(), names.size());
  auto name = names.begin();
  for (Enum value : values) EXPECT_STREQ(to_string(value), *name++);
}

TEST(EnumNamesTest, TheLowerLayersNamesKeepTheirSpelling) {
  ExpectSpelling(
      LinkConventionName,
      {LinkConvention::kStandardDH, LinkConvention::kModifiedDH,
       LinkConvention::kHayati, LinkConvention::kUrdf, LinkConvention::kFrame},
      {"standard_dh", "modified_dh", "hayati", "urdf", "frame"});
  ExpectSpelling(
      JointTypeName,
      {JointType::kRevolute, JointType::kPrismatic, JointType::kFixed},
      {"revolute", "prismatic", "fixed"});
  ExpectSpelling(
      ParameterKindUnit,
      {ParameterKind::kLength, ParameterKind::kAngle, ParameterKind::kGain},
      {"m", "rad", "1"});
  ExpectSpelling(JointTermKindToString,
                 {JointTermKind::kCompliance, JointTermKind::kSine,
                  JointTermKind::kCosine},
                 {"compliance", "sin", "cos"});
  ExpectSpelling(
      TerminationTypeToString,
      {TerminationType::kConvergence, TerminationType::kNoConvergence,
       TerminationType::kFailure, TerminationType::kUserFailure},
      {"CONVERGENCE", "NO_CONVERGENCE", "FAILURE", "USER_FAILURE"});
  EXPECT_STREQ(TerminationTypeToString(static_cast<TerminationType>(9)),
               "UNKNOWN");
  ExpectSpelling(
      PostureGroupName,
      {PostureGroup::kRepeated, PostureGroup::kNew, PostureGroup::kOutOfRange},
      {"repeated", "new", "out_of_range"});
  ExpectSpelling(IkStatusName,
                 {IkStatus::kConverged, IkStatus::kSingular, IkStatus::kLimit,
                  IkStatus::kUnreachable, IkStatus::kInvalid,
                  IkStatus::kIterationCap, IkStatus::kCollision},
                 {"converged", "singular", "limit", "unreachable", "invalid",
                  "iteration_cap", "collision"});
  // MeasurementType's names are read back too.
  ExpectNames(
      MeasurementTypeName, ParseMeasurementType,
      {MeasurementType::kPosition, MeasurementType::kPose,
       MeasurementType::kDistance, MeasurementType::kPoint,
       MeasurementType::kPointDistance, MeasurementType::kPlane},
      {"position", "pose", "distance", "point", "point_distance", "plane"});
}

constexpr const char* kColourList[] = {"red", "green"};

TEST(EnumNamesTest, ANameListNamesTheValuesInTheirOrder) {
  // The list's names are the table's; blue, past the list, has none.
  for (Colour colour : {Colour::kRed, Colour::kGreen}) {
    const char* name = EnumToString(kColourList, colour);
    EXPECT_STREQ(name, EnumToString(kColourNames, colour));
    Colour read = Colour::kBlue;
    ASSERT_TRUE(StringToEnum(kColourList, name, &read)) << name;
    EXPECT_EQ(read, colour) << name;
  }
  EXPECT_STREQ(EnumToString(kColourList, Colour::kBlue), "unknown");
  EXPECT_STREQ(EnumToString(kColourList, static_cast<Colour>(-1), "none"),
               "none");
  Colour untouched = Colour::kBlue;
  for (const char* bad : {"Green", "gree", "green ", "", "blue", "unknown"}) {
    EXPECT_FALSE(StringToEnum(kColourList, bad, &untouched)) << bad;
  }
  EXPECT_EQ(untouched, Colour::kBlue);
}

// The same for an enum whose names are listed in its order (EnumName
// lists, core/enum_name_list.h): `names[i]` is the name of value i.
template <typename Enum>
void ExpectNamesInOrder(const char* (*to_string)(Enum),
                        bool (*from_string)(const std::string&, Enum*),
                        std::initializer_list<const char*> names) {
  std::vector<Enum> values;
  for (size_t i = 0; i < names.size(); ++i) {
    values.push_back(static_cast<Enum>(i));
  }
  EXPECT_STREQ(to_string(static_cast<Enum>(names.size())), "unknown");
  ExpectNames(to_string, from_string, values, names);
}

TEST(EnumNamesTest, TheUpperLayersEnumsKeepTheirNames) {
  ExpectNamesInOrder(
      CalibrationStageToString, StringToCalibrationStage,
      {"options", "split", "registration", "parameter_set", "identifiability",
       "baseline", "model_selection", "term_selection", "fit", "validation",
       "learned_residual", "done"});
  EXPECT_STREQ(CalibrationStageToString(CalibrationStage::kDone), "done");
  ExpectNamesInOrder(BeforeBaselineToString, StringToBeforeBaseline,
                     {"auto", "training", "refit", "none"});
  EXPECT_STREQ(BeforeBaselineToString(BeforeBaseline::kNone), "none");
  ExpectNamesInOrder(Iso9283RegistrationToString, StringToIso9283Registration,
                     {"robot", "file"});
  EXPECT_STREQ(Iso9283RegistrationToString(Iso9283Registration::kFile), "file");
  ExpectNamesInOrder(
      DesignAlgorithmToString, StringToDesignAlgorithm,
      {"eae", "random", "fedorov", "detmax", "greedy", "approx"});
  EXPECT_STREQ(DesignAlgorithmToString(DesignAlgorithm::kApprox), "approx");
  ExpectNamesInOrder(DesignCriterionToString, StringToDesignCriterion,
                     {"det", "svd", "task_rms"});
  EXPECT_STREQ(DesignCriterionToString(DesignCriterion::kTaskRms), "task_rms");
  ExpectNamesInOrder(MeasureStatusToString, StringToMeasureStatus,
                     {"ok", "not_visible", "unreachable", "error"});
  EXPECT_STREQ(MeasureStatusToString(MeasureStatus::kError), "error");
  // Names without a reading back.
  EXPECT_STREQ(DeviceTypeName(DeviceType::kLaserTracker), "laser_tracker");
  EXPECT_STREQ(DeviceTypeName(DeviceType::kMocap), "mocap");
  EXPECT_STREQ(DeviceTypeName(DeviceType::kCamera), "camera");
  EXPECT_STREQ(ShapeTypeName(ShapeType::kBox), "box");
  EXPECT_STREQ(ShapeTypeName(ShapeType::kCylinder), "cylinder");
  EXPECT_STREQ(ShapeTypeName(ShapeType::kCapsule), "capsule");
  EXPECT_STREQ(ShapeTypeName(ShapeType::kSphere), "sphere");
  EXPECT_STREQ(ShapeTypeName(ShapeType::kMesh), "mesh");
}

// The pools and the garbage kinds a user names are fewer than those named.
TEST(EnumNamesTest, SomeNamedValuesAreNotReadBack) {
  // A CSV pool is named by its path, a pool in memory is given.
  const char* const pools[] = {"lattice",    "sobol", "random",
                               "measurable", "csv",   "poses"};
  for (int i = 0; i < 6; ++i) {
    const auto pool = static_cast<SelectPool>(i);
    EXPECT_STREQ(SelectPoolToString(pool), pools[i]);
    const bool read_back =
        pool != SelectPool::kCsv && pool != SelectPool::kPoses;
    SelectPool read = SelectPool::kLattice;
    EXPECT_EQ(StringToSelectPool(pools[i], &read), read_back) << pools[i];
    EXPECT_EQ(read, read_back ? pool : SelectPool::kLattice) << pools[i];
  }
  const char* const garbage[] = {
      "none",          "not_json",       "nan",  "wrong_id", "wrong_joints",
      "wrong_markers", "unknown_status", "hang", "exit",     "line"};
  for (int i = 0; i < 10; ++i) {
    const auto kind = static_cast<DriverGarbage>(i);
    EXPECT_STREQ(DriverGarbageToString(kind), garbage[i]);
    DriverGarbage read = DriverGarbage::kNone;
    const bool asked =
        kind != DriverGarbage::kNone && kind != DriverGarbage::kLine;
    EXPECT_EQ(StringToDriverGarbage(garbage[i], &read), asked) << garbage[i];
    EXPECT_EQ(read, asked ? kind : DriverGarbage::kNone) << garbage[i];
  }
}

}  // namespace
}  // namespace activecal
