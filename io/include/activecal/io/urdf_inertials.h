// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The gravity model of a URDF chain (joint_errors.h: GravityModel): the
// mass and centre of mass of every link on the chain that a moving joint
// carries, from the links' <inertial> elements, for the compliance terms.
//
// The centre of mass of a link is its <inertial><origin xyz> in the link's
// frame, carried into the frame of the last moving joint before it (links
// after fixed joints follow the fixed joints' origins). Links before the
// first moving joint (the base) carry no torque and are skipped; links off
// the chain (side branches) are not counted.

#ifndef ACTIVECAL_IO_URDF_INERTIALS_H_
#define ACTIVECAL_IO_URDF_INERTIALS_H_

#include <string>

#include "activecal/core/joint_errors.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {

// Fills gravity->bodies (gravity, payload untouched). False, with one line
// in *error naming the links, when no moving link has a mass ("<source>:
// compliance needs link masses: no <inertial> on links a, b, c").
bool ParseUrdfInertials(const std::string& xml, const std::string& source,
                        const UrdfChainOptions& options, GravityModel* gravity,
                        std::string* error);
bool LoadUrdfInertials(const std::string& path, const UrdfChainOptions& options,
                       GravityModel* gravity, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_URDF_INERTIALS_H_
