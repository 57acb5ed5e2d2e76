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
// does (lattice.h).

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

// `num_poses` poses (one per row, num_poses x num_joints) inside the joint
// ranges. Returns false with a message when a range is not finite or
// num_poses < 1.
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
