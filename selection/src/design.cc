// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/selection/design.h"

#include <glog/logging.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "activecal/core/parallel.h"
#include "activecal/core/validation.h"
#include "activecal/selection/criteria.h"
#include "selection_internal.h"

namespace activecal {

Design::Design(const CandidatePool& pool, double ridge)
    : pool_(&pool),
      member_(pool.size(), 0),
      info_(pool.num_parameters(), ridge) {}

void Design::Add(int64_t pose) {
  CHECK(pose >= 0 && pose < pool_->size())
      << "pose " << pose << " is not in the pool of " << pool_->size();
  CHECK(!member_[pose]) << "pose " << pose << " is already in the design";
  member_[pose] = 1;
  poses_.push_back(pose);
  info_.Add(pool_->block(pose));
}

bool Design::Remove(int64_t pose) {
  return internal::RemoveDesignPose(*pool_, pose, &info_, &member_, &poses_);
}

void Design::Rebuild() {
  InformationMatrix fresh(pool_->num_parameters(), info_.ridge());
  fresh.set_refresh_interval(info_.refresh_interval());
  for (int64_t i : poses_) fresh.Add(pool_->block(i));
  fresh.Refresh();
  info_ = std::move(fresh);
}

void Design::ClearRidge() {
  InformationMatrix fresh(pool_->num_parameters(), 0.0);
  fresh.set_refresh_interval(info_.refresh_interval());
  info_ = std::move(fresh);
  Rebuild();
}

namespace internal {

bool RemoveDesignPose(const CandidatePool& pool, int64_t pose,
                      InformationMatrix* info, std::vector<char>* member,
                      std::vector<int64_t>* poses) {
  CHECK(pose >= 0 && pose < pool.size() && (*member)[pose])
      << "pose " << pose << " is not in the design";
  if (!info->Remove(pool.block(pose))) return false;
  (*member)[pose] = 0;
  poses->erase(std::find(poses->begin(), poses->end(), pose));
  return true;
}

void ForEachPoseChunk(int64_t n, int num_threads,
                      const std::function<void(int64_t, int64_t)>& fn) {
  constexpr int64_t kChunk = 512;
  const int64_t num_chunks = (n + kChunk - 1) / kChunk;
  ParallelFor(num_chunks, num_threads, [&](int64_t cb, int64_t ce, int) {
    for (int64_t c = cb; c < ce; ++c) {
      const int64_t begin = c * kChunk;
      fn(begin, std::min(kChunk, n - begin));
    }
  });
}

void ForEachQuadraticForm(
    const CandidatePool& pool, const Eigen::MatrixXd& V, int num_threads,
    const std::function<void(int64_t, const Eigen::MatrixXd&)>& fn,
    PoolReading reading) {
  const int64_t n = pool.size();
  const int t = pool.block_rows();
  // Chunks of poses: W = X_chunk V in one product, then t x t blocks.
  ForEachPoseChunk(n, num_threads, [&](int64_t begin, int64_t count) {
    RowMatrixXd W, buffer;
    Eigen::MatrixXd S(t, t);
    // A single-precision pool is widened to double chunk by chunk.
    const Eigen::Map<const RowMatrixXd> X =
        reading == PoolReading::kExact ? pool.ExactRows(begin, count, &buffer)
                                       : pool.Rows(begin, count, &buffer);
    W.noalias() = X * V;
    for (int64_t k = 0; k < count; ++k) {
      // lazyProduct: a t x p times p x t product is too small for the
      // blocked GEMM kernel (packing dominated: 3x slower at t = 3).
      S.noalias() = W.middleRows(k * t, t).lazyProduct(
          X.middleRows(k * t, t).transpose());
      fn(begin + k, S);
    }
  });
}

}  // namespace internal

void ComputeAddGains(const CandidatePool& pool, const InformationMatrix& info,
                     int num_threads, Eigen::VectorXd* gains) {
  gains->resize(pool.size());
  internal::ForEachQuadraticForm(pool, info.inverse(), num_threads,
                                 [gains](int64_t i, const Eigen::MatrixXd& D) {
                                   Eigen::MatrixXd S = D;
                                   S.diagonal().array() += 1.0;
                                   (*gains)[i] = LogDetSpd(S);
                                 });
}

void ComputeVariances(const CandidatePool& pool,
                      const std::vector<Eigen::MatrixXd>& Vs, int num_threads,
                      std::vector<Eigen::VectorXd>* variances,
                      PoolReading reading) {
  const int64_t n = pool.size();
  const int t = pool.block_rows();
  const size_t m = Vs.size();
  variances->resize(m);
  // With V = L L^T, d_i = tr(X_i L L^T X_i^T) = ||X_i L||_F^2: a triangular
  // product (half the flops of X_i V) and a squared norm instead of a
  // t x t block. A V that is not numerically positive definite takes the
  // general path.
  std::vector<Eigen::MatrixXd> Ls(m);
  for (size_t v = 0; v < m; ++v) {
    (*variances)[v].resize(n);
    const Eigen::LLT<Eigen::MatrixXd> llt(Vs[v]);
    if (llt.info() != Eigen::Success) {
      Eigen::VectorXd* out = &(*variances)[v];
      internal::ForEachQuadraticForm(
          pool, Vs[v], num_threads,
          [out](int64_t i, const Eigen::MatrixXd& D) { (*out)[i] = D.trace(); },
          reading);
    } else {
      Ls[v] = llt.matrixL();
    }
  }
  internal::ForEachPoseChunk(n, num_threads, [&](int64_t begin, int64_t count) {
    RowMatrixXd W, buffer;
    // One read of the blocks (one recomputation from an exact source) for
    // every V.
    const Eigen::Map<const RowMatrixXd> X =
        reading == PoolReading::kExact ? pool.ExactRows(begin, count, &buffer)
                                       : pool.Rows(begin, count, &buffer);
    for (size_t v = 0; v < m; ++v) {
      if (Ls[v].size() == 0) continue;  // done by the general path
      W.noalias() = X * Ls[v].triangularView<Eigen::Lower>();
      Eigen::VectorXd& d = (*variances)[v];
      for (int64_t k = 0; k < count; ++k) {
        d[begin + k] = W.middleRows(k * t, t).squaredNorm();
      }
    }
  });
}

void ComputeVariances(const CandidatePool& pool, const Eigen::MatrixXd& V,
                      int num_threads, Eigen::VectorXd* variances,
                      PoolReading reading) {
  std::vector<Eigen::VectorXd> out;
  ComputeVariances(pool, std::vector<Eigen::MatrixXd>{V}, num_threads, &out,
                   reading);
  *variances = std::move(out[0]);
}

bool PrepareCandidates(const CandidatePool& pool, int num_poses,
                       const DesignConstraints& constraints,
                       std::vector<char>* eligible, std::string* error,
                       int64_t prior_equations) {
  std::ostringstream msg;
  const int64_t n = pool.size();
  eligible->assign(n, 1);
  std::vector<char> seen(n, 0);
  for (int64_t f : constraints.fixed) {
    if (f < 0 || f >= n) {
      msg << "fixed pose " << f << " is outside the pool [0, " << n << ")";
      break;
    }
    if (seen[f]) {
      msg << "fixed pose " << f << " is listed twice";
      break;
    }
    if (constraints.excluded && constraints.excluded(f)) {
      msg << "fixed pose " << f << " is also excluded";
      break;
    }
    seen[f] = 1;
    (*eligible)[f] = 0;
  }
  int64_t available = 0;
  if (msg.tellp() == 0) {
    for (int64_t i = 0; i < n; ++i) {
      if ((*eligible)[i] && constraints.excluded && constraints.excluded(i)) {
        (*eligible)[i] = 0;
      }
      available += (*eligible)[i];
    }
    const int64_t fixed = static_cast<int64_t>(constraints.fixed.size());
    if (num_poses <= 0) {
      msg << "the number of poses must be > 0, got " << num_poses;
    } else if (num_poses < fixed) {
      msg << "the number of poses (" << num_poses << ") is smaller than the "
          << fixed << " fixed poses";
    } else if (num_poses - fixed > available) {
      msg << "asked for " << num_poses << " poses, but the pool has only "
          << available + fixed << " usable poses (" << fixed << " fixed, "
          << n - available - fixed << " excluded of " << n << ")";
    } else if (static_cast<int64_t>(num_poses) * pool.block_rows() +
                   prior_equations <
               pool.num_parameters()) {
      msg << num_poses << " poses give " << num_poses * pool.block_rows()
          << " equations, fewer than the " << pool.num_parameters()
          << " parameters: every such design is singular";
    }
  }
  return FinishValidation(msg, error);
}

std::string SelectionStep::name() const {
  switch (kind) {
    case kInitial:
      return "initial";
    case kExchange:
      return "exchange";
    case kAdd:
      return "add";
    case kExcursionUp:
      return "excursion up " + std::to_string(excursion_size);
    case kExcursionDown:
      return "excursion down " + std::to_string(excursion_size);
  }
  return "unknown";
}

std::string SelectionSummary::BriefReport() const {
  std::ostringstream out;
  out << "activecal selection (" << algorithm
      << "): " << TerminationTypeToString(termination_type) << "\n  " << message
      << "\n";
  if (IsSolutionUsable()) {
    out << "  " << design.size() << " poses from a pool of " << pool_size
        << ", " << num_parameters << " parameters\n";
    out.precision(6);
    out << "  log10 det(X^T X) = " << log10_det()
        << ", OI = " << OiFromLogDet(log_det, num_parameters) << "\n";
    if (!std::isnan(task_criterion)) {
      out << "  task criterion tr(W M^-1) = " << task_criterion << "\n";
    }
    if (!std::isnan(task_criterion_lower_bound)) {
      out << "  certified: task efficiency >= " << efficiency_lower_bound
          << " (tr(W M^-1) of the best " << design.size()
          << "-pose design >= " << task_criterion_lower_bound << ")\n";
    } else if (!std::isnan(efficiency_lower_bound)) {
      out << "  certified: D-efficiency >= " << efficiency_lower_bound
          << " (log10 det of the best " << design.size()
          << "-pose design <= " << log_det_upper_bound / std::log(10.0)
          << ")\n";
    }
    out << "  " << history.size() << " steps, " << restarts
        << " restart(s), best restart " << best_restart << ", " << seconds
        << " s\n";
  }
  return out.str();
}

}  // namespace activecal
