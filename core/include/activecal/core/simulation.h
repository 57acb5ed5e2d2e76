// Simulated measurements, for trying a calibration without hardware and for
// testing: the measured point computed from the true parameters plus
// i.i.d. Gaussian noise on each axis, reproducible for a seed.

#ifndef ACTIVECAL_CORE_SIMULATION_H_
#define ACTIVECAL_CORE_SIMULATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/robot_model.h"

namespace activecal {

// One 3D position measurement: the joint readings and the point the device
// measured, in metres in the device's frame.
struct PositionMeasurement {
  Eigen::VectorXd joints;
  Eigen::Vector3d position;
};

// Measurements at each row of `joints` (num_poses x num_joints), from the
// full parameter vector `true_parameters`, with noise of standard deviation
// noise_m (metres) on each axis. Returns false with a message on bad input
// (sizes, non-finite values, joints out of range, negative noise).
bool SimulatePositionMeasurements(const RobotModel& model,
                                  const Eigen::VectorXd& true_parameters,
                                  const Eigen::MatrixXd& joints, double noise_m,
                                  uint64_t seed,
                                  std::vector<PositionMeasurement>* out,
                                  std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_SIMULATION_H_
