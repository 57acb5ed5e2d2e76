#include "activecal/residuals/pool_builder.h"

#include <glog/logging.h>

#include <algorithm>
#include <chrono>
#include <utility>

#include "activecal/core/random.h"
#include "activecal/residuals/jacobians.h"

namespace activecal {

Eigen::MatrixXd SampleBlocks(const RowMatrixXd& stacked, int block_rows,
                             int64_t max_rows) {
  CHECK_GT(block_rows, 0);
  CHECK_GE(max_rows, block_rows);
  const int64_t rows = stacked.rows();
  if (rows <= max_rows) return stacked;
  const int64_t blocks = rows / block_rows;
  const int64_t n = max_rows / block_rows;
  // A fixed-seed random subset, not every k-th pose: a stride equal to a
  // lattice's level count (k = 10 at --levels=10) would hold the last joint
  // at one level in every sampled pose and hide its parameters.
  Random random(0x5a3b1e);
  std::vector<int64_t> chosen = random.SampleWithoutReplacement(blocks, n);
  std::sort(chosen.begin(), chosen.end());
  Eigen::MatrixXd sample(n * block_rows, stacked.cols());
  for (int64_t i = 0; i < n; ++i) {
    sample.middleRows(i * block_rows, block_rows) =
        stacked.middleRows(chosen[i] * block_rows, block_rows);
  }
  return sample;
}

bool MeasuredInformationRows(const RobotModel& model,
                             const Eigen::VectorXd& parameters,
                             const std::vector<Measurement>& measured,
                             double rotation_weight_m_per_rad, double sigma_m,
                             RowMatrixXd* rows, std::string* error) {
  CHECK(rows != nullptr);
  CHECK_GT(sigma_m, 0.0);
  Eigen::MatrixXd J;
  if (!StackedJacobian(model, parameters, measured, rotation_weight_m_per_rad,
                       &J, error)) {
    return false;
  }
  *rows = J;
  int64_t r = 0;
  for (const Measurement& m : measured) {
    const int dim = m.dimension();
    for (int k = 0; k < dim; ++k) {
      double sigma = 0;
      if (m.type == MeasurementType::kDistance) {
        sigma = m.sigma_m[0];
      } else if (k < 3) {
        sigma = m.sigma_m[k];
      } else {
        sigma = rotation_weight_m_per_rad * m.sigma_rad;
      }
      if (sigma > 0) rows->row(r + k) *= sigma_m / sigma;
    }
    r += dim;
  }
  CHECK_EQ(r, rows->rows());
  return true;
}

bool BuildCandidatePool(RobotModel* model, const Eigen::VectorXd& parameters,
                        const Eigen::MatrixXd& joints,
                        const CandidatePoolOptions& options,
                        CandidatePool* pool, CandidatePoolSummary* summary) {
  CHECK(model != nullptr);
  CHECK(pool != nullptr);
  CHECK(summary != nullptr);
  *summary = CandidatePoolSummary();
  summary->num_free_before = model->num_free();
  const auto start = std::chrono::steady_clock::now();
  PoolJacobianOptions jacobian_options;
  jacobian_options.type = options.type;
  jacobian_options.rotation_weight_m_per_rad =
      options.rotation_weight_m_per_rad;
  jacobian_options.num_threads = options.num_threads;
  jacobian_options.progress = options.progress;
  RowMatrixXd stacked;
  if (!PoolJacobians(*model, parameters, joints, jacobian_options, &stacked,
                     &summary->message)) {
    return false;
  }
  summary->jacobian_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  const int block_rows = MeasurementDimension(options.type);
  if (options.check_identifiability) {
    const Eigen::MatrixXd sample =
        SampleBlocks(stacked, block_rows, options.max_analysis_rows);
    RobotModel fixed_model = *model;
    std::vector<int> fixed_columns;
    if (options.auto_fix) {
      if (!FixUnidentifiableParameters(&fixed_model, sample,
                                       options.rank_tolerance,
                                       &summary->identifiability,
                                       &fixed_columns, &summary->fixed_names)) {
        summary->message = summary->identifiability.Message();
        return false;
      }
    } else {
      summary->identifiability =
          AnalyzeIdentifiability(*model, sample, options.rank_tolerance);
      if (!summary->identifiability.identifiable()) {
        summary->message = summary->identifiability.Message();
        return false;
      }
    }
    if (!fixed_columns.empty()) {
      RowMatrixXd kept(stacked.rows(), stacked.cols() - fixed_columns.size());
      for (int c = 0, d = 0, k = 0; c < stacked.cols(); ++c) {
        if (d < static_cast<int>(fixed_columns.size()) &&
            fixed_columns[d] == c) {
          ++d;
        } else {
          kept.col(k++) = stacked.col(c);
        }
      }
      stacked = std::move(kept);
      *model = std::move(fixed_model);
    }
  }
  return CandidatePool::Create(std::move(stacked), block_rows, pool,
                               &summary->message);
}

}  // namespace activecal
