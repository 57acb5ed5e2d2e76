// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The PUMA 560 of Sun & Hollerbach, "Active Robot Calibration Algorithm",
// Section V, with the 27 free parameters in the paper's order:
//
//   B  (Hayati, no joint): gamma alpha a beta
//   L1 (standard DH):      gamma alpha a d
//   L2 (Hayati):           gamma alpha a beta
//   L3, L4, L5 (DH):       gamma alpha a d
//   L6 (DH, alpha = 0):    gamma a d
//
// Gains are held at 1, the tool point at the origin of frame 6. Nominal
// values are Table II, true values Table I; joint ranges are eq. (25).

#ifndef ACTIVECAL_CORE_PUMA560_H_
#define ACTIVECAL_CORE_PUMA560_H_

#include <Eigen/Core>

#include "activecal/core/robot_model.h"

namespace activecal {

// The model, with the nominal (Table II) values.
RobotModel Puma560PaperModel();
// The true values (Table I), a full parameter vector for Puma560PaperModel().
Eigen::VectorXd Puma560TrueParameters();

}  // namespace activecal

#endif  // ACTIVECAL_CORE_PUMA560_H_
