#include "activecal/core/candidate_pool.h"

#include <cmath>
#include <sstream>

namespace activecal {

bool CandidatePool::Create(RowMatrixXd stacked, int block_rows,
                           CandidatePool* pool, std::string* error) {
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
  if (msg.tellp() != 0) {
    if (error) *error = msg.str();
    return false;
  }
  pool->size_ = stacked.rows() / block_rows;
  pool->block_rows_ = block_rows;
  pool->stacked_ = std::move(stacked);
  return true;
}

Eigen::MatrixXd CandidatePool::Stack(const std::vector<int64_t>& design) const {
  Eigen::MatrixXd X(design.size() * block_rows_, num_parameters());
  for (size_t k = 0; k < design.size(); ++k) {
    X.middleRows(k * block_rows_, block_rows_) = block(design[k]);
  }
  return X;
}

}  // namespace activecal
