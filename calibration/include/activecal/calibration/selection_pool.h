// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The pool side of activecal_select (and the Python module's select): the
// parameters a design is for, the storage of the pool's Jacobian blocks,
// the pool itself, and the task's pool when it is not the pool.
//
//   SelectionPoolOptions options;  // parameter set, measurement, storage
//   CandidatePool pool;
//   SelectionPoolSummary summary;
//   if (!BuildSelectionPool(&model, pool_joints, options, &pool, &summary))
//     ...summary.message...
//   CandidatePool task_pool;
//   bool task_is_pool;
//   BuildTaskPool(model, pool_joints, task_joints, options, &task_pool,
//                 &task_is_pool, &error);
//   W = TaskMatrix(task_is_pool ? pool : task_pool);  // selection layer

#ifndef ACTIVECAL_CALIBRATION_SELECTION_POOL_H_
#define ACTIVECAL_CALIBRATION_SELECTION_POOL_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "activecal/calibration/pool_builder.h"
#include "activecal/cell/cell_checker.h"
#include "activecal/core/candidate_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/estimation/parameter_reduction.h"

namespace activecal {

enum class PoolStorage { kAuto, kDouble, kFloat };

// "auto", "double", "float".
bool PoolStorageFromString(const std::string& name, PoolStorage* storage);

// The preprocess of the pool (e.g. the cell's, cell/pool_filter.h): sets
// *kept to the rows of pool_joints to keep (ascending) and *note to one
// line saying what removed the others ("6211 of 200000 poses feasible;
// rejected: joint margin 9114, ..."). False (with *note saying why) when
// it cannot run.
using PoolFilter =
    std::function<bool(const Eigen::MatrixXd& pool_joints,
                       std::vector<int64_t>* kept, std::string* note)>;

struct SelectionPoolOptions {
  // Reduced to what the pool separates (analysed on at most
  // reduction_sample_size of its poses, a fixed-seed subset); the pool is
  // linearised at the generic point of that analysis.
  ParameterSet parameter_set = ParameterSet::kFile;
  int64_t reduction_sample_size = 2000;
  MeasurementType type = MeasurementType::kPosition;  // position or pose
  double rotation_weight_m_per_rad = 1.0;
  // Hold parameters the pool cannot identify at their nominal values
  // instead of failing.
  bool auto_fix = false;
  int num_threads = 0;
  // kAuto: single precision when the double blocks would take more than
  // max_double_pool_mib and the design reads such pools (reads_float:
  // fedorov or approx with the D criterion). kFloat needs reads_float.
  PoolStorage storage = PoolStorage::kDouble;
  int64_t max_double_pool_mib = 2048;
  bool reads_float = false;
  // The memory the pool may take (bytes; <= 0: the machine's physical
  // memory): a pool larger than this, once its parameters and storage are
  // chosen, fails (USER_FAILURE) before its Jacobians are allocated.
  double memory_limit_bytes = 0.0;
  ProgressCallback progress;  // the pool's Jacobians
  // If set, applied first: the reduction, the Jacobians and the
  // identifiability check see only the rows it keeps.
  PoolFilter filter;
  // With a filter: the markers seen at each row it kept, one mask per kept
  // row (CandidatePoolOptions::marker_masks), read once it has run (e.g.
  // the targets_seen of CellPoolFilter's summary: cell_planning.h,
  // SetCellPoolFilter). Null: each pose's rows are marker 0's.
  const std::vector<uint32_t>* kept_marker_masks = nullptr;

  bool IsValid(std::string* error) const;
};

struct SelectionPoolSummary {
  // CONVERGENCE: the pool was built; USER_FAILURE: bad options; FAILURE:
  // the reduction or the pool failed (message; the pool's
  // identifiability report in pool.identifiability).
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  bool reduction_failed = false;       // message is "parameter_set=<name>: ..."
  std::vector<HeldParameter> dropped;  // by the reduction
  bool single_precision = false;       // the storage chosen
  double double_mib = 0;               // the blocks' size in double
  CandidatePoolSummary pool;           // auto_fix's held, jacobian_seconds
  // With options.filter: the rows of pool_joints the pool was built from
  // (pool pose k is row kept[k]) and the filter's note.
  bool filtered = false;
  std::vector<int64_t> kept;
  std::string filter_note;

  // dropped, then the pool's held.
  std::vector<std::string> HeldFixed() const;
};

// The memory a selection pool holds (bytes): `pool_size` poses' joint
// values (double) and their Jacobian blocks, MeasurementDimension(type)
// rows of `num_parameters` columns per pose, in single or double precision.
double SelectionPoolBytes(int64_t pool_size, int num_joints,
                          MeasurementType type, int num_parameters,
                          bool single_precision);

// The machine's physical memory (bytes; 0 when it cannot be told).
double PhysicalMemoryBytes();

// The check made before a pool of `pool_size` poses of `model` is sampled
// or a lattice listed, so that a pool too large is refused in one line
// rather than a std::bad_alloc midway: true when the least such a pool can
// take (SelectionPoolBytes with one single-precision column: the parameters
// the design is for are known only after the reduction) fits in
// `available_bytes` (<= 0: PhysicalMemoryBytes(); no check when that is 0);
// otherwise false with one line in *error: "a pool of 100000000000 poses
// needs at least 5.59e+03 GiB (joint values and one single-precision
// Jacobian column per measurement row), more than this machine's 23.4 GiB
// of memory". BuildSelectionPool checks the pool's exact size again once
// its parameters and storage are chosen.
bool CheckSelectionPoolSize(int64_t pool_size, const RobotModel& model,
                            MeasurementType type, std::string* error,
                            double available_bytes = 0.0);

// The lattice pool of the programs: *lattice of `levels` values a joint
// over the joint ranges of `model` (with a cell's `checker`: within its
// joint margins, WithinJointMargins), checked by CheckSelectionPoolSize
// for `type` measurements before it is listed, its one-turn notes
// (JointLattice::OneTurnNotes) appended to *notes as "note: <note>\n"
// lines. False with *error "<option_prefix>levels=<levels>: <why>"
// (option_prefix "--" for a program's flag).
bool MakeLatticePool(const RobotModel& model, const CellChecker* checker,
                     int levels, MeasurementType type,
                     const std::string& option_prefix, JointLattice* lattice,
                     std::string* notes, std::string* error);

// Applies options.filter (if set), then applies and reduces
// options.parameter_set on *model (its nominal becomes the analysis
// point), chooses the storage and builds *pool at the rows kept with the
// identifiability check. A filter that keeps no row is a FAILURE whose
// message carries its note; so is a failed identifiability check, which
// then names the filter's note too. A pool larger than
// options.memory_limit_bytes once its parameters and storage are chosen is
// a USER_FAILURE ("a pool of N poses needs X GiB (...), more than ...").
bool BuildSelectionPool(RobotModel* model, const Eigen::MatrixXd& pool_joints,
                        const SelectionPoolOptions& options,
                        CandidatePool* pool, SelectionPoolSummary* summary);

// The task: position rows at task_joints (the pool's poses when it has no
// rows). When those are the pool's own rows (no task joints, a position
// pool), *task_is_pool is set and *task_pool left empty; otherwise
// *task_pool is built at model.nominal. False with *error on failure.
bool BuildTaskPool(const RobotModel& model, const Eigen::MatrixXd& pool_joints,
                   const Eigen::MatrixXd& task_joints,
                   const SelectionPoolOptions& options,
                   CandidatePool* task_pool, bool* task_is_pool,
                   std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SELECTION_POOL_H_
