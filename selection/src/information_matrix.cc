// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/selection/information_matrix.h"

#include <Eigen/Cholesky>
#include <cmath>

namespace activecal {
namespace {

constexpr double kNegInf = -std::numeric_limits<double>::infinity();
// An update whose determinant factor is below this (a removal taking away
// almost all information in some direction) is recomputed from scratch.
constexpr double kIllConditionedLogFactor = -20.0;
// A Cholesky pivot L_ii^2 below this fraction of M_ii means column i is (to
// rounding) a combination of the columns before it: M is singular. The test
// is invariant to column scaling, as the D-criterion is.
constexpr double kRelativePivotTolerance = 1e-10;
constexpr double kEmptyColumnTolerance = 1e-14;

bool PivotsPositive(const Eigen::Ref<const Eigen::MatrixXd>& M,
                    const Eigen::Ref<const Eigen::MatrixXd>& llt) {
  // A column with (to rounding) no information at all is singular too,
  // whatever its pivot: compare with the best-informed column.
  const double max_diag = M.diagonal().maxCoeff();
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    if (!(M(i, i) > kEmptyColumnTolerance * max_diag)) return false;
  }
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    const double pivot = llt(i, i) * llt(i, i);
    if (!(pivot > kRelativePivotTolerance * M(i, i))) return false;
  }
  return true;
}

}  // namespace

double LogDetSpd(const Eigen::Ref<const Eigen::MatrixXd>& S) {
  const Eigen::Index n = S.rows();
  if (n == 1) return S(0, 0) > 0 ? std::log(S(0, 0)) : kNegInf;
  if (n == 3) {
    // Sylvester's criterion, then the determinant.
    const double a = S(0, 0), b = S(0, 1), c = S(0, 2);
    const double d = S(1, 1), e = S(1, 2), f = S(2, 2);
    const double m2 = a * d - b * b;
    const double det =
        a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d);
    if (!(a > 0 && m2 > 0 && det > 0)) return kNegInf;
    return std::log(det);
  }
  Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success || !PivotsPositive(S, llt.matrixLLT())) {
    return kNegInf;
  }
  return 2.0 * llt.matrixLLT().diagonal().array().log().sum();
}

InformationMatrix::InformationMatrix(int num_parameters, double ridge)
    : M_(ridge * Eigen::MatrixXd::Identity(num_parameters, num_parameters)),
      V_(Eigen::MatrixXd::Zero(num_parameters, num_parameters)),
      ridge_(ridge) {
  if (ridge > 0) Refresh();
}

void InformationMatrix::Refresh() {
  Eigen::LLT<Eigen::MatrixXd> llt(M_);
  const Eigen::VectorXd diag = llt.matrixLLT().diagonal();
  positive_definite_ =
      llt.info() == Eigen::Success && PivotsPositive(M_, llt.matrixLLT());
  updates_since_refresh_ = 0;
  if (!positive_definite_) return;
  log_det_ = 2.0 * diag.array().log().sum();
  V_ = llt.solve(Eigen::MatrixXd::Identity(M_.rows(), M_.cols()));
  V_ = 0.5 * (V_ + V_.transpose()).eval();
}

void InformationMatrix::Add(const BlockRef& X) {
  M_.noalias() += X.transpose() * X;
  if (!positive_definite_) {
    Refresh();
    return;
  }
  const Eigen::MatrixXd W = V_ * X.transpose();  // p x t
  Eigen::MatrixXd S = X * W;                     // t x t
  S.diagonal().array() += 1.0;
  Eigen::LLT<Eigen::MatrixXd> llt(S);
  log_det_ += LogDetSpd(S);
  V_.noalias() -= W * llt.solve(W.transpose());
  if (++updates_since_refresh_ >= refresh_interval_) Refresh();
}

bool InformationMatrix::Remove(const BlockRef& Y) {
  if (!positive_definite_) return false;
  const Eigen::MatrixXd W = V_ * Y.transpose();
  Eigen::MatrixXd S = -(Y * W);
  S.diagonal().array() += 1.0;
  const double factor = LogDetSpd(S);
  if (factor < kIllConditionedLogFactor) {
    // Too close to singular for the update formula to be trusted: decide
    // from the matrix itself.
    const Eigen::MatrixXd before = M_;
    M_.noalias() -= Y.transpose() * Y;
    Refresh();
    if (!positive_definite_) {
      M_ = before;
      Refresh();
      return false;
    }
    return true;
  }
  M_.noalias() -= Y.transpose() * Y;
  log_det_ += factor;
  Eigen::LLT<Eigen::MatrixXd> llt(S);
  V_.noalias() += W * llt.solve(W.transpose());
  if (++updates_since_refresh_ >= refresh_interval_) Refresh();
  return true;
}

double InformationMatrix::AddGain(const BlockRef& X) const {
  Eigen::MatrixXd S = X * V_ * X.transpose();
  S.diagonal().array() += 1.0;
  return LogDetSpd(S);
}

double InformationMatrix::RemoveLoss(const BlockRef& Y) const {
  Eigen::MatrixXd S = -(Y * V_ * Y.transpose());
  S.diagonal().array() += 1.0;
  return LogDetSpd(S);
}

}  // namespace activecal
