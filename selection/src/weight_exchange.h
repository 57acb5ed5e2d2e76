// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The inner solver of the approximate D-optimal design: the weights on a
// working set of pose blocks, optimised by randomized exchanges (after
// Harman, Filova & Richtarik, "A randomized exchange algorithm for
// computing optimal approximate designs of experiments", JASA 2020, REX).
// Not installed.
//
// Each iteration recomputes M(w), V = M(w)^-1 and the variances
// d_k = tr(X_k V X_k^T) of the working set from the weights, stops if
// max_k d_k <= target, else moves weight by exact line search
//
//   1. from the support pose of least variance to the pose of largest
//      variance (the vertex exchange of Bohning 1986, which alone converges);
//   2. within random pairs of the support and the poses of largest
//      variance (each pair's variances read afresh from V, which follows
//      every step by a rank-2t update).
//
// A pair step costs O(p^2 t) against O(n t p t) for updating every
// variance of the working set, so an iteration makes many cheap steps
// between two recomputations. Every step increases log det M(w); the
// variances, V and the result are always recomputed from the weights.

#ifndef ACTIVECAL_SELECTION_SRC_WEIGHT_EXCHANGE_H_
#define ACTIVECAL_SELECTION_SRC_WEIGHT_EXCHANGE_H_

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "activecal/core/random.h"
#include "activecal/core/types.h"

namespace activecal {
namespace internal {

// M(w) of a weighted set of blocks and its inverse.
struct WeightedInformation {
  Eigen::MatrixXd M, V;
  double log_det = -std::numeric_limits<double>::infinity();
  // V and log_det from M; false (V untouched) if M is numerically
  // singular.
  bool Factor();
};

// The step alpha in [0, max_step] maximising
// f(alpha) = log det(M + alpha (A+ - A-)) - log det M
//          = log det(I + alpha S G),
// A+ = X+^T X+, A- = X-^T X-, G = [X+; X-] V [X+; X-]^T (2t x 2t),
// S = diag(I_t, -I_t), by safeguarded Newton steps on f' (which decreases
// in alpha). *det_ratio receives det(I + alpha S G) = det M' / det M.
double ExchangeStep(const Eigen::MatrixXd& G, int t, double max_step,
                    double* det_ratio);

// Work space of ExchangePair (no allocation per call once sized).
struct PairWorkspace {
  Eigen::MatrixXd U, VU, G, C, K;
};

// Moves weight between blocks a and b of Xw (t rows each) towards the one
// of larger variance under V, by ExchangeStep, and updates V = M(w)^-1 by
// the Woodbury formula. Returns false if no weight moved (equal
// variances, or the losing block has no weight).
bool ExchangePair(const RowMatrixXd& Xw, int t, int64_t a, int64_t b,
                  std::vector<double>* w, Eigen::MatrixXd* V,
                  PairWorkspace* work);

struct WeightExchangeOptions {
  double target = 0;       // stop when max_k d_k <= target
  int max_iterations = 0;  // recomputations of M(w)
  // Poses of largest variance joining the support in the random pairs.
  int num_top = 0;
};

// Optimises the weights w (>= 0, sum 1; M(w) non-singular) of the nw
// blocks of t rows of Xw. On return *info holds M(w) and V recomputed from
// the returned weights, *d their variances, *iterations the iterations
// made (added). If an iteration leaves M(w) numerically singular (to
// LogDetSpd's relative tests), stops on the weights before it and returns
// true: the caller's check judges them. Returns false with *error only if
// the starting M(w) is singular.
bool ExchangeWeights(const RowMatrixXd& Xw, int t,
                     const WeightExchangeOptions& options, Random* random,
                     std::vector<double>* w, WeightedInformation* info,
                     Eigen::VectorXd* d, int64_t* iterations,
                     std::string* error);

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_SRC_WEIGHT_EXCHANGE_H_
