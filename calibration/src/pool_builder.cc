// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/pool_builder.h"

#include <glog/logging.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "activecal/core/parallel.h"
#include "activecal/core/random.h"
#include "activecal/residuals/jacobians.h"

namespace activecal {

namespace {

// The fixed-seed random subset of n of `blocks` poses SampleBlocks takes,
// in pool order. Not every k-th pose: a stride equal to a lattice's level
// count (k = 10 at --levels=10) would hold the last joint at one level in
// every sampled pose and hide its parameters.
std::vector<int64_t> SampleBlockIndices(int64_t blocks, int64_t n) {
  Random random(0x5a3b1e);
  std::vector<int64_t> chosen = random.SampleWithoutReplacement(blocks, n);
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

// PoolJacobians names a failing pose by its row in the joints it was given
// ("pool pose N: ..." or "... at pool pose N"): rewrites N to to_pool(N),
// its index in the whole pool.
void RenamePoolPose(const std::function<int64_t(int64_t)>& to_pool,
                    std::string* message) {
  const std::string key = "pool pose ";
  const size_t at = message->find(key);
  if (at == std::string::npos) return;
  const size_t first = at + key.size();
  size_t last = first;
  while (last < message->size() &&
         std::isdigit(static_cast<unsigned char>((*message)[last]))) {
    ++last;
  }
  if (last == first) return;
  const int64_t i = std::stoll(message->substr(first, last - first));
  message->replace(first, last - first, std::to_string(to_pool(i)));
}

// What a single-precision pool's exact source recomputes its blocks from.
struct ExactPoolData {
  RobotModel model;
  Eigen::VectorXd parameters;
  Eigen::MatrixXd joints;
  std::vector<uint32_t> marker_masks;
  PoolJacobianOptions options;
};

// The blocks of the poses `joints` (pool poses first .. first + n - 1): with
// no masks, PoolJacobians (marker 0's t rows per pose); with masks (one per
// pool pose, CandidatePoolOptions::marker_masks), every marker's t rows per
// pose, in marker order, those of a marker not seen at the pose zero.
// Marker 0's rows are PoolJacobians', the others' the measurement
// Jacobians of those markers (MeasurementJacobian: the identification's
// residuals).
bool MaskedPoolJacobians(const RobotModel& model,
                         const Eigen::VectorXd& parameters,
                         const Eigen::MatrixXd& joints,
                         const std::vector<uint32_t>& masks, int64_t first,
                         const PoolJacobianOptions& options,
                         RowMatrixXd* stacked, std::string* error) {
  if (masks.empty()) {
    return PoolJacobians(model, parameters, joints, options, stacked, error);
  }
  RowMatrixXd first_marker;
  if (!PoolJacobians(model, parameters, joints, options, &first_marker,
                     error)) {
    return false;
  }
  const int t = MeasurementDimension(options.type);
  const int num_markers = model.num_markers();
  const int p = model.num_free();
  const int64_t n = joints.rows();
  stacked->setZero(n * t * num_markers, p);
  std::vector<std::string> errors(n);
  ParallelFor(n, options.num_threads, [&](int64_t begin, int64_t end, int) {
    Eigen::MatrixXd jacobian;
    for (int64_t i = begin; i < end; ++i) {
      const uint32_t mask = masks[first + i];
      const int64_t row = i * t * num_markers;
      if (mask & 1u) {
        stacked->middleRows(row, t) = first_marker.middleRows(i * t, t);
      }
      for (int k = 1; k < num_markers; ++k) {
        if (!(mask & (1u << k))) continue;
        Measurement m;
        m.type = options.type;
        m.joints = joints.row(i).transpose();
        m.marker = k;
        if (!MeasurementJacobian(model, parameters, m,
                                 options.rotation_weight_m_per_rad, &jacobian,
                                 &errors[i])) {
          errors[i] = "pool pose " + std::to_string(i) + ": " + errors[i];
          break;
        }
        stacked->middleRows(row + k * t, t) = jacobian;
      }
    }
  });
  for (const std::string& e : errors) {
    if (!e.empty()) {
      if (error) *error = e;
      return false;
    }
  }
  return true;
}

// Checks options.marker_masks against the pool.
bool CheckMarkerMasks(const RobotModel& model, const Eigen::MatrixXd& joints,
                      const CandidatePoolOptions& options, std::string* error) {
  const std::vector<uint32_t>& masks = options.marker_masks;
  if (masks.empty()) return true;
  if (static_cast<int64_t>(masks.size()) != joints.rows()) {
    *error = "pool: " + std::to_string(masks.size()) + " marker masks for " +
             std::to_string(joints.rows()) + " poses";
    return false;
  }
  if (model.num_markers() > 32) {
    *error = "pool: marker masks hold 32 markers, the model has " +
             std::to_string(model.num_markers());
    return false;
  }
  const uint32_t all = EveryMarkerMask(model);
  for (size_t i = 0; i < masks.size(); ++i) {
    if ((masks[i] & all) == 0) {
      *error = "pool pose " + std::to_string(i) + ": no marker seen";
      return false;
    }
  }
  return true;
}

}  // namespace

Eigen::MatrixXd SampleBlocks(const RowMatrixXd& stacked, int block_rows,
                             int64_t max_rows) {
  CHECK_GT(block_rows, 0);
  CHECK_GE(max_rows, block_rows);
  const int64_t rows = stacked.rows();
  if (rows <= max_rows) return stacked;
  const int64_t blocks = rows / block_rows;
  const int64_t n = max_rows / block_rows;
  const std::vector<int64_t> chosen = SampleBlockIndices(blocks, n);
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

namespace {

// The identifiability check (and auto-fix) of BuildCandidatePool on the
// Jacobian rows `sample`; fixed_columns: the columns to drop, in order.
// *model: the model of the pool's columns (auto_fix may hold some of its
// parameters: summary->free, summary->held).
bool CheckPoolIdentifiability(const Eigen::MatrixXd& sample,
                              const CandidatePoolOptions& options,
                              RobotModel* model,
                              std::vector<int>* fixed_columns,
                              CandidatePoolSummary* summary) {
  if (options.auto_fix) {
    if (!FixUnidentifiableParameters(*model, sample, options.rank_tolerance,
                                     &summary->identifiability, &summary->free,
                                     &summary->held, fixed_columns)) {
      summary->message = summary->identifiability.Message();
      return false;
    }
    *model = WithFreeSet(*model, summary->free);
    return true;
  }
  summary->identifiability =
      AnalyzeIdentifiability(*model, sample, options.rank_tolerance);
  if (!summary->identifiability.identifiable()) {
    summary->message = summary->identifiability.Message();
    return false;
  }
  return true;
}

// The single-precision pool: the identifiability check on double Jacobians
// of the sampled poses, then the Jacobians of the final free parameters in
// chunks, each rounded to float as it is done (the pool is never held in
// double), and an exact source that recomputes any poses' blocks in double.
bool BuildSinglePrecisionPool(RobotModel* model,
                              const Eigen::VectorXd& parameters,
                              const Eigen::MatrixXd& joints,
                              const CandidatePoolOptions& options,
                              const PoolJacobianOptions& jacobian_options,
                              CandidatePool* pool,
                              CandidatePoolSummary* summary) {
  const int t = MeasurementDimension(options.type) *
                (options.marker_masks.empty() ? 1 : model->num_markers());
  const int64_t n = joints.rows();
  if (options.check_identifiability) {
    Eigen::MatrixXd sample_joints;
    std::vector<int64_t> chosen;  // empty: every pose
    if (n * t <= options.max_analysis_rows) {
      sample_joints = joints;
    } else {
      chosen = SampleBlockIndices(n, options.max_analysis_rows / t);
      sample_joints.resize(chosen.size(), joints.cols());
      for (size_t k = 0; k < chosen.size(); ++k) {
        sample_joints.row(k) = joints.row(chosen[k]);
      }
    }
    PoolJacobianOptions sample_options = jacobian_options;
    sample_options.progress = nullptr;
    RowMatrixXd sample;
    std::vector<uint32_t> sample_masks;
    if (!options.marker_masks.empty()) {
      sample_masks = options.marker_masks;
      if (!chosen.empty()) {
        sample_masks.resize(chosen.size());
        for (size_t k = 0; k < chosen.size(); ++k) {
          sample_masks[k] = options.marker_masks[chosen[k]];
        }
      }
    }
    if (!MaskedPoolJacobians(*model, parameters, sample_joints, sample_masks, 0,
                             sample_options, &sample, &summary->message)) {
      // Name the pose in the whole pool, not in the sample.
      if (!chosen.empty()) {
        RenamePoolPose([&](int64_t i) { return chosen[i]; }, &summary->message);
      }
      return false;
    }
    std::vector<int> fixed_columns;
    if (!CheckPoolIdentifiability(sample, options, model, &fixed_columns,
                                  summary)) {
      return false;
    }
  }
  const int p = model->num_free();
  RowMatrixXf stacked(n * t, p);
  constexpr int64_t kChunk = 1 << 16;
  RowMatrixXd chunk;
  for (int64_t begin = 0; begin < n; begin += kChunk) {
    const int64_t count = std::min(kChunk, n - begin);
    PoolJacobianOptions chunk_options = jacobian_options;
    if (options.progress) {
      chunk_options.progress = [&](int64_t done, int64_t) {
        options.progress(begin + done, n);
      };
    }
    if (!MaskedPoolJacobians(*model, parameters,
                             joints.middleRows(begin, count),
                             options.marker_masks, begin, chunk_options, &chunk,
                             &summary->message)) {
      // Name the pose in the whole pool, not in the chunk.
      RenamePoolPose([begin](int64_t i) { return begin + i; },
                     &summary->message);
      return false;
    }
    stacked.middleRows(begin * t, count * t) = chunk.cast<float>();
  }
  if (!CandidatePool::Create(std::move(stacked), t, pool, &summary->message)) {
    return false;
  }
  auto data = std::make_shared<const ExactPoolData>(ExactPoolData{
      *model, parameters, joints, options.marker_masks, jacobian_options});
  pool->set_exact_source(
      [data](int64_t begin, int64_t count, RowMatrixXd* rows) {
        PoolJacobianOptions o = data->options;
        o.num_threads = 1;  // called from the sweep's own threads
        o.progress = nullptr;
        std::string error;
        // The poses were checked when the pool was built.
        CHECK(MaskedPoolJacobians(data->model, data->parameters,
                                  data->joints.middleRows(begin, count),
                                  data->marker_masks, begin, o, rows, &error))
            << error;
      });
  return true;
}

}  // namespace

bool BuildCandidatePool(const RobotModel& input,
                        const Eigen::VectorXd& parameters,
                        const Eigen::MatrixXd& joints,
                        const CandidatePoolOptions& options,
                        CandidatePool* pool, CandidatePoolSummary* summary) {
  CHECK(pool != nullptr);
  CHECK(summary != nullptr);
  *summary = CandidatePoolSummary();
  summary->num_free_before = input.num_free();
  summary->free = FreeSet(input);
  RobotModel model_copy = input;
  RobotModel* model = &model_copy;
  const auto start = std::chrono::steady_clock::now();
  PoolJacobianOptions jacobian_options;
  jacobian_options.type = options.type;
  jacobian_options.rotation_weight_m_per_rad =
      options.rotation_weight_m_per_rad;
  jacobian_options.num_threads = options.num_threads;
  jacobian_options.progress = options.progress;
  if (!CheckMarkerMasks(input, joints, options, &summary->message)) {
    return false;
  }
  if (options.single_precision) {
    const bool ok = BuildSinglePrecisionPool(model, parameters, joints, options,
                                             jacobian_options, pool, summary);
    summary->jacobian_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    return ok;
  }
  RowMatrixXd stacked;
  if (!MaskedPoolJacobians(*model, parameters, joints, options.marker_masks, 0,
                           jacobian_options, &stacked, &summary->message)) {
    return false;
  }
  summary->jacobian_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  const int block_rows =
      MeasurementDimension(options.type) *
      (options.marker_masks.empty() ? 1 : model->num_markers());
  if (options.check_identifiability) {
    const Eigen::MatrixXd sample =
        SampleBlocks(stacked, block_rows, options.max_analysis_rows);
    std::vector<int> fixed_columns;
    if (!CheckPoolIdentifiability(sample, options, model, &fixed_columns,
                                  summary)) {
      return false;
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
    }
  }
  return CandidatePool::Create(std::move(stacked), block_rows, pool,
                               &summary->message);
}

uint32_t EveryMarkerMask(const RobotModel& model) {
  return model.num_markers() >= 32 ? ~0u : (1u << model.num_markers()) - 1u;
}

}  // namespace activecal
