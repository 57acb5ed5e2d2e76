// The candidate poses a design is chosen from, as their Jacobian blocks:
// pose i contributes the block X_i of t rows (3 for a position measurement)
// and p columns (free parameters). Blocks are stored stacked and row-major,
// so each is contiguous.

#ifndef ACTIVECAL_CORE_CANDIDATE_POOL_H_
#define ACTIVECAL_CORE_CANDIDATE_POOL_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/types.h"

namespace activecal {

class CandidatePool {
 public:
  using Block = Eigen::Map<const RowMatrixXd>;

  CandidatePool() = default;

  // Takes the stacked blocks (size() * block_rows rows). Returns false with
  // a message when the shape is wrong or an entry is not finite.
  static bool Create(RowMatrixXd stacked, int block_rows, CandidatePool* pool,
                     std::string* error);

  int64_t size() const { return size_; }
  int block_rows() const { return block_rows_; }
  int num_parameters() const { return static_cast<int>(stacked_.cols()); }
  Block block(int64_t i) const {
    return Block(stacked_.data() + i * block_rows_ * stacked_.cols(),
                 block_rows_, stacked_.cols());
  }
  const RowMatrixXd& stacked() const { return stacked_; }

  // The design matrix of a design: its blocks stacked.
  Eigen::MatrixXd Stack(const std::vector<int64_t>& design) const;

 private:
  RowMatrixXd stacked_;
  int block_rows_ = 0;
  int64_t size_ = 0;
};

}  // namespace activecal

#endif  // ACTIVECAL_CORE_CANDIDATE_POOL_H_
