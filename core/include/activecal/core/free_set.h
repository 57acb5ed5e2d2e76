// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The free set: which parameters of a robot model a calibration estimates,
// as a value.
//
// A RobotModel carries the free flags its file gives (RobotModel::IsFree).
// Every step that chooses parameters (a named parameter set, the reduction
// to what the data separate, the auto-fix, model selection, the pool's
// identifiability check) takes the model as const and returns a FreeSet,
// with what it held fixed as HeldParameter values; WithFreeSet makes the
// model a fit runs on. Nothing narrows a model's flags in place.
//
//   FreeSet free(model);                    // the file's flags
//   free.Set(model.ParameterIndex("L2.d"), false);
//   const RobotModel fitted = WithFreeSet(model, free);
//
// Indices are into the full parameter vector (RobotModel::nominal order).

#ifndef ACTIVECAL_CORE_FREE_SET_H_
#define ACTIVECAL_CORE_FREE_SET_H_

#include <string>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

class FreeSet {
 public:
  FreeSet() = default;
  // The free flags of `model`.
  explicit FreeSet(const RobotModel& model);
  // Every one of num_parameters parameters fixed.
  static FreeSet None(int num_parameters);

  int num_parameters() const { return static_cast<int>(free_.size()); }
  bool Contains(int parameter_index) const { return free_[parameter_index]; }
  void Set(int parameter_index, bool free) { free_[parameter_index] = free; }
  // The number of free parameters.
  int size() const;
  bool empty() const { return size() == 0; }
  // The free parameters' indices, ascending (free-parameter order).
  std::vector<int> Indices() const;

  bool operator==(const FreeSet& other) const { return free_ == other.free_; }
  bool operator!=(const FreeSet& other) const { return free_ != other.free_; }

 private:
  std::vector<bool> free_;
};

// A copy of `model` whose free flags are `free` (free.num_parameters() must
// be model.num_parameters()).
RobotModel WithFreeSet(const RobotModel& model, const FreeSet& free);

// The step that held a parameter fixed.
enum class HoldStage {
  kParameterSet,    // the named set reduced to what the data separate
  kAutoFix,         // auto-fix: not identifiable from the data
  kModelSelection,  // model selection: the held-out error did not support it
};
// "parameter_set", "auto_fix", "model_selection".
const char* HoldStageToString(HoldStage stage);
bool StringToHoldStage(const std::string& text, HoldStage* stage);

// A parameter a step held at its value, and why.
struct HeldParameter {
  std::string name;    // "shoulder_pan_joint.rx"
  std::string reason;  // "a combination of B.rx, B.ry (residual 2e-16)"
  HoldStage stage = HoldStage::kParameterSet;
};

// The names of `held`, in order.
std::vector<std::string> HeldNames(const std::vector<HeldParameter>& held);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_FREE_SET_H_
