// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/parameter_sets.h"

#include "activecal/core/enum_name_list.h"
#include "activecal/core/random.h"

namespace activecal {

constexpr const char* kParameterSetNames[] = {"registration", "offsets", "full",
                                              "file"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(ParameterSet, kParameterSetNames)

FreeSet ParameterSetFreeSet(const RobotModel& model, ParameterSet set,
                            bool with_orientation) {
  if (set == ParameterSet::kFile) return FreeSet(model);
  const bool offsets = set != ParameterSet::kRegistration;
  const bool full = set == ParameterSet::kFull;
  FreeSet free = FreeSet::None(model.num_parameters());
  auto set_block = [&](int block, int within, bool value) {
    free.Set(model.block_offset(block) + within, value);
  };
  if (model.base.convention == LinkConvention::kFrame) {
    for (int j = 0; j < 6; ++j) set_block(0, j, true);
  } else {
    // Another base keeps its flags as the file has them.
    for (int j = 0; j < model.block_size(0); ++j) {
      set_block(0, j, model.IsFree(model.block_offset(0) + j));
    }
  }
  for (int b = 1; b <= model.num_joints(); ++b) {
    const Link& l = model.link(b);
    if (l.convention == LinkConvention::kUrdf) {
      set_block(b, kUrdfOffset, offsets);
      for (int j = kUrdfX; j <= kUrdfRz; ++j) set_block(b, j, full);
    } else {
      const bool revolute = l.joint_type == JointType::kRevolute;
      set_block(b, kGamma, full || (offsets && revolute));
      set_block(b, kD, full || (offsets && !revolute));
      set_block(b, kAlpha, full);
      set_block(b, kA, full);
      if (l.convention == LinkConvention::kHayati) set_block(b, kBeta, full);
    }
  }
  for (int k = 0; k < model.num_markers(); ++k) {
    const int b = model.marker_block(k);
    for (int j = 0; j < 3; ++j) set_block(b, j, true);
    for (int j = 3; j < model.block_size(b); ++j) {
      set_block(b, j, with_orientation);
    }
  }
  return free;
}

Eigen::VectorXd GenericPoint(const RobotModel& model,
                             const Eigen::VectorXd& parameters) {
  Random random(0x5eed);
  Eigen::VectorXd p = parameters;
  for (int i : model.FreeParameterIndices()) {
    if (!model.is_marker_block(model.BlockOf(i))) continue;
    // 1 mm or 1 mrad: one scale in SI units.
    p[i] += 1e-3 * random.Gaussian();
  }
  return p;
}

bool ParseParameterSet(const std::string& text, bool urdf_robot,
                       ParameterSet* set, std::string* error) {
  *set = urdf_robot ? ParameterSet::kFull : ParameterSet::kFile;
  if (text.empty() || StringToParameterSet(text, set)) return true;
  *error = "parameter_set must be registration, offsets, full or file, got '" +
           text + "'";
  return false;
}

}  // namespace activecal
