// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A hint for orientations read in the wrong convention.
//
// Pose measurements whose orientation was read in another Euler convention
// than the device's (intrinsic for extrinsic, XYZ for ZYX, a tracker's
// "Rx, Ry, Rz" taken for roll, pitch, yaw) still fit in position: the
// points are right, only the frames are turned, by a different rotation at
// every pose.
//
// The test does not depend on the device's frame or the target's
// orientation on the flange (both unknown before the fit, and pulled away
// by a fit to wrong orientations): between two poses i and j, the angle of
// the measured relative rotation R_i^T R_j equals the model's (an angle is
// the same in every frame), and the distance between the measured points
// equals the model's. PoseFitOf gives the RMS of both mismatches over the
// pairs of the first kPoseFitMaxPoses poses.
//
// The rule: the rotation mismatch above kOrientationHintRad (50 mrad) and
// above kOrientationHintRatio times the distance mismatch (m) as an angle
// at 1 m: orientations off by more than the points are. Correct data: the
// rotation mismatch about the device's noise and the robot's geometric
// errors (mrad), the hint silent. Misread angles: hundreds of mrad, while
// the points (right, but with a target point fitted to the wrong frames)
// are off by less (tenths of a metre at most on a 1.5 m robot).

#ifndef ACTIVECAL_ESTIMATION_ORIENTATION_CHECK_H_
#define ACTIVECAL_ESTIMATION_ORIENTATION_CHECK_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

inline constexpr double kOrientationHintRad = 0.05;
inline constexpr double kOrientationHintRatio = 1.0;
inline constexpr int kPoseFitMaxPoses = 200;

struct PoseFit {
  int num_poses = 0;
  double position_rms_m = 0;    // RMS distance mismatch over the pairs (m)
  double rotation_rms_rad = 0;  // RMS relative-angle mismatch (rad)
};

// The mismatches above of the pose measurements of `measurements` and the
// model at `parameters` (full vector); other types are not counted.
PoseFit PoseFitOf(const RobotModel& model, const Eigen::VectorXd& parameters,
                  const std::vector<Measurement>& measurements);

// True under the rule above.
bool OrientationFitsBadly(const PoseFit& fit);

// "orientations fit badly (between 40 poses, relative rotations differ
// from the model's by 612 mrad RMS, distances by 3.1 mm): check the orientation
// convention (<what>)": one line, for OrientationFitsBadly; `what` names the
// columns and convention read.
std::string OrientationHint(const PoseFit& fit, const std::string& what);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_ORIENTATION_CHECK_H_
