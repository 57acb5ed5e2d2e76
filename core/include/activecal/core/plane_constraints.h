// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Planes for a calibration without a tracker: the marker (the centre of a
// probe ball of radius r, r = 0 for a sharp tip) touched an unknown plane
// from several configurations (measurement.h, kPlane rows). The residual
// of a touch is its signed distance from the plane minus the radius,
// n . p - d - r.
//
// Each plane label is 3 unknowns of the fit, stored as 4 values (n, d): a
// unit normal n and the offset d (the plane is n . x = d). Ceres keeps n on
// the unit sphere (SphereManifold: each step is taken in the tangent plane
// at the current n and mapped back), so the parameterisation has no
// singular point: the naive choices have one in use. z = a x + b y + c
// cannot hold a vertical plane; a x + b y + c z = 1 cannot hold a plane
// through the origin (a table the base stands on); two angles of the
// normal lose one degree of freedom at their poles (a normal along the
// axis they turn about); n / d (the normal scaled by the inverse offset)
// is infinite at d = 0. A flipped normal with the opposite d is the same
// plane with the probe on the other side: the sign is fixed once, at the
// start (FitPlane), and the fit keeps it (a step never crosses the
// sphere's antipode).
//
// Eliminated (projected out of the Jacobian, jacobians.h), the plane's
// parameters leave what the touches say about the robot: a plane absorbs
// the base's translation along its normal and its tilt; touches of one
// plane cannot see the base's translation in the plane nor its rotation
// about the normal. Nor can planes see the scale: all lengths scaled by s
// about the base's origin move the touches of a plane by the same amount
// along its normal, (s - 1) (d + r), absorbed by its offset (unless one
// plane is touched with balls of different radii, which separate it only
// by (s - 1) times their difference). So a label needs at least three
// rows not on a line.

#ifndef ACTIVECAL_CORE_PLANE_CONSTRAINTS_H_
#define ACTIVECAL_CORE_PLANE_CONSTRAINTS_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// The labels of the planes of `measurements` (plane rows), each once, in
// order of first appearance.
std::vector<std::string> PlaneLabels(
    const std::vector<Measurement>& measurements);

// At least three rows of every plane label. False with a message naming
// the label and its first (0-based) measurement otherwise.
bool CheckPlaneLabels(const std::vector<Measurement>& measurements,
                      std::string* error);

// The signed distance n . p - d - radius of the touch at centre p from the
// plane (n, d) = (plane[0..2], plane[3]).
double PlaneResidual(const Eigen::Vector4d& plane, const Eigen::Vector3d& p,
                     double radius);

// Two orthonormal vectors perpendicular to the unit normal n (a basis of
// the tangent plane of the sphere at n).
Eigen::Matrix<double, 3, 2> PlaneTangentBasis(const Eigen::Vector3d& n);

// The least-squares plane of probe centres `centres` with radii `radii`:
// minimises the sum of PlaneResidual^2 over unit n and d. The normal's sign:
// towards the side the probe came from, the mean of flange - centre over
// the touches (`approach`, the tip frame's origin minus the centre; the
// stylus points from the flange to the plane); when that is zero, towards
// the base frame's origin; when the plane passes through it, the largest
// component of n positive. False with a message when the centres lie on a
// line (or fewer than 3).
bool FitPlane(const std::vector<Eigen::Vector3d>& centres,
              const std::vector<double>& radii,
              const std::vector<Eigen::Vector3d>& approach,
              Eigen::Vector4d* plane, std::string* error = nullptr);

// The fitted plane (FitPlane) of each label's plane rows at `parameters`
// (full vector), labels in PlaneLabels order; the approach of a touch is
// flange - centre, or minus the marker frame's z axis (TargetFrame) when
// the model puts the ball within 1 cm of the flange. False with the label when
// a plane's touches are on a line.
bool FitPlanes(const RobotModel& model, const Eigen::VectorXd& parameters,
               const std::vector<Measurement>& measurements,
               const std::vector<std::string>& labels,
               std::vector<Eigen::Vector4d>* planes,
               std::string* error = nullptr);

// Turns back each plane of `planes` (4 values a label, labels in
// PlaneLabels order) whose normal points away from the same label's in
// `reference` (a solver's step of pi on the sphere, from a start far off):
// with one probe radius r on the label's rows, (-n, -d - 2 r) is the same
// fit with every residual negated, and the normal's sign says on which side
// the probe is, so it is put back to the reference's side. A plane touched
// with several radii has no such twin and is left as it is.
void OrientPlanesLike(const Eigen::VectorXd& reference,
                      const std::vector<Measurement>& measurements,
                      const std::vector<std::string>& labels,
                      Eigen::VectorXd* planes);

// Simulated touches of the plane (n, d) = plane by the model at
// `parameters` (full vector), for tests and simulations: joints drawn
// uniformly in their ranges (Random(seed)), each moved to the nearest
// configuration (ReachPoint) that puts marker `marker` at radius_m from the
// plane, kept when it is reached, within the joint ranges and with the
// flange on the normal's side (the probe comes from there); up to
// num_touches rows of type kPlane labelled `label`. Fewer when 200 draws
// per touch do not find them.
std::vector<Measurement> SimulatePlaneTouches(const RobotModel& model,
                                              const Eigen::VectorXd& parameters,
                                              const std::string& label,
                                              const Eigen::Vector4d& plane,
                                              double radius_m, int num_touches,
                                              uint64_t seed, int marker = 0);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_PLANE_CONSTRAINTS_H_
