// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/simulation.h"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>
#include <utility>

#include "activecal/core/kinematics.h"
#include "activecal/core/random.h"

namespace activecal {
namespace {

bool CheckNoise(double sigma, const char* what, std::string* error) {
  if (sigma >= 0.0 && std::isfinite(sigma)) return true;
  if (error) {
    std::ostringstream msg;
    msg << "simulation: " << what
        << " noise standard deviation must be finite and >= 0, got " << sigma;
    *error = msg.str();
  }
  return false;
}

}  // namespace

bool SimulateMeasurements(const RobotModel& model,
                          const Eigen::VectorXd& true_parameters,
                          const std::vector<Measurement>& plan,
                          const SimulationNoise& noise, uint64_t seed,
                          std::vector<Measurement>* out, std::string* error) {
  if (!model.CheckParameters(true_parameters, error)) return false;
  if (!CheckNoise(noise.position_m, "position", error) ||
      !CheckNoise(noise.rotation_rad, "rotation", error)) {
    return false;
  }
  std::vector<Measurement> result;
  result.reserve(plan.size());
  Random random(seed);
  for (size_t i = 0; i < plan.size(); ++i) {
    Measurement like = plan[i];
    like.position.setZero();
    like.rotation.setZero();
    like.distance = 0.0;
    std::string why;
    if (!CheckMeasurement(model, like, &why)) {
      if (error) {
        *error = "simulation: measurement " + std::to_string(i) + ": " + why;
      }
      return false;
    }
    Measurement m = PredictMeasurement(model, true_parameters, like);
    if (m.type == MeasurementType::kDistance && m.distance < 1e-12) {
      if (error) {
        *error = "simulation: measurement " + std::to_string(i) +
                 ": its two poses put the measured point at the same place "
                 "(e.g. a joint one turn apart): a distance between them "
                 "measures nothing";
      }
      return false;
    }
    switch (m.type) {
      case MeasurementType::kPosition:
        for (int k = 0; k < 3; ++k) {
          m.position[k] += noise.position_m * random.Gaussian();
        }
        break;
      case MeasurementType::kPose: {
        for (int k = 0; k < 3; ++k) {
          m.position[k] += noise.position_m * random.Gaussian();
        }
        Eigen::Vector3d w;
        for (int k = 0; k < 3; ++k)
          w[k] = noise.rotation_rad * random.Gaussian();
        const Eigen::Matrix3d R_true =
            Eigen::AngleAxisd(m.rotation.norm(),
                              m.rotation.norm() > 0
                                  ? Eigen::Vector3d(m.rotation.normalized())
                                  : Eigen::Vector3d::UnitX())
                .toRotationMatrix();
        const Eigen::Matrix3d R_noise =
            w.norm() > 0
                ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
                : Eigen::Matrix3d::Identity();
        const Eigen::AngleAxisd aa(R_true * R_noise);
        m.rotation = aa.angle() * aa.axis();
        break;
      }
      case MeasurementType::kDistance:
      case MeasurementType::kPointDistance:
        m.distance += noise.position_m * random.Gaussian();
        break;
      case MeasurementType::kPlane:
      case MeasurementType::kPoint:
        // No measured value: where the marker sat about the point is in
        // the joints the plan gives (ReachPoint, point_reach.h).
        break;
    }
    result.push_back(std::move(m));
  }
  *out = std::move(result);
  return true;
}

bool SimulateAtRandomLatticePoses(const RobotModel& model,
                                  const Eigen::VectorXd& true_parameters,
                                  const JointLattice& lattice, int num_poses,
                                  double noise_m, uint64_t seed,
                                  std::vector<int64_t>* poses,
                                  std::vector<Measurement>* out,
                                  std::string* error) {
  if (num_poses <= 0 || num_poses > lattice.size()) {
    *error = "num_poses must be in [1, " + std::to_string(lattice.size()) +
             "], got " + std::to_string(num_poses);
    return false;
  }
  Random random(Random::StreamSeed(seed, 0));
  *poses = random.SampleWithoutReplacement(lattice.size(), num_poses);
  std::vector<Measurement> plan(poses->size());
  for (size_t i = 0; i < poses->size(); ++i) {
    plan[i].joints = lattice.JointValues((*poses)[i]);
  }
  SimulationNoise noise;
  noise.position_m = noise_m;
  return SimulateMeasurements(model, true_parameters, plan, noise,
                              Random::StreamSeed(seed, 1), out, error);
}

bool SimulationPlan(const Eigen::MatrixXd& joints, MeasurementType type,
                    std::vector<Measurement>* plan, int* identical_row) {
  plan->clear();
  *identical_row = -1;
  if (type != MeasurementType::kDistance) {
    *plan = MeasurementPlan(joints, type);
    return true;
  }
  const int n = static_cast<int>(joints.rows());
  if (n < 2) return false;
  for (int i = 0; i + 1 < n; ++i) {
    if (joints.row(i) == joints.row(i + 1)) {
      plan->clear();
      *identical_row = i;
      return false;
    }
    Measurement m;
    m.type = type;
    m.joints = joints.row(i).transpose();
    m.joints2 = joints.row(i + 1).transpose();
    plan->push_back(m);
  }
  return true;
}

bool PerturbParameters(const RobotModel& model, const Eigen::VectorXd& values,
                       double length_std_m, double angle_std_rad, uint64_t seed,
                       Eigen::VectorXd* perturbed, std::string* error) {
  for (const auto& [name, sigma] :
       {std::pair<const char*, double>{"perturb_m", length_std_m},
        {"perturb_rad", angle_std_rad}}) {
    if (!(sigma >= 0.0 && std::isfinite(sigma))) {
      if (error) {
        std::ostringstream msg;
        msg << name << " must be >= 0 and finite, got " << sigma;
        *error = msg.str();
      }
      return false;
    }
  }
  if (values.size() != model.num_parameters()) {
    if (error) {
      *error = "perturbation: " + std::to_string(values.size()) +
               " parameter values for a model of " +
               std::to_string(model.num_parameters());
    }
    return false;
  }
  *perturbed = values;
  Random random(Random::StreamSeed(seed, 0x5eed));
  for (int i : model.FreeParameterIndices()) {
    const ParameterKind kind = model.Kind(i);
    const double g = random.Gaussian();
    if (kind == ParameterKind::kLength) (*perturbed)[i] += length_std_m * g;
    if (kind == ParameterKind::kAngle) (*perturbed)[i] += angle_std_rad * g;
  }
  return true;
}

}  // namespace activecal
