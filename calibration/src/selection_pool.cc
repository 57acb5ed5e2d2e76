// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/selection_pool.h"

#include <unistd.h>

#include <algorithm>
#include <sstream>

#include "activecal/calibration/pool_reduction.h"
#include "activecal/cell/cell_setup.h"

namespace activecal {

bool PoolStorageFromString(const std::string& name, PoolStorage* storage) {
  if (name == "auto") {
    *storage = PoolStorage::kAuto;
  } else if (name == "double") {
    *storage = PoolStorage::kDouble;
  } else if (name == "float") {
    *storage = PoolStorage::kFloat;
  } else {
    return false;
  }
  return true;
}

bool SelectionPoolOptions::IsValid(std::string* error) const {
  std::string e;
  if (type != MeasurementType::kPosition && type != MeasurementType::kPose) {
    e = "measurement must be position or pose";
  } else if (storage == PoolStorage::kFloat && !reads_float) {
    e = "float storage needs a design that reads single-precision pools "
        "(fedorov or approx with the D criterion)";
  } else if (storage == PoolStorage::kAuto && max_double_pool_mib < 0) {
    e = "max_double_pool_mib must be >= 0, got " +
        std::to_string(max_double_pool_mib);
  } else if (reduction_sample_size <= 0) {
    e = "reduction_sample_size must be > 0, got " +
        std::to_string(reduction_sample_size);
  }
  if (e.empty()) return true;
  if (error) *error = e;
  return false;
}

std::vector<std::string> SelectionPoolSummary::HeldFixed() const {
  std::vector<std::string> names;
  for (const HeldParameter& d : dropped) names.push_back(d.name);
  for (const HeldParameter& h : pool.held) names.push_back(h.name);
  return names;
}

double SelectionPoolBytes(int64_t pool_size, int num_joints,
                          MeasurementType type, int num_parameters,
                          bool single_precision) {
  const double entry = single_precision ? sizeof(float) : sizeof(double);
  return static_cast<double>(pool_size) *
         (sizeof(double) * num_joints +
          entry * MeasurementDimension(type) * num_parameters);
}

double PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0
             ? static_cast<double>(pages) * static_cast<double>(page)
             : 0.0;
}

namespace {

// True when `need` bytes (at least that when `lower_bound`) fit in
// `available` (<= 0: the physical memory); otherwise false with one line in
// *error, `what` saying what is counted.
bool FitsInMemory(int64_t pool_size, double need, bool lower_bound,
                  const std::string& what, double available,
                  std::string* error) {
  const double have = available > 0 ? available : PhysicalMemoryBytes();
  if (!(have > 0) || need <= have) return true;
  if (error) {
    constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
    std::ostringstream s;
    s.precision(3);
    s << "a pool of " << pool_size << " poses needs "
      << (lower_bound ? "at least " : "") << need / kGiB << " GiB (" << what
      << "), more than "
      << (available > 0 ? "the limit of " : "this machine's ") << have / kGiB
      << " GiB of memory";
    *error = s.str();
  }
  return false;
}

// The preprocess hook: the rows options.filter keeps, into *kept_joints.
bool ApplyPoolFilter(const SelectionPoolOptions& options,
                     const Eigen::MatrixXd& pool_joints,
                     Eigen::MatrixXd* kept_joints,
                     SelectionPoolSummary* summary) {
  summary->filtered = true;
  if (!options.filter(pool_joints, &summary->kept, &summary->filter_note)) {
    summary->message = "pool filter: " + summary->filter_note;
    return false;
  }
  if (summary->kept.empty()) {
    summary->message = "no pose of the pool is left: " + summary->filter_note;
    return false;
  }
  kept_joints->resize(summary->kept.size(), pool_joints.cols());
  for (size_t k = 0; k < summary->kept.size(); ++k) {
    kept_joints->row(k) = pool_joints.row(summary->kept[k]);
  }
  return true;
}

}  // namespace

bool CheckSelectionPoolSize(int64_t pool_size, const RobotModel& model,
                            MeasurementType type, std::string* error,
                            double available_bytes) {
  return FitsInMemory(
      pool_size,
      SelectionPoolBytes(pool_size, model.num_joints(), type, 1, true),
      /*lower_bound=*/true,
      "joint values and one single-precision Jacobian column per "
      "measurement row",
      available_bytes, error);
}

bool BuildSelectionPool(RobotModel* model, const Eigen::MatrixXd& all_joints,
                        const SelectionPoolOptions& options,
                        CandidatePool* pool, SelectionPoolSummary* summary) {
  *summary = SelectionPoolSummary();
  std::string error;
  if (!options.IsValid(&error)) {
    summary->termination_type = TerminationType::kUserFailure;
    summary->message = error;
    return false;
  }
  // The preprocess (a cell's): everything below sees the rows kept.
  Eigen::MatrixXd kept_joints;
  if (options.filter &&
      !ApplyPoolFilter(options, all_joints, &kept_joints, summary)) {
    return false;
  }
  const Eigen::MatrixXd& pool_joints =
      options.filter ? kept_joints : all_joints;
  const std::vector<uint32_t>* masks =
      options.filter ? options.kept_marker_masks : nullptr;
  {
    PoolReductionOptions reduction_options;
    reduction_options.type = options.type;
    reduction_options.rotation_weight_m_per_rad =
        options.rotation_weight_m_per_rad;
    reduction_options.sample_size = options.reduction_sample_size;
    PoolReduction reduction;
    if (masks != nullptr &&
        masks->size() != static_cast<size_t>(pool_joints.rows())) {
      summary->message = "pool filter: " + std::to_string(masks->size()) +
                         " marker masks for " +
                         std::to_string(pool_joints.rows()) + " poses";
      return false;
    }
    if (!ReduceForPool(*model, options.parameter_set, pool_joints, masks,
                       reduction_options, &reduction)) {
      summary->reduction_failed = true;
      summary->message =
          "parameter_set=" +
          std::string(ParameterSetToString(options.parameter_set)) + ": " +
          reduction.message;
      return false;
    }
    summary->dropped = reduction.held;
    *model = WithFreeSet(*model, reduction.free);
    model->nominal = reduction.point;
  }
  summary->double_mib = 8.0 * pool_joints.rows() *
                        MeasurementDimension(options.type) * model->num_free() /
                        (1024.0 * 1024.0);
  summary->single_precision =
      options.storage == PoolStorage::kFloat ||
      (options.storage == PoolStorage::kAuto && options.reads_float &&
       summary->double_mib > options.max_double_pool_mib);
  {
    const bool single = summary->single_precision;
    const std::string what = std::string("joint values and ") +
                             (single ? "single" : "double") +
                             "-precision Jacobians of " +
                             std::to_string(model->num_free()) + " parameters";
    if (!FitsInMemory(
            pool_joints.rows(),
            SelectionPoolBytes(pool_joints.rows(), model->num_joints(),
                               options.type, model->num_free(), single),
            /*lower_bound=*/false, what, options.memory_limit_bytes, &error)) {
      summary->termination_type = TerminationType::kUserFailure;
      summary->message = error;
      return false;
    }
  }

  CandidatePoolOptions pool_options;
  pool_options.single_precision = summary->single_precision;
  pool_options.type = options.type;
  pool_options.rotation_weight_m_per_rad = options.rotation_weight_m_per_rad;
  pool_options.num_threads = options.num_threads;
  pool_options.check_identifiability = true;
  pool_options.auto_fix = options.auto_fix;
  pool_options.progress = options.progress;
  if (masks) pool_options.marker_masks = *masks;
  if (!BuildCandidatePool(*model, model->nominal, pool_joints, pool_options,
                          pool, &summary->pool)) {
    summary->message = summary->pool.message;
    if (summary->filtered)
      summary->message += " (" + summary->filter_note + ")";
    return false;
  }
  *model = WithFreeSet(*model, summary->pool.free);
  summary->termination_type = TerminationType::kConvergence;
  return true;
}

bool BuildTaskPool(const RobotModel& model, const Eigen::MatrixXd& pool_joints,
                   const Eigen::MatrixXd& task_joints,
                   const SelectionPoolOptions& options,
                   CandidatePool* task_pool, bool* task_is_pool,
                   std::string* error) {
  *task_is_pool =
      task_joints.rows() == 0 && options.type == MeasurementType::kPosition;
  if (*task_is_pool) return true;
  CandidatePoolOptions task_options;
  task_options.type = MeasurementType::kPosition;
  task_options.num_threads = options.num_threads;
  CandidatePoolSummary task_summary;
  if (!BuildCandidatePool(model, model.nominal,
                          task_joints.rows() ? task_joints : pool_joints,
                          task_options, task_pool, &task_summary)) {
    if (error) *error = task_summary.message;
    return false;
  }
  return true;
}

bool MakeLatticePool(const RobotModel& model, const CellChecker* checker,
                     int levels, MeasurementType type,
                     const std::string& option_prefix, JointLattice* lattice,
                     std::string* notes, std::string* error) {
  std::string why;
  if (!JointLattice::Create(
          checker ? WithinJointMargins(*checker, model) : model, levels,
          lattice, &why) ||
      !CheckSelectionPoolSize(lattice->size(), model, type, &why)) {
    *error = option_prefix + "levels=" + std::to_string(levels) + ": " + why;
    return false;
  }
  for (const std::string& note : lattice->OneTurnNotes(model)) {
    *notes += "note: " + note + "\n";
  }
  return true;
}

}  // namespace activecal
