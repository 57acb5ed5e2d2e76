// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Design criteria and observability indices.
//
// With sigma_1 >= ... >= sigma_L the non-zero singular values of the stacked
// m x p design matrix X (L = p for an identifiable design):
//
//   OI  (Sun & Hollerbach eq. 1)  (sigma_1 ... sigma_L)^(1/L) / L
//   OID                           det(X^T X) = prod sigma_i^2
//   O1  (Borm & Menq)             (sigma_1 ... sigma_L)^(1/L) / sqrt(m)
//   O2  (Driels & Pathre)         sigma_L / sigma_1
//   O3  (Nahvi et al.)            sigma_L
//   O4  (Nahvi & Hollerbach)      sigma_L^2 / sigma_1
//   O5  (Sun & Hollerbach)        1 / sum(1 / sigma_i)
//
// Only OI, OID and O1 are invariant to column scaling; the others are
// reported as computed on the unscaled matrix.

#ifndef ACTIVECAL_SELECTION_CRITERIA_H_
#define ACTIVECAL_SELECTION_CRITERIA_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "activecal/core/candidate_pool.h"

namespace activecal {

struct ObservabilityIndices {
  Eigen::VectorXd singular_values;  // descending
  int rank = 0;                     // non-zero singular values (L)
  double oi = 0.0;
  double log10_oid = 0.0;  // log10 det X^T X
  double o1 = 0.0, o2 = 0.0, o3 = 0.0, o4 = 0.0, o5 = 0.0;
};

// All indices from the SVD of a stacked design matrix.
ObservabilityIndices ComputeObservabilityIndices(const Eigen::MatrixXd& X);

// The paper's OI from the natural log det of X^T X, for p parameters.
double OiFromLogDet(double log_det, int num_parameters);
// And back.
double LogDetFromOi(double oi, int num_parameters);

// log det of the information matrix of a design, recomputed from scratch
// (sum of X_i^T X_i, Cholesky); -infinity when singular.
double LogDetFromScratch(const CandidatePool& pool,
                         const std::vector<int64_t>& design);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_CRITERIA_H_
