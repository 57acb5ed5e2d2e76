// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/parameter_reduction.h"

#include <glog/logging.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "activecal/residuals/jacobians.h"

namespace activecal {

std::vector<int> ReductionPriority(const RobotModel& model) {
  std::vector<int> order;
  auto add_block = [&](int b, const std::vector<int>& within) {
    const int offset = model.block_offset(b);
    for (int j : within) {
      if (model.IsFree(offset + j)) order.push_back(offset + j);
    }
  };
  auto all = [&](int b) {
    std::vector<int> v(model.block_size(b));
    std::iota(v.begin(), v.end(), 0);
    return v;
  };
  add_block(0, all(0));
  for (int k = 0; k < model.num_markers(); ++k) {
    add_block(model.marker_block(k), all(model.marker_block(k)));
  }
  for (int b = 1; b <= model.num_joints(); ++b) {
    const Link& l = model.link(b);
    std::vector<int> within = all(b);
    // The joint offset first.
    // (Two enums of block indices: compared as the ints they index with.)
    const int offset =
        l.convention == LinkConvention::kUrdf   ? static_cast<int>(kUrdfOffset)
        : l.joint_type == JointType::kPrismatic ? static_cast<int>(kD)
                                                : static_cast<int>(kGamma);
    within.erase(std::find(within.begin(), within.end(), offset));
    within.insert(within.begin(), offset);
    add_block(b, within);
  }
  return order;
}

FreeSet ReduceToIdentifiable(const RobotModel& model,
                             const Eigen::MatrixXd& jacobian, double tolerance,
                             std::vector<HeldParameter>* held) {
  CHECK(held != nullptr);
  const std::vector<int> free = model.FreeParameterIndices();
  CHECK_EQ(jacobian.cols(), static_cast<int>(free.size()));
  const std::vector<std::string> names = model.ParameterNames();
  held->clear();
  const double longest =
      jacobian.cols() ? jacobian.colwise().norm().maxCoeff() : 0.0;
  std::vector<int> kept_columns;  // into jacobian
  Eigen::MatrixXd basis(jacobian.rows(), 0);
  FreeSet kept(model);
  for (int parameter : ReductionPriority(model)) {
    const int c = static_cast<int>(
        std::find(free.begin(), free.end(), parameter) - free.begin());
    const double norm = jacobian.col(c).norm();
    if (!(norm > kNoEffectRelativeNorm * longest)) {
      held->push_back({names[parameter], "has no effect on these measurements",
                       HoldStage::kParameterSet});
      kept.Set(parameter, false);
      continue;
    }
    Eigen::VectorXd r = jacobian.col(c) / norm;
    // Twice-repeated Gram-Schmidt against the kept directions.
    for (int pass = 0; pass < 2; ++pass) {
      r -= basis * (basis.transpose() * r);
    }
    const double rest = r.norm();
    if (rest > tolerance) {
      basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
      basis.col(basis.cols() - 1) = r / rest;
      kept_columns.push_back(c);
      continue;
    }
    // Which kept parameters explain it: least-squares coefficients on the
    // kept unit columns, largest first.
    Eigen::MatrixXd K(jacobian.rows(), kept_columns.size());
    for (size_t k = 0; k < kept_columns.size(); ++k) {
      K.col(k) = jacobian.col(kept_columns[k]).normalized();
    }
    const Eigen::VectorXd a =
        K.colPivHouseholderQr().solve(jacobian.col(c) / norm);
    std::vector<int> by(a.size());
    std::iota(by.begin(), by.end(), 0);
    std::stable_sort(by.begin(), by.end(), [&](int x, int y) {
      return std::abs(a[x]) > std::abs(a[y]);
    });
    std::ostringstream reason;
    reason << "a combination of";
    int listed = 0;
    for (int k : by) {
      if (listed == 4 || std::abs(a[k]) < 0.05 * std::abs(a[by[0]])) break;
      reason << (listed ? ", " : " ") << names[free[kept_columns[k]]];
      ++listed;
    }
    reason.precision(1);
    reason << " (residual " << std::scientific << rest << ")";
    held->push_back({names[parameter], reason.str(), HoldStage::kParameterSet});
    kept.Set(parameter, false);
  }
  return kept;
}

bool ReduceParameterSet(const RobotModel& model, ParameterSet set,
                        const std::vector<Measurement>& measurements,
                        double rotation_weight_m_per_rad,
                        Eigen::VectorXd* point, FreeSet* free,
                        std::vector<HeldParameter>* held, std::string* error) {
  CHECK(point != nullptr);
  CHECK(free != nullptr);
  CHECK(held != nullptr);
  held->clear();
  bool with_orientation = false;
  for (const Measurement& m : measurements) {
    with_orientation |= m.type == MeasurementType::kPose;
  }
  *free = ParameterSetFreeSet(model, set, with_orientation);
  if (free->empty()) {
    if (error) {
      *error =
          "nothing to identify: no parameter is free (choose a parameter set "
          "registration, offsets or full, or mark parameters free in the "
          "robot file)";
    }
    return false;
  }
  if (set == ParameterSet::kFile) return true;
  const RobotModel named = WithFreeSet(model, *free);
  const Eigen::VectorXd given = *point;
  // The reduction is done where the fit will be. Only a marker guessed at
  // the tip frame's origin (the default, which says nothing about the end
  // effector) moves to the generic point: there, on the last joint's axis,
  // that joint's rotations look like they have no effect, which they have
  // on a real end effector. A marker given anywhere else is where the fit
  // starts and where its truth is: reduced there, a marker on the flange
  // axis drops the combinations that are degenerate on the axis instead of
  // keeping them for a fit that cannot separate them.
  Eigen::VectorXd at = GenericPoint(named, given);
  for (int k = 0; k < named.num_markers(); ++k) {
    const int offset = named.block_offset(named.marker_block(k));
    if (!given.segment(offset, 3).isZero(0)) {
      at.segment(offset, kMarkerBlockSize) =
          given.segment(offset, kMarkerBlockSize);
    }
  }
  Eigen::MatrixXd J;
  if (!StackedJacobian(named, at, measurements, rotation_weight_m_per_rad, &J,
                       error)) {
    return false;
  }
  *free = ReduceToIdentifiable(named, J, kRedundancyTolerance, held);
  // What is held keeps exactly the value it was given; only parameters the
  // fit will estimate start from the generic point.
  for (int i = 0; i < named.num_parameters(); ++i) {
    if (!free->Contains(i)) at[i] = given[i];
  }
  *point = at;
  return true;
}

}  // namespace activecal
