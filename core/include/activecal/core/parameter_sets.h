// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Which parameters a calibration identifies, chosen by name rather than by
// editing free flags:
//
//   registration  the base frame (6 for a 'frame' base; a DH base's free
//                 flags as the file has them) and the marker points (x, y,
//                 z of every marker; their angles too with 6D measurements)
//   offsets       registration + every joint offset (URDF 'offset'; DH
//                 'gamma' of a revolute joint, 'd' of a prismatic one)
//   full          offsets + every geometric correction of every link (URDF
//                 x, y, z, rx, ry, rz; DH gamma, alpha, a, d, and beta of a
//                 Hayati link); joint gains stay fixed
//   file          what the robot file marks free (the default for YAML
//                 robots; 'full' is the default for URDF robots)
//
// A set usually holds parameters the data cannot separate (the first
// joint's origin and the base frame); the reduction
// (estimation/parameter_reduction.h) keeps what the data separate and
// names what it held. Sets are free sets (free_set.h): values, the model
// is not changed.

#ifndef ACTIVECAL_CORE_PARAMETER_SETS_H_
#define ACTIVECAL_CORE_PARAMETER_SETS_H_

#include <Eigen/Core>
#include <string>

#include "activecal/core/free_set.h"
#include "activecal/core/robot_model.h"

namespace activecal {

enum class ParameterSet { kRegistration, kOffsets, kFull, kFile };

// "registration", "offsets", "full" or "file".
const char* ParameterSetToString(ParameterSet set);
// False if `text` is none of them.
bool StringToParameterSet(const std::string& text, ParameterSet* set);

// The free set `set` names on `model` (kFile: the model's own flags).
// `with_orientation`: the measurements see the markers' orientation (6D).
FreeSet ParameterSetFreeSet(const RobotModel& model, ParameterSet set,
                            bool with_orientation);

// A generic point near `parameters` for identifiability analysis: every
// free marker parameter moved by a fixed pseudo-random amount (seeded, the
// same on every platform) of 1 mm (points) or 1 mrad (angles) times a
// standard normal draw. A marker guessed at the tip frame's origin sits on
// the last joint's axis and at its origin, where that joint's rotation
// corrections do not move it: at the guess they would look like they have
// no effect, which they do on a real end effector. The robot's own geometry
// is left as it is, so designed symmetries (parallel axes) keep the
// redundancies they really cause.
Eigen::VectorXd GenericPoint(const RobotModel& model,
                             const Eigen::VectorXd& parameters);

// The parameter set an option names: StringToParameterSet(text), or when
// `text` is empty the default, kFull for a URDF robot and kFile otherwise.
// False with *error "parameter_set must be registration, offsets, full or
// file, got '<text>'" (a program prefixes "--").
bool ParseParameterSet(const std::string& text, bool urdf_robot,
                       ParameterSet* set, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_PARAMETER_SETS_H_
