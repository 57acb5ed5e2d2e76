// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Simulated measurements, for trying a calibration without hardware and for
// testing: the measured point computed from the true parameters plus
// i.i.d. Gaussian noise on each axis, reproducible for a seed.

#ifndef ACTIVECAL_CORE_SIMULATION_H_
#define ACTIVECAL_CORE_SIMULATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/lattice.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// Standard deviations of the simulated device noise.
struct SimulationNoise {
  // On each axis of a measured point, and on a measured distance (m).
  double position_m = 0.0;
  // On each component of a pose's rotation vector, applied in the target
  // frame: R_measured = R_true * Exp(noise) (rad).
  double rotation_rad = 0.0;
};

// The measurements a device would report for `plan` (type and joints of
// each measurement; the measured values are ignored), from the full
// parameter vector `true_parameters`, with Gaussian noise. Reproducible for
// a seed. Returns false with a message naming the measurement on bad input.
bool SimulateMeasurements(const RobotModel& model,
                          const Eigen::VectorXd& true_parameters,
                          const std::vector<Measurement>& plan,
                          const SimulationNoise& noise, uint64_t seed,
                          std::vector<Measurement>* out, std::string* error);

// The plan of measurements of `type` at the rows of `joints` (num_poses x
// num_joints) that SimulateMeasurements takes: kPosition or kPose one at
// each row (MeasurementPlan), kDistance one between each pair of
// consecutive rows (0-1, 1-2, ...). For kDistance false with
// *identical_row -1 when there are fewer than 2 rows, or the first of two
// identical consecutive rows (0-based; a distance between them measures
// nothing). What activecal_simulate and the Python module's simulate
// measure.
bool SimulationPlan(const Eigen::MatrixXd& joints, MeasurementType type,
                    std::vector<Measurement>* plan, int* identical_row);

// A simulated session at random lattice poses (what activecal_identify
// simulates without --measurements): num_poses distinct poses of `lattice`
// drawn without replacement (Random stream (seed, 0); their indices in
// *poses), each measured in position with noise_m per axis (stream
// (seed, 1)). False with *error "num_poses must be in [1, N], got k" or
// SimulateMeasurements' message.
bool SimulateAtRandomLatticePoses(const RobotModel& model,
                                  const Eigen::VectorXd& true_parameters,
                                  const JointLattice& lattice, int num_poses,
                                  double noise_m, uint64_t seed,
                                  std::vector<int64_t>* poses,
                                  std::vector<Measurement>* out,
                                  std::string* error);

// The parameters of a simulated robot whose file has no true values (a
// URDF): `values` (a full parameter vector, e.g. the nominal) with every
// free parameter of `model` moved by an independent Gaussian draw, a length
// (ParameterKind::kLength) with standard deviation length_std_m, an angle
// (kAngle) with angle_std_rad; the other free parameters (gains) and every
// fixed one keep their values. One draw per free parameter in
// FreeParameterIndices order from Random stream (seed, 0x5eed), so the
// result is the same for a seed whatever the caller. What
// activecal_simulate, activecal_sim_cell (--perturb_m, --perturb_rad) and
// the Python module's Robot.perturbed compute. False with *error
// ("perturb_m must be >= 0 and finite, got -1") for a negative or
// non-finite standard deviation or values of the wrong size.
bool PerturbParameters(const RobotModel& model, const Eigen::VectorXd& values,
                       double length_std_m, double angle_std_rad, uint64_t seed,
                       Eigen::VectorXd* perturbed, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_SIMULATION_H_
