// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/measurement.h"

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/validation.h"

namespace activecal {
namespace {

// The count and finiteness of measured joint readings, and their ranges
// widened by the tolerance for measured joints.
bool MeasuredJointsValid(const RobotModel& model, const Eigen::VectorXd& q,
                         std::string* why) {
  return model.CheckJointValues(q, why, kMeasuredJointToleranceRad,
                                kMeasuredJointToleranceM);
}

}  // namespace

int MeasurementDimension(MeasurementType type) {
  switch (type) {
    case MeasurementType::kPosition:
    case MeasurementType::kPoint:
      return 3;
    case MeasurementType::kPose:
      return 6;
    case MeasurementType::kDistance:
    case MeasurementType::kPointDistance:
    case MeasurementType::kPlane:
      return 1;
  }
  return 0;
}

constexpr const char* kMeasurementTypeNames[] = {
    "position", "pose", "distance", "point", "point_distance", "plane"};

const char* MeasurementTypeName(MeasurementType type) {
  return EnumToString(kMeasurementTypeNames, type);
}

bool ParseMeasurementType(const std::string& name, MeasurementType* type) {
  return StringToEnum(kMeasurementTypeNames, name, type);
}

bool CheckMeasurement(const RobotModel& model, const Measurement& m,
                      std::string* error) {
  std::string why;
  if (m.marker < 0 || m.marker >= model.num_markers()) {
    if (error) {
      *error = "marker " + std::to_string(m.marker + 1) +
               " is not a marker of the model (it has " +
               std::to_string(model.num_markers()) + ")";
    }
    return false;
  }
  if (m.type == MeasurementType::kPointDistance) {
    // No joints: a relation between two fixed points.
    std::ostringstream bad;
    if (m.point.empty() || m.point2.empty()) {
      bad << "a point distance needs two point labels";
    } else if (m.point == m.point2) {
      bad << "a point distance between point '" << m.point
          << "' and itself measures nothing";
    } else if (!std::isfinite(m.distance) || m.distance < 0) {
      bad << "known distance must be finite and >= 0, got " << m.distance;
    } else if (!std::isfinite(m.sigma_m[0]) || m.sigma_m[0] < 0) {
      bad << "distance standard deviation (sigma_m) must be finite and >= 0";
    }
    if (bad.tellp() == 0) return true;
    if (error) *error = bad.str();
    return false;
  }
  // Joint readings are what the robot did: they may lie beyond the joint
  // ranges by the tolerance for measured joints (planned poses may not).
  if (!MeasuredJointsValid(model, m.joints, &why)) {
    if (error) *error = "joints: " + why;
    return false;
  }
  std::ostringstream msg;
  if (!m.sigma_m.allFinite() || (m.sigma_m.array() < 0).any()) {
    msg << "measurement standard deviation (sigma_m) must be finite and >= 0";
  } else if (!std::isfinite(m.sigma_rad) || m.sigma_rad < 0) {
    msg << "measurement standard deviation (sigma_rad) must be finite and >= 0";
  }
  if (msg.tellp() != 0) {
    if (error) *error = msg.str();
    return false;
  }
  switch (m.type) {
    case MeasurementType::kPosition:
    case MeasurementType::kPose:
      if (!m.position.allFinite()) {
        msg << "measured position is not finite";
      } else if (m.type == MeasurementType::kPose && !m.rotation.allFinite()) {
        msg << "measured rotation is not finite";
      } else if (m.type == MeasurementType::kPose &&
                 m.rotation.norm() > M_PI + 1e-9) {
        msg << "measured rotation vector has angle " << m.rotation.norm()
            << " rad > pi";
      }
      break;
    case MeasurementType::kDistance:
      if (!MeasuredJointsValid(model, m.joints2, &why)) {
        msg << "second pose joints: " << why;
      } else if (m.joints == m.joints2) {
        msg << "a distance between two identical poses (the same joint "
               "values twice) measures nothing: its Jacobian is undefined";
      } else if (!std::isfinite(m.distance) || m.distance < 0) {
        msg << "measured distance must be finite and >= 0, got " << m.distance;
      }
      break;
    case MeasurementType::kPoint:
      if (m.point.empty()) msg << "a point row needs a point label";
      break;
    case MeasurementType::kPointDistance:
      break;  // checked above
    case MeasurementType::kPlane:
      if (m.plane.empty()) {
        msg << "a plane row needs a plane label";
      } else if (!std::isfinite(m.probe_radius_m) || m.probe_radius_m < 0) {
        msg << "probe radius must be finite and >= 0, got " << m.probe_radius_m;
      }
      break;
  }
  return FinishValidation(msg, error);
}

std::vector<Measurement> MeasurementPlan(const Eigen::MatrixXd& joints,
                                         MeasurementType type) {
  std::vector<Measurement> plan(joints.rows());
  for (int i = 0; i < joints.rows(); ++i) {
    plan[i].type = type;
    plan[i].joints = joints.row(i).transpose();
  }
  return plan;
}

Measurement PredictMeasurement(const RobotModel& model,
                               const Eigen::VectorXd& parameters,
                               const Measurement& like) {
  Measurement out = like;
  // A known distance between fixed points depends on no pose.
  if (like.type == MeasurementType::kPointDistance) return out;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  TargetFrame(model, parameters, like.joints, &R, &t, like.marker);
  out.position = t;
  out.rotation.setZero();
  out.distance = 0.0;
  if (like.type == MeasurementType::kPose) {
    const Eigen::AngleAxisd aa(R);
    out.rotation = aa.angle() * aa.axis();
  } else if (like.type == MeasurementType::kDistance) {
    out.position.setZero();
    out.distance =
        (t - MeasuredPoint(model, parameters, like.joints2, like.marker))
            .norm();
  }
  return out;
}

}  // namespace activecal
