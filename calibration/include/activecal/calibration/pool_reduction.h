// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The parameters a pool of poses can separate: a named parameter set
// (core/parameter_sets.h) reduced (estimation/parameter_reduction.h) on
// the measurements a design over the pool could plan, with, when a cell's
// targets are the markers, each pose's rows those of the markers it sees.
// One implementation for activecal_select (BuildSelectionPool),
// activecal_active, activecal_sim_cell and activecal_simulate.
//
//   PoolReduction reduction;
//   if (!ReduceForPool(model, ParameterSet::kFull, joints, &seen_masks,
//                      PoolReductionOptions(), &reduction))
//     ...reduction.message...
//   model = WithFreeSet(model, reduction.free);
//   // reduction.held[k] = {"back.x", "marker 'back' is seen at none of the
//   //                      1200 poses of the pool", kParameterSet}

#ifndef ACTIVECAL_CALIBRATION_POOL_REDUCTION_H_
#define ACTIVECAL_CALIBRATION_POOL_REDUCTION_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/free_set.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"

namespace activecal {

struct PoolReductionOptions {
  MeasurementType type = MeasurementType::kPosition;  // position or pose
  double rotation_weight_m_per_rad = 1.0;
  // The analysis looks at most this many poses of the pool, in pool
  // order: a fixed-seed random subset (SubsampleRows, core/joint_sampling.h),
  // or with evenly_spaced rows i * N / sample_size (activecal_active's and
  // activecal_sim_cell's subset since they reduce, kept so that their
  // outputs do not change; a stride equal to a lattice's level count would
  // hold the last joint at one value).
  int64_t sample_size = 2000;
  bool evenly_spaced = false;
};

struct PoolReduction {
  FreeSet free;           // the parameters to identify
  Eigen::VectorXd point;  // the analysis point (ReduceParameterSet's)
  // What the reduction held, in priority order. A parameter of a marker
  // that no mask shows seen at any pose of the pool has the reason
  // "marker '<name>' is seen at none of the <N> poses of the pool".
  std::vector<HeldParameter> held;
  std::string message;  // why it failed
};

// Reduces `set` on `model` to what measurements of type options.type at
// the rows of `joints` (SI, one pose per row) separate, analysed at
// model.nominal (ReduceParameterSet). seen_masks: null, each pose plans
// marker 0; otherwise one mask per row of `joints` (bit k: marker k is
// seen, e.g. PoseVerdict::targets_seen), each pose planning the markers
// seen (markers 32 and above: never). False with *message (what
// ReduceParameterSet says, or a mask count that does not match the pool)
// when nothing is left to identify or the input is wrong.
bool ReduceForPool(const RobotModel& model, ParameterSet set,
                   const Eigen::MatrixXd& joints,
                   const std::vector<uint32_t>* seen_masks,
                   const PoolReductionOptions& options, PoolReduction* result);

// The lines a program prints for the parameters the reduction of `set`
// held, one each: "  --parameter_set=<set>: <name> held fixed: <reason>\n".
std::string HeldFixedLines(ParameterSet set,
                           const std::vector<HeldParameter>& held);

// The reduction of the programs that reduce their model themselves
// (activecal_active, activecal_sim_cell, activecal_simulate): ReduceForPool
// of *model on evenly spaced rows, then *model's free set the reduced one
// and HeldFixedLines appended to *report. False with *error
// "--parameter_set=<set>: <why>" (*model untouched). reduction (may be
// null): the whole result.
bool ReduceModelForPool(ParameterSet set, const Eigen::MatrixXd& joints,
                        const std::vector<uint32_t>* seen_masks,
                        RobotModel* model, std::string* report,
                        std::string* error, PoolReduction* reduction = nullptr);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_POOL_REDUCTION_H_
