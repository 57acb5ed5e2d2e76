// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The candidate poses a design is chosen from, as their Jacobian blocks:
// pose i contributes the block X_i of t rows (3 for a position measurement)
// and p columns (free parameters). Blocks are stored stacked and row-major,
// so each is contiguous.
//
// Storage is double, or single precision for pools too large to hold in
// double (a 10^7-pose pool of a 7-axis arm: 7.4 GB in double, 3.7 GB in
// float). A single-precision pool is read through CopyRows / CopyBlock,
// which widen to double: every product the algorithms form with it is
// computed in double. block() and stacked() are for double pools only.
//
// A pool may also carry an exact source: a function that recomputes the
// blocks of any poses in double (the pool builder sets one: the analytic
// Jacobians at the poses' joint values). The certificate and the final log
// det of a design read the blocks through ExactRows / ExactBlock, so a
// single-precision pool still gets a certificate over the double-precision
// blocks, computed by streaming them (no second copy of the pool).

#ifndef ACTIVECAL_CORE_CANDIDATE_POOL_H_
#define ACTIVECAL_CORE_CANDIDATE_POOL_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "activecal/core/types.h"

namespace activecal {

class CandidatePool {
 public:
  using Block = Eigen::Map<const RowMatrixXd>;
  // Fills rows (resized to count * t x p) with the blocks of poses
  // [begin, begin + count) in double. Called from several threads at once.
  using RowsSource =
      std::function<void(int64_t begin, int64_t count, RowMatrixXd* rows)>;

  CandidatePool() = default;

  // Takes the stacked blocks (size() * block_rows rows). Returns false with
  // a message when the shape is wrong or an entry is not finite.
  static bool Create(RowMatrixXd stacked, int block_rows, CandidatePool* pool,
                     std::string* error);
  // The same in single precision (entries beyond float's range are refused
  // as not finite).
  static bool Create(RowMatrixXf stacked, int block_rows, CandidatePool* pool,
                     std::string* error);

  int64_t size() const { return size_; }
  int block_rows() const { return block_rows_; }
  int num_parameters() const { return num_parameters_; }
  bool single_precision() const { return single_; }
  // Bytes held by the blocks.
  int64_t storage_bytes() const;

  // Pose i's block; double pools only (CHECK-fails on a single-precision
  // pool: use CopyBlock).
  Block block(int64_t i) const;
  // All blocks stacked; double pools only.
  const RowMatrixXd& stacked() const;

  // Poses [begin, begin + count) stacked into `rows` (count * t x p), in
  // double whatever the storage. For a double pool, prefer Rows().
  void CopyRows(int64_t begin, int64_t count, RowMatrixXd* rows) const;
  // Pose i's block in double.
  RowMatrixXd CopyBlock(int64_t i) const;
  // Poses [begin, begin + count) stacked: a view into a double pool, or
  // widened into *buffer for a single-precision one. The returned map is
  // valid while the pool and *buffer are.
  Eigen::Map<const RowMatrixXd> Rows(int64_t begin, int64_t count,
                                     RowMatrixXd* buffer) const;

  // The exact source (see above); without one, ExactRows = Rows.
  void set_exact_source(RowsSource source) { exact_ = std::move(source); }
  bool has_exact_source() const { return static_cast<bool>(exact_); }
  Eigen::Map<const RowMatrixXd> ExactRows(int64_t begin, int64_t count,
                                          RowMatrixXd* buffer) const;
  RowMatrixXd ExactBlock(int64_t i) const;

  // The design matrix of a design: its blocks stacked.
  Eigen::MatrixXd Stack(const std::vector<int64_t>& design) const;

 private:
  RowMatrixXd stacked_;
  RowMatrixXf stacked_float_;
  bool single_ = false;
  RowsSource exact_;
  int block_rows_ = 0;
  int num_parameters_ = 0;
  int64_t size_ = 0;
};

}  // namespace activecal

#endif  // ACTIVECAL_CORE_CANDIDATE_POOL_H_
