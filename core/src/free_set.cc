// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/free_set.h"

#include <algorithm>

#include "activecal/core/enum_names.h"

namespace activecal {

FreeSet::FreeSet(const RobotModel& model) : free_(model.num_parameters()) {
  for (int i = 0; i < model.num_parameters(); ++i) free_[i] = model.IsFree(i);
}

FreeSet FreeSet::None(int num_parameters) {
  FreeSet set;
  set.free_.assign(num_parameters, false);
  return set;
}

int FreeSet::size() const {
  return static_cast<int>(std::count(free_.begin(), free_.end(), true));
}

std::vector<int> FreeSet::Indices() const {
  std::vector<int> indices;
  for (int i = 0; i < num_parameters(); ++i) {
    if (free_[i]) indices.push_back(i);
  }
  return indices;
}

RobotModel WithFreeSet(const RobotModel& model, const FreeSet& free) {
  RobotModel out = model;
  for (int i = 0; i < model.num_parameters(); ++i) {
    out.SetFree(i, free.Contains(i));
  }
  return out;
}

constexpr EnumName<HoldStage> kHoldStageNames[] = {
    {HoldStage::kParameterSet, "parameter_set"},
    {HoldStage::kAutoFix, "auto_fix"},
    {HoldStage::kModelSelection, "model_selection"}};
ACTIVECAL_ENUM_STRING_FUNCTIONS(HoldStage, kHoldStageNames)

std::vector<std::string> HeldNames(const std::vector<HeldParameter>& held) {
  std::vector<std::string> names;
  for (const HeldParameter& h : held) names.push_back(h.name);
  return names;
}

}  // namespace activecal
