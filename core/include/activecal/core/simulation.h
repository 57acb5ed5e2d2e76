// Simulated measurements, for trying a calibration without hardware and for
// testing: the measured point computed from the true parameters plus
// i.i.d. Gaussian noise on each axis, reproducible for a seed.

#ifndef ACTIVECAL_CORE_SIMULATION_H_
#define ACTIVECAL_CORE_SIMULATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

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

}  // namespace activecal

#endif  // ACTIVECAL_CORE_SIMULATION_H_
