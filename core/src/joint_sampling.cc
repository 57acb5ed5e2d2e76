// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/joint_sampling.h"

#include <algorithm>
#include <boost/random/sobol.hpp>
#include <cmath>
#include <vector>

#include "activecal/core/random.h"

namespace activecal {

bool JointSamplingFromString(const std::string& name, JointSampling* sampling) {
  if (name == "sobol") {
    *sampling = JointSampling::kSobol;
  } else if (name == "random") {
    *sampling = JointSampling::kRandom;
  } else {
    return false;
  }
  return true;
}

bool PoolJointRange(const RobotModel& model, int j, double* low, double* width,
                    bool* one_turn, std::string* why) {
  const Link& link = model.links[j];
  const bool lo = std::isfinite(link.joint_min);
  const bool hi = std::isfinite(link.joint_max);
  if (link.joint_type != JointType::kRevolute) {
    if (!lo || !hi) {
      if (why) {
        *why = "joint " + std::to_string(j + 1) + " (" + link.name +
               ") has no finite range to sample";
      }
      return false;
    }
    *low = link.joint_min;
    *width = link.joint_max - link.joint_min;
    *one_turn = false;
    return true;
  }
  if (lo && hi && link.joint_max - link.joint_min < 2 * M_PI) {
    *low = link.joint_min;
    *width = link.joint_max - link.joint_min;
    *one_turn = false;
    return true;
  }
  // One turn: a value and itself + 2 pi are the same pose.
  *low = lo ? link.joint_min : hi ? link.joint_max - 2 * M_PI : -M_PI;
  *width = 2 * M_PI;
  *one_turn = true;
  return true;
}

bool SampleJointValues(const RobotModel& model, JointSampling sampling,
                       int64_t num_poses, uint64_t seed,
                       Eigen::MatrixXd* joints, std::string* error) {
  const int n = model.num_joints();
  if (num_poses < 1) {
    if (error) {
      *error = "pool size must be >= 1, got " + std::to_string(num_poses);
    }
    return false;
  }
  if (n < 1) {
    if (error) *error = "the model has no joints to sample";
    return false;
  }
  std::vector<double> low(n), width(n);
  for (int j = 0; j < n; ++j) {
    bool one_turn = false;
    if (!PoolJointRange(model, j, &low[j], &width[j], &one_turn, error)) {
      return false;
    }
  }
  joints->resize(num_poses, n);
  if (sampling == JointSampling::kRandom) {
    Random random(seed);
    for (int64_t i = 0; i < num_poses; ++i) {
      for (int j = 0; j < n; ++j) {
        (*joints)(i, j) = low[j] + width[j] * random.Uniform();
      }
    }
    return true;
  }
  // Sobol: 64-bit integer coordinates, XOR-shifted, top 53 bits -> [0, 1).
  // Boost's engine starts at the sequence's second point; the first (all
  // zero bits) is put back, so that the first 2^k points form a net (one
  // point in each of 2^k bins of every joint).
  boost::random::sobol engine(static_cast<std::size_t>(n));
  std::vector<uint64_t> shift(n);
  for (int j = 0; j < n; ++j) shift[j] = Random::StreamSeed(seed, j);
  for (int64_t i = 0; i < num_poses; ++i) {
    for (int j = 0; j < n; ++j) {
      const uint64_t point = i == 0 ? 0 : static_cast<uint64_t>(engine());
      const uint64_t bits = point ^ shift[j];
      const double u = std::ldexp(static_cast<double>(bits >> 11), -53);
      (*joints)(i, j) = low[j] + width[j] * u;
    }
  }
  return true;
}

Eigen::MatrixXd SubsampleRows(const Eigen::MatrixXd& rows, int64_t max_rows) {
  if (rows.rows() <= max_rows) return rows;
  Random random(0x5a3b1e);
  std::vector<int64_t> chosen = random.SampleWithoutReplacement(
      rows.rows(), std::max<int64_t>(1, max_rows));
  std::sort(chosen.begin(), chosen.end());
  Eigen::MatrixXd subset(chosen.size(), rows.cols());
  for (size_t i = 0; i < chosen.size(); ++i)
    subset.row(i) = rows.row(chosen[i]);
  return subset;
}

}  // namespace activecal
