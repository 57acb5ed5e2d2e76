// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/selection/task_criterion.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "selection_internal.h"

namespace activecal {
namespace {

using internal::kInf;

// tr(S^-1 B) for a symmetric positive definite S; +infinity otherwise.
double TraceSolve(const Eigen::MatrixXd& S, const Eigen::MatrixXd& B) {
  if (LogDetSpd(S) == -kInf) return kInf;
  Eigen::LLT<Eigen::MatrixXd> llt(S);
  return llt.solve(B).trace();
}

}  // namespace

Eigen::MatrixXd TaskMatrix(const CandidatePool& task_poses) {
  CHECK_GT(task_poses.size(), 0) << "no task poses";
  Eigen::MatrixXd W;
  if (!task_poses.single_precision()) {
    const RowMatrixXd& J = task_poses.stacked();
    W = J.transpose() * J;
  } else {
    // Widened to double and summed chunk by chunk.
    const int p = task_poses.num_parameters();
    W = Eigen::MatrixXd::Zero(p, p);
    constexpr int64_t kChunk = 1 << 14;
    RowMatrixXd buffer;
    for (int64_t b = 0; b < task_poses.size(); b += kChunk) {
      const auto J =
          task_poses.Rows(b, std::min(kChunk, task_poses.size() - b), &buffer);
      W.noalias() += J.transpose() * J;
    }
  }
  W /= static_cast<double>(task_poses.size());
  return 0.5 * (W + W.transpose());
}

double TaskCriterionFromScratch(const CandidatePool& pool,
                                const Eigen::MatrixXd& W,
                                const RowMatrixXd& prior_rows,
                                const std::vector<int64_t>& design) {
  const int p = pool.num_parameters();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  if (prior_rows.rows() > 0) M.noalias() += prior_rows.transpose() * prior_rows;
  for (int64_t i : design) {
    const RowMatrixXd X = pool.ExactBlock(i);
    M.noalias() += X.transpose() * X;
  }
  if (LogDetSpd(M) == -kInf) return kInf;
  Eigen::LLT<Eigen::MatrixXd> llt(M);
  return llt.solve(W).trace();
}

double TaskSwapChange(const Eigen::Ref<const Eigen::MatrixXd>& Ax,
                      const Eigen::Ref<const Eigen::MatrixXd>& Bx,
                      const Eigen::Ref<const Eigen::MatrixXd>& Ay,
                      const Eigen::Ref<const Eigen::MatrixXd>& By,
                      const Eigen::Ref<const Eigen::MatrixXd>& D,
                      const Eigen::Ref<const Eigen::MatrixXd>& E) {
  Eigen::MatrixXd S = Ax;
  S.diagonal().array() += 1.0;
  Eigen::LLT<Eigen::MatrixXd> llt(S);
  const Eigen::MatrixXd SiD = llt.solve(D);  // S^-1 D
  const double add = -llt.solve(Bx).trace();
  Eigen::MatrixXd T = -Ay;
  T.noalias() += D.transpose() * SiD;
  T.diagonal().array() += 1.0;  // I - A_y'
  Eigen::MatrixXd By1 = By;
  By1.noalias() -= E.transpose() * SiD;
  By1.noalias() -= SiD.transpose() * E;
  By1.noalias() += SiD.transpose() * Bx * SiD;
  return add + TraceSolve(T, By1);
}

TaskDesign::TaskDesign(const CandidatePool& pool, const Eigen::MatrixXd& W,
                       const RowMatrixXd& prior_rows, double ridge)
    : pool_(&pool),
      W_(W),
      member_(pool.size(), 0),
      info_(pool.num_parameters(), ridge) {
  CHECK_EQ(W.rows(), pool.num_parameters());
  CHECK_EQ(W.cols(), pool.num_parameters());
  if (prior_rows.rows() > 0) {
    CHECK_EQ(prior_rows.cols(), pool.num_parameters());
    info_.Add(prior_rows);
    info_.Refresh();
  }
  Update();
}

void TaskDesign::Update() {
  if (!info_.positive_definite()) {
    value_ = kInf;
    return;
  }
  const Eigen::MatrixXd& V = info_.inverse();
  value_ = (W_.cwiseProduct(V)).sum();  // tr(W V), both symmetric
  vwv_.noalias() = V * W_ * V;
  vwv_ = 0.5 * (vwv_ + vwv_.transpose()).eval();
}

void TaskDesign::Add(int64_t pose) {
  CHECK(pose >= 0 && pose < pool_->size() && !member_[pose])
      << "pose " << pose << " is not a pool pose outside the design";
  member_[pose] = 1;
  poses_.push_back(pose);
  info_.Add(pool_->block(pose));
  Update();
}

bool TaskDesign::Remove(int64_t pose) {
  if (!internal::RemoveDesignPose(*pool_, pose, &info_, &member_, &poses_)) {
    return false;
  }
  Update();
  return true;
}

double TaskDesign::AddChange(int64_t pose) const {
  CHECK(positive_definite());
  const auto X = pool_->block(pose);
  Eigen::MatrixXd S = X * info_.inverse() * X.transpose();
  S.diagonal().array() += 1.0;
  const Eigen::MatrixXd B = X * vwv_ * X.transpose();
  return -TraceSolve(S, B);
}

double TaskDesign::RemoveChange(int64_t pose) const {
  CHECK(positive_definite());
  const auto Y = pool_->block(pose);
  Eigen::MatrixXd S = -(Y * info_.inverse() * Y.transpose());
  S.diagonal().array() += 1.0;
  const Eigen::MatrixXd B = Y * vwv_ * Y.transpose();
  return TraceSolve(S, B);
}

double TaskDesign::SwapChange(int64_t add, int64_t remove) const {
  CHECK(positive_definite());
  const auto X = pool_->block(add);
  const auto Y = pool_->block(remove);
  const Eigen::MatrixXd& V = info_.inverse();
  return TaskSwapChange(X * V * X.transpose(), X * vwv_ * X.transpose(),
                        Y * V * Y.transpose(), Y * vwv_ * Y.transpose(),
                        X * V * Y.transpose(), X * vwv_ * Y.transpose());
}

void TaskDesign::AllQuadraticForms(int num_threads, std::vector<double>* a,
                                   std::vector<double>* b) const {
  CHECK(positive_definite());
  const int64_t n = pool_->size();
  const int t = pool_->block_rows();
  const int p = pool_->num_parameters();
  const int tt = t * t;
  a->resize(n * tt);
  b->resize(n * tt);
  Eigen::MatrixXd VV(p, 2 * p);
  VV << info_.inverse(), vwv_;
  internal::ForEachPoseChunk(n, num_threads, [&](int64_t begin, int64_t count) {
    Eigen::Map<const RowMatrixXd> X(pool_->stacked().data() + begin * t * p,
                                    count * t, p);
    RowMatrixXd G;
    G.noalias() = X * VV;
    for (int64_t k = 0; k < count; ++k) {
      const auto Xk = X.middleRows(k * t, t);
      Eigen::Map<Eigen::MatrixXd>(a->data() + (begin + k) * tt, t, t)
          .noalias() = G.block(k * t, 0, t, p).lazyProduct(Xk.transpose());
      Eigen::Map<Eigen::MatrixXd>(b->data() + (begin + k) * tt, t, t)
          .noalias() = G.block(k * t, p, t, p).lazyProduct(Xk.transpose());
    }
  });
}

}  // namespace activecal
