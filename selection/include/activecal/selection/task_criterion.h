// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The task-accuracy criterion (I-optimality): how well a design predicts
// the robot's position where it will work.
//
// With M = M0 + sum_{i in design} X_i^T X_i the information matrix of the
// design (M0: the information of poses already measured, the prior) and
// J_x the 3 position rows of the Jacobian at task pose x, the covariance of
// the identified parameters is sigma^2 M^-1 and the predicted RMS position
// error over the task poses is
//
//   rms = sigma * sqrt(mean_x tr(J_x M^-1 J_x^T))
//       = sigma * sqrt(tr(W M^-1)),      W = mean_x J_x^T J_x.
//
// phi = tr(W M^-1) is the criterion (dimensionless: rms in units of sigma).
// W = I gives the A-criterion. Measurements of unequal precision enter
// through their rows: a block scaled by sigma / sigma_i (whitened to the
// reference sigma) counts as it should.
//
// Adding a block X (t rows) changes V = M^-1 by a rank-t update, and
//
//   add X:     phi' = phi - tr((I + A_x)^-1 B_x)
//   remove Y:  phi' = phi + tr((I - A_y)^-1 B_y)
//
// with A_i = X_i V X_i^T and B_i = X_i V W V X_i^T (t x t). A swap (add x,
// then remove y) needs D = X V Y^T and E = X V W V Y^T:
//
//   A_y' = A_y - D^T S^-1 D,   S = I + A_x
//   B_y' = B_y - E^T S^-1 D - D^T S^-1 E + D^T S^-1 B_x S^-1 D
//   phi' = phi - tr(S^-1 B_x) + tr((I - A_y')^-1 B_y').
//
// Given V W V (once per design) every candidate costs O(t p^2), every pair
// O(t^2 p) more. TaskDesign keeps V current through InformationMatrix
// (refreshed from M by Cholesky every refresh_interval() updates) and
// recomputes phi = tr(W V) after every change.

#ifndef ACTIVECAL_SELECTION_TASK_CRITERION_H_
#define ACTIVECAL_SELECTION_TASK_CRITERION_H_

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/types.h"
#include "activecal/selection/information_matrix.h"

namespace activecal {

// W = mean over the task poses of J_x^T J_x (p x p), from the task poses'
// position Jacobian blocks (a pool whose blocks are the task poses; its
// parameters must be the design pool's).
Eigen::MatrixXd TaskMatrix(const CandidatePool& task_poses);

// sigma * sqrt(phi): the predicted RMS position error (m for sigma in m).
inline double PredictedTaskRms(double phi, double sigma_m) {
  return sigma_m * std::sqrt(phi);
}

// phi = tr(W (M0 + sum X_i^T X_i)^-1) recomputed from scratch (Cholesky);
// +infinity when M is singular. prior_rows (may be empty, 0 rows): the
// stacked whitened rows of the poses already measured, M0 = R^T R.
double TaskCriterionFromScratch(const CandidatePool& pool,
                                const Eigen::MatrixXd& W,
                                const RowMatrixXd& prior_rows,
                                const std::vector<int64_t>& design);

// A design with V = M^-1 and phi kept current, and the changes of phi for
// adding, removing and swapping poses by the formulas above.
class TaskDesign {
 public:
  // An empty design over `pool` (which must outlive it) with the prior
  // rows. ridge > 0 adds ridge * I to M (a start that is still singular).
  TaskDesign(const CandidatePool& pool, const Eigen::MatrixXd& W,
             const RowMatrixXd& prior_rows, double ridge = 0.0);

  const std::vector<int64_t>& poses() const { return poses_; }
  int size() const { return static_cast<int>(poses_.size()); }
  bool Contains(int64_t pose) const { return member_[pose] != 0; }
  bool positive_definite() const { return info_.positive_definite(); }
  // phi = tr(W V); +infinity while M is singular.
  double value() const { return value_; }
  double log_det() const { return info_.log_det(); }
  const Eigen::MatrixXd& inverse() const { return info_.inverse(); }
  // V W V, current with the design (valid when positive_definite()).
  const Eigen::MatrixXd& vwv() const { return vwv_; }

  // CHECK-fails for a pose already in the design.
  void Add(int64_t pose);
  // Refused (false) if M would stop being positive definite.
  bool Remove(int64_t pose);

  // The change of phi (negative: better) for adding a pose not in the
  // design, removing one in it (+infinity if M would become singular), and
  // adding `add` while removing `remove`. Require positive_definite().
  double AddChange(int64_t pose) const;
  double RemoveChange(int64_t pose) const;
  double SwapChange(int64_t add, int64_t remove) const;

  // A_i and B_i of every pool pose, in parallel (the result does not depend
  // on num_threads): a[i * t * t ...] column-major t x t blocks.
  void AllQuadraticForms(int num_threads, std::vector<double>* a,
                         std::vector<double>* b) const;

 private:
  void Update();

  const CandidatePool* pool_;
  Eigen::MatrixXd W_;
  std::vector<int64_t> poses_;
  std::vector<char> member_;
  InformationMatrix info_;
  Eigen::MatrixXd vwv_;
  double value_ = std::numeric_limits<double>::infinity();
};

// The change of phi for a swap from the t x t pieces (the formula above):
// Ax, Bx of the added pose, Ay, By of the removed one, D = X V Y^T,
// E = X V W V Y^T. +infinity when the result would be singular.
double TaskSwapChange(const Eigen::Ref<const Eigen::MatrixXd>& Ax,
                      const Eigen::Ref<const Eigen::MatrixXd>& Bx,
                      const Eigen::Ref<const Eigen::MatrixXd>& Ay,
                      const Eigen::Ref<const Eigen::MatrixXd>& By,
                      const Eigen::Ref<const Eigen::MatrixXd>& D,
                      const Eigen::Ref<const Eigen::MatrixXd>& E);

}  // namespace activecal

#endif  // ACTIVECAL_SELECTION_TASK_CRITERION_H_
