#include "activecal/core/simulation.h"

#include <cmath>
#include <sstream>

#include "activecal/core/kinematics.h"
#include "activecal/core/random.h"

namespace activecal {

bool SimulatePositionMeasurements(const RobotModel& model,
                                  const Eigen::VectorXd& true_parameters,
                                  const Eigen::MatrixXd& joints, double noise_m,
                                  uint64_t seed,
                                  std::vector<PositionMeasurement>* out,
                                  std::string* error) {
  if (!model.CheckParameters(true_parameters, error)) return false;
  if (!(noise_m >= 0.0) || !std::isfinite(noise_m)) {
    if (error) {
      std::ostringstream msg;
      msg << "simulation: noise standard deviation must be finite and >= 0, "
          << "got " << noise_m;
      *error = msg.str();
    }
    return false;
  }
  std::vector<PositionMeasurement> result;
  result.reserve(joints.rows());
  Random random(seed);
  for (int i = 0; i < joints.rows(); ++i) {
    const Eigen::VectorXd q = joints.row(i).transpose();
    std::string why;
    if (!model.CheckJointValues(q, &why)) {
      if (error) *error = "simulation: pose " + std::to_string(i) + ": " + why;
      return false;
    }
    PositionMeasurement m;
    m.joints = q;
    m.position = MeasuredPoint(model, true_parameters, q);
    for (int k = 0; k < 3; ++k) m.position[k] += noise_m * random.Gaussian();
    result.push_back(std::move(m));
  }
  *out = std::move(result);
  return true;
}

}  // namespace activecal
