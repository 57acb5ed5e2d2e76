// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// ISO 9283:1998 section 7.2: pose accuracy (AP) and pose repeatability (RP)
// of n cycles to one commanded pose, the figures robot data sheets quote.
//
//   Iso9283PoseResult r;
//   if (!Iso9283Pose(commanded, attained, &r, &error)) ...
//   r.ap_p_m, r.rp_l_m, r.ap_rad, r.rp_rad
//
// All in the robot's base frame (register the device first), SI units.
// Position (7.2.1, 7.2.2), with x_j the attained positions, j = 1..n:
//   x_bar = (1/n) sum x_j                     (the barycentre)
//   AP_p = |x_bar - x_c|                      (and its components AP_x,y,z)
//   l_j = |x_j - x_bar|,  l_bar = (1/n) sum l_j
//   S_l = sqrt(sum (l_j - l_bar)^2 / (n - 1)),  RP_l = l_bar + 3 S_l
// Orientation: ISO writes a, b, c for the rotations about the base's x, y,
// z axes and takes AP_a = a_bar - a_c, RP_a = +-3 S_a. Here the deviation
// of cycle j is the rotation vector d_j = log(R_j R_c^T) (rad, about the
// base's x, y, z): the same as ISO's angle differences for the small
// deviations a robot has (to first order), and free of the Euler-angle
// singularity at pitch +-90 deg and of angle wrapping (never an RPY
// round trip). Then
//   AP_(a,b,c) = d_bar = (1/n) sum d_j
//   S_a = sqrt(sum (d_j,x - d_bar,x)^2 / (n - 1)),  RP_a = 3 S_a (+-)
// and likewise b (y) and c (z).

#ifndef ACTIVECAL_ESTIMATION_ISO9283_H_
#define ACTIVECAL_ESTIMATION_ISO9283_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace activecal {

struct Iso9283Sample {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, base frame
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

struct Iso9283PoseResult {
  int num_cycles = 0;
  Eigen::Vector3d barycentre_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d ap_xyz_m = Eigen::Vector3d::Zero();  // x_bar - x_c
  double ap_p_m = 0.0;
  double l_bar_m = 0.0, s_l_m = 0.0;
  double rp_l_m = 0.0;
  Eigen::Vector3d ap_rad = Eigen::Vector3d::Zero();  // AP_a, AP_b, AP_c
  Eigen::Vector3d s_rad = Eigen::Vector3d::Zero();   // S_a, S_b, S_c
  Eigen::Vector3d rp_rad = Eigen::Vector3d::Zero();  // RP_a, RP_b, RP_c (+-)
};

// The figures of `attained` (n >= 2 cycles) against `commanded`. False
// with *error for fewer than 2 cycles or a rotation that is not one
// (|R^T R - I| > 1e-6 or det < 0).
bool Iso9283Pose(const Iso9283Sample& commanded,
                 const std::vector<Iso9283Sample>& attained,
                 Iso9283PoseResult* result, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_ESTIMATION_ISO9283_H_
