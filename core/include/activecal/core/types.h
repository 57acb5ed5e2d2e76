// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Common matrix types.

#ifndef ACTIVECAL_CORE_TYPES_H_
#define ACTIVECAL_CORE_TYPES_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>

#include "activecal/core/enum_name_list.h"

namespace activecal {

// Row-major dynamic matrix: stacked Jacobian blocks are contiguous per pose.
using RowMatrixXd =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowMatrixXf =
    Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Reports progress of long work: `done` of `total` units (poses, restarts,
// rounds). It may be called from several worker threads at once, so it must
// be thread-safe; it never changes a result. Empty: no reports.
using ProgressCallback = std::function<void(int64_t done, int64_t total)>;

// How an algorithm ended (after Ceres' TerminationType), in every Summary
// of the library: identification, Monte Carlo, every selection algorithm
// and the approximate design.
enum class TerminationType {
  // The algorithm reached its stopping rule (converged, a local optimum,
  // the tolerance); its results are complete.
  kConvergence,
  // An iteration bound stopped it first: the result returned is valid but
  // perhaps improvable (selection: a non-singular design of the requested
  // size; identification: the estimates so far, no covariance).
  kNoConvergence,
  // Valid input that cannot give an answer: too few equations,
  // unidentifiable parameters, a singular pool, a failed covariance.
  kFailure,
  // Invalid input: options, model, initial values, a measurement.
  kUserFailure,
};

// "CONVERGENCE", "NO_CONVERGENCE", "FAILURE", "USER_FAILURE".
inline const char* TerminationTypeToString(TerminationType type) {
  constexpr const char* kNames[] = {"CONVERGENCE", "NO_CONVERGENCE", "FAILURE",
                                    "USER_FAILURE"};
  return EnumToString(kNames, type, "UNKNOWN");
}

}  // namespace activecal

#endif  // ACTIVECAL_CORE_TYPES_H_
