// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// What a measuring device reports about the robot, one struct for every
// kind: a 3D position (laser tracker, stereo camera), a full 6D pose (a
// tracker with a 6D probe), or the distance between the measured points of
// two poses (a ballbar or a length artefact). Without a tracker: the marker
// at a fixed point whose coordinates are unknown (a ball in a socket of a
// block, reached from several configurations), and a known distance
// between two such points (point_constraints.h). Measurements of different
// kinds can be mixed freely in one identification.
//
// Units: metres and radians. Orientations are rotation vectors (axis times
// angle, radians) of the target frame in the device's frame.

#ifndef ACTIVECAL_CORE_MEASUREMENT_H_
#define ACTIVECAL_CORE_MEASUREMENT_H_

#include <Eigen/Core>
#include <cmath>
#include <string>

#include "activecal/core/robot_model.h"

namespace activecal {

enum class MeasurementType {
  kPosition,  // the measured point: 3 rows (m)
  kPose,      // point and target orientation: 6 rows (m, then weighted rad)
  kDistance,  // distance between the points of two poses: 1 row (m)
  // The marker was at the fixed point `point` (a label), whose 3
  // coordinates in the device frame (the robot's base frame when no row
  // sees a device) are unknowns of the fit: 3 rows (m), predicted point -
  // the point's coordinates.
  kPoint,
  // A known distance between fixed points `point` and `point2` (no
  // joints): 1 row (m), |c(point) - c(point2)| - distance.
  kPointDistance,
  // The marker touched the unknown plane `plane` (a label), with a probe
  // ball of radius probe_radius_m whose centre is the marker: 1 row (m),
  // n . p - d - probe_radius_m, the plane (n, d) an extra parameter block
  // of 4 (unit normal n, offset d; 3 degrees of freedom,
  // plane_constraints.h).
  kPlane,
};

// Rows of the residual and of the Jacobian: 3, 6, 1, 3, 1 or 1.
int MeasurementDimension(MeasurementType type);
// "position", "pose", "distance", "point", "point_distance", "plane".
const char* MeasurementTypeName(MeasurementType type);
// Parses a name above; false if unknown.
bool ParseMeasurementType(const std::string& name, MeasurementType* type);

struct Measurement {
  MeasurementType type = MeasurementType::kPosition;
  // Joint readings of the pose (the first pose for a distance).
  Eigen::VectorXd joints;
  // Distance only: joint readings of the second pose.
  Eigen::VectorXd joints2;
  // Position and pose: the measured point (m).
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  // Pose only: rotation vector of the target frame (rad).
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();
  // Distance and point distance: the measured distance (m).
  double distance = 0.0;
  // Point: the fixed point's label; point distance: its two points' labels.
  std::string point;
  std::string point2;
  // Plane: the touched plane's label, and the probe radius (m, >= 0): the
  // marker (the probe ball's centre) lies at this signed distance from the
  // plane, on the side its normal points to.
  std::string plane;
  double probe_radius_m = 0.0;
  // The marker (measured point) of the model this measurement sees,
  // 0-based; a distance is between two positions of the same marker.
  int marker = 0;
  // Standard deviations of the measured values when the device reports them
  // (zero: not given; the identification then uses its own noise options).
  // Position, pose and point: of the point's x, y, z (m); distance and point
  // distance: sigma_m[0] is the distance's (m).
  Eigen::Vector3d sigma_m = Eigen::Vector3d::Zero();
  // Pose only: of each rotation-vector component (rad); zero: not given.
  double sigma_rad = 0.0;

  int dimension() const { return MeasurementDimension(type); }
  // True for the rows whose residual involves constraint parameters that
  // are not the model's: fixed-point coordinates or a plane.
  bool involves_points() const {
    return type == MeasurementType::kPoint ||
           type == MeasurementType::kPointDistance ||
           type == MeasurementType::kPlane;
  }
};

// How far beyond its joint range a measured joint reading may lie. Real
// readings do lie slightly outside the nominal limits (a torso reads
// 0.35018 m against a 0.35 m limit); farther out is a wrong file or wrong
// units. Planned poses (pools, poses files, lattices) keep to the ranges.
inline constexpr double kMeasuredJointToleranceRad = 5.0 * M_PI / 180.0;
inline constexpr double kMeasuredJointToleranceM = 0.01;  // prismatic

// Checks a measurement against the model: joint counts, finiteness, joint
// readings within their ranges widened by the tolerances above, a
// non-negative distance, point labels given (and two different ones for a
// point distance, which has no joints). The message names the field.
bool CheckMeasurement(const RobotModel& model, const Measurement& measurement,
                      std::string* error);

// A plan of one measurement of `type` (kPosition or kPose: one pose each)
// at each row of `joints` (num_poses x num_joints), measured values zero:
// what SimulateMeasurements and the Jacobian functions take. (A distance
// needs two poses: its joints2 stays empty, which CheckMeasurement refuses.)
std::vector<Measurement> MeasurementPlan(
    const Eigen::MatrixXd& joints,
    MeasurementType type = MeasurementType::kPosition);

// The measurement the device would report at `parameters` (full vector),
// without noise, for the joints (and type) of `like`.
Measurement PredictMeasurement(const RobotModel& model,
                               const Eigen::VectorXd& parameters,
                               const Measurement& like);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_MEASUREMENT_H_
