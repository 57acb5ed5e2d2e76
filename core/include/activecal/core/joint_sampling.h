// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Candidate poses beyond the lattice: quasi-random (Sobol) or random joint
// values inside the model's joint ranges, for any number of joints. A
// lattice of L levels on n joints has L^n poses and covers a 7- or 8-axis
// arm's space badly; a Sobol sequence of any size fills it evenly (its
// projections on every joint and pair of joints stay uniform).
//
//   Eigen::MatrixXd joints;
//   if (!SampleJointValues(model, JointSampling::kSobol, 1000000, seed,
//                          &joints, &error)) { ... }
//
// Sobol points come from Boost's sobol engine (Joe and Kuo's direction
// numbers, integer arithmetic: the same on every platform), digitally
// shifted by a seeded random word per joint (a shift keeps the net's
// uniformity and moves the first point off the corner of the ranges).
// Random points use Random (random.h). A revolute joint whose range spans a
// full turn is sampled over one turn from its lower limit, as the lattice
// does (lattice.h); a continuous joint (no limits) over one turn from -pi,
// [-pi, pi).

#ifndef ACTIVECAL_CORE_JOINT_SAMPLING_H_
#define ACTIVECAL_CORE_JOINT_SAMPLING_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "activecal/core/robot_model.h"

namespace activecal {

enum class JointSampling {
  kSobol,   // quasi-random, digitally shifted by the seed
  kRandom,  // independent uniform draws
};

// "sobol" or "random"; false for another name.
bool JointSamplingFromString(const std::string& name, JointSampling* sampling);

// The interval [*low, *low + *width) a pool takes a joint's values from:
// its range, both ends included (*one_turn false), for a range narrower
// than a turn; one turn, its end left out (*one_turn true: it is the start
// again), for a revolute joint whose range spans a turn or more (from its
// lower limit) or is unbounded (a continuous joint: from -pi; bounded
// above only: from upper - 2 pi; below only: from lower). False with the
// reason in *why (naming the joint, 1-based j) for a prismatic joint
// without a finite range.
bool PoolJointRange(const RobotModel& model, int j, double* low, double* width,
                    bool* one_turn, std::string* why);

// `num_poses` poses (one per row, num_poses x num_joints) inside the joint
// ranges (PoolJointRange). Returns false with a message for a prismatic
// joint without a finite range or num_poses < 1.
bool SampleJointValues(const RobotModel& model, JointSampling sampling,
                       int64_t num_poses, uint64_t seed,
                       Eigen::MatrixXd* joints, std::string* error);

// At most max_rows of `rows`, a fixed-seed random subset in their order (all
// of them when there are no more): what an analysis of a large pool looks
// at. Not every k-th row: a stride equal to a lattice's level count would
// hold the last joint at one value in every row kept. Deterministic.
Eigen::MatrixXd SubsampleRows(const Eigen::MatrixXd& rows, int64_t max_rows);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_JOINT_SAMPLING_H_
