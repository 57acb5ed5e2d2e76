// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The information matrix M = sum_i X_i^T X_i of a design, with its
// log-determinant and inverse V = M^-1 kept current as pose blocks are added
// and removed (matrix determinant lemma and Woodbury identity, O(t p^2) per
// update for a block of t rows):
//
//   add X:     log det(M + X^T X) = log det M + log det(I + X V X^T)
//   remove Y:  log det(M - Y^T Y) = log det M + log det(I - Y V Y^T)
//
// Every refresh_interval() updates, and whenever an update is badly
// conditioned, V and log det M are recomputed from M by Cholesky, so that
// rounding cannot build up. Log-determinants are natural logarithms.
//
// A matrix that is not positive definite (fewer independent rows than
// parameters) has log_det() = -infinity and no inverse; adds are still
// accepted and the inverse appears once M becomes positive definite. A
// ridge r > 0 adds r * I to M for regularised starts.

#ifndef ACTIVECAL_SELECTION_INFORMATION_MATRIX_H_
#define ACTIVECAL_SELECTION_INFORMATION_MATRIX_H_

#include <Eigen/Core>
#include <limits>

#include "activecal/core/types.h"

namespace activecal {

// log det of a symmetric matrix, or -infinity when it is not positive
// definite.
double LogDetSpd(const Eigen::Ref<const Eigen::MatrixXd>& S);

class InformationMatrix {
 public:
  using BlockRef = Eigen::Ref<const RowMatrixXd>;

  explicit InformationMatrix(int num_parameters, double ridge = 0.0);

  int num_parameters() const { return static_cast<int>(M_.rows()); }
  double ridge() const { return ridge_; }
  bool positive_definite() const { return positive_definite_; }
  // Natural log of det M; -infinity when M is not positive definite.
  double log_det() const {
    return positive_definite_ ? log_det_
                              : -std::numeric_limits<double>::infinity();
  }
  const Eigen::MatrixXd& matrix() const { return M_; }
  // V = M^-1; valid only when positive_definite().
  const Eigen::MatrixXd& inverse() const { return V_; }

  // M += X^T X.
  void Add(const BlockRef& X);
  // M -= Y^T Y, refused (returning false, nothing changed) when the result
  // would not be positive definite.
  bool Remove(const BlockRef& Y);

  // log det(I + X V X^T): the change of log det M if X were added.
  // Requires positive_definite().
  double AddGain(const BlockRef& X) const;
  // log det(I - Y V Y^T): the change if Y were removed; -infinity when the
  // result would not be positive definite. Requires positive_definite().
  double RemoveLoss(const BlockRef& Y) const;

  // Recomputes V and log det M from M.
  void Refresh();
  int refresh_interval() const { return refresh_interval_; }
  void set_refresh_interval(int n) { refresh_interval_ = n < 1 ? 1 : n; }

 private:
  Eigen::MatrixXd M_;
  Eigen::MatrixXd V_;
  double ridge_;
  double log_det_ = 0.0;
  bool positive_definite_ = false;
  int updates_since_refresh_ = 0;
  int refresh_interval_ = 50;
};

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_INFORMATION_MATRIX_H_
