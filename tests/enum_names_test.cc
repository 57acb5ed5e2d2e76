// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The enum name tables (core/enum_names.h): EnumToString and StringToEnum
// on a table, and the XToString/StringToX pairs the layers define with
// ACTIVECAL_ENUM_STRING_FUNCTIONS: every name as it was spelled before the
// tables, a round trip, a name that is not one.

#include "activecal/core/enum_names.h"

#include <gtest/gtest.h>

#include <string>

#include "activecal/cell/cell_checker.h"
#include "activecal/core/free_set.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/learned_residual.h"
#include "activecal/estimation/model_selection.h"
#include "activecal/io/controller_programs.h"

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
                 std::initializer_list<Enum> values,
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

}  // namespace
}  // namespace activecal
