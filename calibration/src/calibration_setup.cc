// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/calibration_setup.h"

#include <cmath>
#include <sstream>

#include "activecal/calibration/selection_pool.h"
#include "activecal/core/joint_errors.h"
#include "activecal/core/lattice.h"
#include "activecal/core/simulation.h"
#include "activecal/io/urdf_inertials.h"

namespace activecal {

bool ParseVector3(const std::string& text, Eigen::Vector3d* v) {
  std::istringstream in(text);
  char c1 = 0, c2 = 0;
  double x, y, z;
  if (!(in >> x >> c1 >> y >> c2 >> z) || c1 != ',' || c2 != ',') return false;
  std::string rest;
  if (in >> rest) return false;
  *v = Eigen::Vector3d(x, y, z);
  return v->allFinite();
}

bool MakeTermFamilies(const RobotModel& model, const TermFamilyOptions& o,
                      OptionSpelling spelling,
                      std::vector<TermFamily>* families, std::string* error) {
  const std::string p = spelling == OptionSpelling::kFlags ? "--" : "";
  auto fail = [&](const std::string& message) {
    *error = message;
    return false;
  };
  families->clear();
  if (!o.payload_com_m.empty() && !(o.payload_kg > 0)) {
    return fail(p + "payload_com_m needs " + p +
                "payload_kg > 0 (a payload without mass)");
  }
  if (!(o.payload_kg >= 0) || !std::isfinite(o.payload_kg)) {
    return fail(p + "payload_kg must be finite and >= 0");
  }
  if (o.harmonics < 0 || o.harmonics > 8) {
    return fail(p + "harmonics must be in [0, 8], got " +
                std::to_string(o.harmonics));
  }
  if (o.compliance) {
    GravityModel gravity;
    if (!ParseVector3(o.gravity, &gravity.gravity)) {
      return fail(p + "gravity: expected 'x,y,z' in m/s^2, got '" + o.gravity +
                  "'");
    }
    gravity.payload_kg = o.payload_kg;
    if (!o.payload_com_m.empty() &&
        !ParseVector3(o.payload_com_m, &gravity.payload_com_m)) {
      return fail(p + "payload_com_m: expected 'x,y,z' in m, got '" +
                  o.payload_com_m + "'");
    }
    std::string why;
    if (o.urdf_robot) {
      if (!LoadUrdfInertials(o.robot_path, o.chain, &gravity, &why)) {
        return fail(p + "compliance: " + why);
      }
    } else if (!(o.payload_kg > 0)) {
      return fail(p + "compliance needs link masses: " + p + "robot " +
                  o.robot_path +
                  " is not a URDF with <inertial> elements; give a URDF or " +
                  p + "payload_kg");
    }
    families->push_back({"compliance", ComplianceTerms(model, gravity)});
  } else if (o.payload_kg > 0) {
    return fail(p + "payload_kg is used by " + p + "compliance only");
  }
  if (o.harmonics > 0) {
    families->push_back({"periodic", HarmonicTerms(model, o.harmonics)});
  }
  return true;
}

bool CheckOptionsBeforeReading(const CalibrationOptions& options,
                               bool validation_file,
                               const CalibrationTextOptions& text,
                               std::string* error) {
  if (!options.LearnedResidualIsValid(error)) {
    *error = OptionsErrorText(*error, text);
    return false;
  }
  const std::string p =
      text.option_spelling == OptionSpelling::kFlags ? "--" : "";
  const bool by_validation =
      options.ResolvedModelSelection() == ModelSelectionMethod::kValidation;
  if (by_validation && !validation_file) {
    *error = p + "model_selection=validation needs " + p + "validation=FILE";
    return false;
  }
  if (!by_validation && validation_file) {
    *error =
        p + "validation is used by " + p + "model_selection=validation only";
    return false;
  }
  return true;
}

bool SimulateCalibrationMeasurements(
    const RobotDescription& robot, const CalibrationSimulationOptions& options,
    OptionSpelling spelling, std::vector<int64_t>* poses,
    std::vector<Measurement>* measurements, std::string* notes,
    std::string* error) {
  const std::string p = spelling == OptionSpelling::kFlags ? "--" : "";
  const RobotModel& model = robot.model;
  notes->clear();
  if (robot.true_parameters.size() != model.num_parameters()) {
    *error = "no " + p + "measurements given and " + p +
             "robot has no true values to simulate from (add 'true:' "
             "entries, see docs/formats.md)";
    return false;
  }
  JointLattice lattice;
  if (!MakeLatticePool(model, nullptr, options.levels,
                       MeasurementType::kPosition, p, &lattice, notes, error)) {
    return false;
  }
  if (!SimulateAtRandomLatticePoses(model, robot.true_parameters, lattice,
                                    options.num_poses, options.noise_m,
                                    options.seed, poses, measurements, error)) {
    *error = p + *error;
    return false;
  }
  if (options.points) {
    *error = p + "points needs " + p + "measurements with type=point rows";
    return false;
  }
  return true;
}

}  // namespace activecal
