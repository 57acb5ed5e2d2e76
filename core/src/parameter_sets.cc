#include "activecal/core/parameter_sets.h"

#include "activecal/core/random.h"

namespace activecal {

const char* ParameterSetName(ParameterSet set) {
  switch (set) {
    case ParameterSet::kRegistration:
      return "registration";
    case ParameterSet::kOffsets:
      return "offsets";
    case ParameterSet::kFull:
      return "full";
    case ParameterSet::kFile:
      return "file";
  }
  return "unknown";
}

bool ParseParameterSet(const std::string& name, ParameterSet* set) {
  for (ParameterSet s : {ParameterSet::kRegistration, ParameterSet::kOffsets,
                         ParameterSet::kFull, ParameterSet::kFile}) {
    if (name == ParameterSetName(s)) {
      *set = s;
      return true;
    }
  }
  return false;
}

void ApplyParameterSet(ParameterSet set, bool with_orientation,
                       RobotModel* model) {
  if (set == ParameterSet::kFile) return;
  const bool offsets = set != ParameterSet::kRegistration;
  const bool full = set == ParameterSet::kFull;
  if (model->base.convention == LinkConvention::kFrame) {
    model->base.free.fill(false);
    for (int j = 0; j < 6; ++j) model->base.free[j] = true;
  }
  for (Link& l : model->links) {
    l.free.fill(false);
    if (l.convention == LinkConvention::kUrdf) {
      l.free[kUrdfOffset] = offsets;
      for (int j = kUrdfX; j <= kUrdfRz; ++j) l.free[j] = full;
    } else {
      const bool revolute = l.joint_type == JointType::kRevolute;
      l.free[kGamma] = full || (offsets && revolute);
      l.free[kD] = full || (offsets && !revolute);
      l.free[kAlpha] = l.free[kA] = full;
      l.free[kBeta] = full && l.convention == LinkConvention::kHayati;
    }
  }
  for (Marker& m : model->markers) {
    m.free.fill(false);
    for (int j = 0; j < 3; ++j) m.free[j] = true;
    for (int j = 3; j < 6; ++j) m.free[j] = with_orientation;
  }
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

}  // namespace activecal
