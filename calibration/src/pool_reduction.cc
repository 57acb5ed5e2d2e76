// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/pool_reduction.h"

#include <algorithm>
#include <utility>

#include "activecal/core/joint_sampling.h"
#include "activecal/estimation/parameter_reduction.h"

namespace activecal {
namespace {

Eigen::MatrixXd Sample(const Eigen::MatrixXd& rows,
                       const PoolReductionOptions& options) {
  if (!options.evenly_spaced) return SubsampleRows(rows, options.sample_size);
  const Eigen::Index n = std::min<Eigen::Index>(
      rows.rows(), std::max<int64_t>(1, options.sample_size));
  Eigen::MatrixXd sample(n, rows.cols());
  for (Eigen::Index i = 0; i < n; ++i) {
    sample.row(i) = rows.row(i * rows.rows() / n);
  }
  return sample;
}

}  // namespace

bool ReduceForPool(const RobotModel& model, ParameterSet set,
                   const Eigen::MatrixXd& joints,
                   const std::vector<uint32_t>* seen_masks,
                   const PoolReductionOptions& options, PoolReduction* result) {
  *result = PoolReduction();
  std::vector<Measurement> plan;
  uint32_t seen_anywhere = 0;
  if (seen_masks == nullptr) {
    plan = MeasurementPlan(Sample(joints, options), options.type);
  } else {
    if (seen_masks->size() != static_cast<size_t>(joints.rows())) {
      result->message = std::to_string(seen_masks->size()) +
                        " marker masks for " + std::to_string(joints.rows()) +
                        " poses";
      return false;
    }
    for (uint32_t mask : *seen_masks) seen_anywhere |= mask;
    // The markers seen at each sampled pose: the mask rides along as a
    // last column through the subsample.
    const int n = static_cast<int>(joints.cols());
    Eigen::MatrixXd tagged(joints.rows(), n + 1);
    tagged.leftCols(n) = joints;
    for (size_t i = 0; i < seen_masks->size(); ++i) {
      tagged(i, n) = (*seen_masks)[i];
    }
    const Eigen::MatrixXd sample = Sample(tagged, options);
    for (Eigen::Index i = 0; i < sample.rows(); ++i) {
      const uint32_t mask = static_cast<uint32_t>(sample(i, n));
      for (int k = 0; k < model.num_markers() && k < 32; ++k) {
        if (!(mask & (1u << k))) continue;
        Measurement m;
        m.type = options.type;
        m.joints = sample.row(i).head(n).transpose();
        m.marker = k;
        plan.push_back(std::move(m));
      }
    }
  }
  result->point = model.nominal;
  std::string error;
  if (!ReduceParameterSet(model, set, plan, options.rotation_weight_m_per_rad,
                          &result->point, &result->free, &result->held,
                          &error)) {
    result->message = error;
    return false;
  }
  if (seen_masks != nullptr) {
    // A marker never seen: say so rather than "has no effect".
    for (HeldParameter& h : result->held) {
      const int index = model.ParameterIndex(h.name);
      if (index < 0) continue;
      const int block = model.BlockOf(index);
      if (!model.is_marker_block(block)) continue;
      const int k = block - model.marker_block(0);
      if (k < 32 && (seen_anywhere & (1u << k))) continue;
      h.reason = "marker '" + model.markers[k].name +
                 "' is seen at none of the " + std::to_string(joints.rows()) +
                 " poses of the pool";
    }
  }
  return true;
}

std::string HeldFixedLines(ParameterSet set,
                           const std::vector<HeldParameter>& held) {
  std::string lines;
  for (const HeldParameter& d : held) {
    lines += "  --parameter_set=" + std::string(ParameterSetToString(set)) +
             ": " + d.name + " held fixed: " + d.reason + "\n";
  }
  return lines;
}

bool ReduceModelForPool(ParameterSet set, const Eigen::MatrixXd& joints,
                        const std::vector<uint32_t>* seen_masks,
                        RobotModel* model, std::string* report,
                        std::string* error, PoolReduction* reduction) {
  PoolReductionOptions options;
  options.evenly_spaced = true;
  PoolReduction local;
  PoolReduction& r = reduction ? *reduction : local;
  if (!ReduceForPool(*model, set, joints, seen_masks, options, &r)) {
    *error = "--parameter_set=" + std::string(ParameterSetToString(set)) +
             ": " + r.message;
    return false;
  }
  *report += HeldFixedLines(set, r.held);
  *model = WithFreeSet(*model, r.free);
  return true;
}

}  // namespace activecal
