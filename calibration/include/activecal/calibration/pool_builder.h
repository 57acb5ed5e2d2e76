// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// BuildCandidatePool: the pipeline from joint values to the candidate pool a
// design is selected from. The Jacobian of every pose at the given
// parameter values (jacobians.h), optionally an identifiability check
// with the auto-fix policy (identification.h: FixUnidentifiableParameters),
// then the CandidatePool.
//
//   CandidatePoolOptions options;
//   options.check_identifiability = true;
//   options.auto_fix = true;
//   CandidatePool pool;
//   CandidatePoolSummary summary;
//   if (!BuildCandidatePool(model, model.nominal, lattice.AllJointValues(),
//                           options, &pool, &summary)) {
//     LOG(ERROR) << summary.message;
//   }
//   // summary.free: the pool's parameters (free_set.h), summary.held the
//   // parameters auto_fix held; WithFreeSet(model, summary.free) is the
//   // model the pool's columns belong to.

#ifndef ACTIVECAL_CALIBRATION_POOL_BUILDER_H_
#define ACTIVECAL_CALIBRATION_POOL_BUILDER_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/free_set.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"
#include "activecal/estimation/identification.h"

namespace activecal {

struct CandidatePoolOptions {
  // What is measured at each pose: kPosition (3 rows) or kPose (6 rows).
  MeasurementType type = MeasurementType::kPosition;
  double rotation_weight_m_per_rad = 1.0;
  int num_threads = 1;  // for the Jacobians; the result does not depend on it
  ProgressCallback progress;

  // Check that the pool identifies every free parameter. A pool of more
  // than max_analysis_rows rows is analysed through a fixed-seed random
  // subset of its poses (whole blocks, all rows of each pose), enough to
  // expose structural rank loss.
  bool check_identifiability = false;
  int64_t max_analysis_rows = 300000;
  double rank_tolerance = 1e-10;
  // When the check fails: hold the parameters FixUnidentifiableParameters
  // names fixed (and drop their columns) instead of failing.
  bool auto_fix = false;

  // Store the blocks in single precision (half the memory: a 10^7-pose pool
  // of 31 parameters takes 3.7 GB instead of 7.4 GB). The Jacobians are
  // computed in double in chunks of 65,536 poses and rounded to float as
  // each chunk is done, so the pool is never held in double; the
  // identifiability check runs on double Jacobians of its sampled poses.
  // The pool gets an exact source (CandidatePool::set_exact_source) that
  // recomputes any poses' blocks in double from a copy of the model,
  // parameters and joint values, for the certificate and the final log det.
  bool single_precision = false;

  // The markers seen at each pose (one mask per row of the joints; bit k:
  // marker k, e.g. PoseVerdict::targets_seen when the cell's targets are
  // the markers). Empty: each pose's block is marker 0's t rows (today's
  // pools). Given: each pose's block is t rows per marker of the model, in
  // marker order, marker k's rows zero where bit k is clear, so that only
  // the markers seen add information (a zero row adds none); a pose that
  // sees no marker is refused. At most 32 markers.
  std::vector<uint32_t> marker_masks;
};

// The marker mask with every marker of `model` (its first 32): a pose
// that measures them all (CandidatePoolOptions::marker_masks).
uint32_t EveryMarkerMask(const RobotModel& model);

struct CandidatePoolSummary {
  std::string message;                    // why it failed
  IdentifiabilityReport identifiability;  // of the pool, before any fixing
  FreeSet free;                           // the pool's columns' parameters
  std::vector<HeldParameter> held;        // held fixed by auto_fix
  int num_free_before = 0;                // free parameters before fixing
  double jacobian_seconds = 0.0;
};

// Builds the pool of the poses `joints` (one per row) at `parameters`, for
// the free parameters of `model`. With options.auto_fix, summary->free may
// hold fewer (summary->held names those held fixed). Returns false with
// summary->message on bad input or when the pool cannot identify the free
// parameters.
bool BuildCandidatePool(const RobotModel& model,
                        const Eigen::VectorXd& parameters,
                        const Eigen::MatrixXd& joints,
                        const CandidatePoolOptions& options,
                        CandidatePool* pool, CandidatePoolSummary* summary);

// The information of measurements already made, as whitened Jacobian rows
// R (so that M0 = R^T R): each measurement's rows at `parameters` (the
// current estimate: a next batch is designed where the robot is now),
// scaled to the reference noise sigma_m. A row whose measurement gives its
// own standard deviation (Measurement::sigma_m, sigma_rad; 0 = not given)
// is scaled by sigma_m / that value, the others by 1: position and
// distance rows by sigma_m / sigma_m[axis], pose rotation rows by
// sigma_m / (rotation_weight * sigma_rad). Returns false with the message
// of the first bad measurement.
bool MeasuredInformationRows(const RobotModel& model,
                             const Eigen::VectorXd& parameters,
                             const std::vector<Measurement>& measured,
                             double rotation_weight_m_per_rad, double sigma_m,
                             RowMatrixXd* rows, std::string* error);

// A fixed-seed random subset of the blocks of `block_rows` rows of
// `stacked`, whole and in pool order, of max_rows / block_rows blocks (all
// of it when it is not taller than max_rows). Deterministic.
Eigen::MatrixXd SampleBlocks(const RowMatrixXd& stacked, int block_rows,
                             int64_t max_rows);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_POOL_BUILDER_H_
