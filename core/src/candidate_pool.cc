// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/candidate_pool.h"

#include <glog/logging.h>

#include <cmath>
#include <sstream>

#include "activecal/core/validation.h"

namespace activecal {

namespace {

// The shape and finiteness checks shared by both storages.
template <typename Matrix>
bool CheckStacked(const Matrix& stacked, int block_rows, std::string* error) {
  std::ostringstream msg;
  if (block_rows <= 0) {
    msg << "candidate pool: block_rows must be > 0, got " << block_rows;
  } else if (stacked.rows() == 0 || stacked.cols() == 0) {
    msg << "candidate pool: empty (" << stacked.rows() << " x "
        << stacked.cols() << ")";
  } else if (stacked.rows() % block_rows != 0) {
    msg << "candidate pool: " << stacked.rows()
        << " rows is not a multiple of the block size " << block_rows;
  } else {
    for (Eigen::Index r = 0; r < stacked.rows() && msg.tellp() == 0; ++r) {
      for (Eigen::Index c = 0; c < stacked.cols(); ++c) {
        if (!std::isfinite(stacked(r, c))) {
          msg << "candidate pool: pose " << r / block_rows << " has a "
              << "non-finite Jacobian entry (row " << r % block_rows
              << ", column " << c << ")";
          break;
        }
      }
    }
  }
  return FinishValidation(msg, error);
}

}  // namespace

bool CandidatePool::Create(RowMatrixXd stacked, int block_rows,
                           CandidatePool* pool, std::string* error) {
  if (!CheckStacked(stacked, block_rows, error)) return false;
  *pool = CandidatePool();
  pool->size_ = stacked.rows() / block_rows;
  pool->block_rows_ = block_rows;
  pool->num_parameters_ = static_cast<int>(stacked.cols());
  pool->stacked_ = std::move(stacked);
  return true;
}

bool CandidatePool::Create(RowMatrixXf stacked, int block_rows,
                           CandidatePool* pool, std::string* error) {
  if (!CheckStacked(stacked, block_rows, error)) return false;
  *pool = CandidatePool();
  pool->size_ = stacked.rows() / block_rows;
  pool->block_rows_ = block_rows;
  pool->num_parameters_ = static_cast<int>(stacked.cols());
  pool->single_ = true;
  pool->stacked_float_ = std::move(stacked);
  return true;
}

int64_t CandidatePool::storage_bytes() const {
  return single_ ? static_cast<int64_t>(stacked_float_.size()) * 4
                 : static_cast<int64_t>(stacked_.size()) * 8;
}

CandidatePool::Block CandidatePool::block(int64_t i) const {
  CHECK(!single_) << "CandidatePool::block on a single-precision pool: use "
                     "CopyBlock or Rows";
  return Block(stacked_.data() + i * block_rows_ * num_parameters_, block_rows_,
               num_parameters_);
}

const RowMatrixXd& CandidatePool::stacked() const {
  CHECK(!single_) << "CandidatePool::stacked on a single-precision pool: use "
                     "CopyRows or Rows";
  return stacked_;
}

void CandidatePool::CopyRows(int64_t begin, int64_t count,
                             RowMatrixXd* rows) const {
  CHECK(begin >= 0 && count >= 0 && begin + count <= size_)
      << "poses [" << begin << ", " << begin + count << ") outside the pool of "
      << size_;
  const int64_t r0 = begin * block_rows_, nr = count * block_rows_;
  if (single_) {
    *rows = stacked_float_.middleRows(r0, nr).cast<double>();
  } else {
    *rows = stacked_.middleRows(r0, nr);
  }
}

RowMatrixXd CandidatePool::CopyBlock(int64_t i) const {
  RowMatrixXd X;
  CopyRows(i, 1, &X);
  return X;
}

Eigen::Map<const RowMatrixXd> CandidatePool::Rows(int64_t begin, int64_t count,
                                                  RowMatrixXd* buffer) const {
  if (!single_) {
    CHECK(begin >= 0 && count >= 0 && begin + count <= size_)
        << "poses [" << begin << ", " << begin + count
        << ") outside the pool of " << size_;
    return Eigen::Map<const RowMatrixXd>(
        stacked_.data() + begin * block_rows_ * num_parameters_,
        count * block_rows_, num_parameters_);
  }
  CopyRows(begin, count, buffer);
  return Eigen::Map<const RowMatrixXd>(buffer->data(), buffer->rows(),
                                       buffer->cols());
}

Eigen::Map<const RowMatrixXd> CandidatePool::ExactRows(
    int64_t begin, int64_t count, RowMatrixXd* buffer) const {
  if (!exact_) return Rows(begin, count, buffer);
  CHECK(begin >= 0 && count >= 0 && begin + count <= size_)
      << "poses [" << begin << ", " << begin + count << ") outside the pool of "
      << size_;
  exact_(begin, count, buffer);
  CHECK(buffer->rows() == count * block_rows_ &&
        buffer->cols() == num_parameters_)
      << "the pool's exact source returned " << buffer->rows() << " x "
      << buffer->cols() << " rows for " << count << " poses";
  return Eigen::Map<const RowMatrixXd>(buffer->data(), buffer->rows(),
                                       buffer->cols());
}

RowMatrixXd CandidatePool::ExactBlock(int64_t i) const {
  RowMatrixXd buffer;
  const Eigen::Map<const RowMatrixXd> X = ExactRows(i, 1, &buffer);
  return X;
}

Eigen::MatrixXd CandidatePool::Stack(const std::vector<int64_t>& design) const {
  Eigen::MatrixXd X(design.size() * block_rows_, num_parameters());
  for (size_t k = 0; k < design.size(); ++k) {
    X.middleRows(k * block_rows_, block_rows_) = CopyBlock(design[k]);
  }
  return X;
}

}  // namespace activecal
