// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Programs for a robot controller that move through a design's poses and
// wait at each for the measurement, for cells without a driver
// (docs/driver_protocol.md): URScript (Universal Robots: movej), KUKA KRL
// (PTP to an AXIS / E6AXIS) and ABB RAPID (MoveAbsJ to a jointtarget).
//
// The joint values are written in the controller's convention: a URDF's
// (or robot file's) joint zero and sign need not be the controller's. A
// small YAML file states them (data/controllers/ holds one per shipped
// robot that differs):
//
//   # controllers/kuka_iiwa14.yaml
//   controller: KUKA LBR iiwa 14 R820
//   joints:                      # one per joint of the robot, chain order
//     - {name: A1, sign: 1, offset_deg: 0, joint: joint_a1}
//     - {name: A2, sign: -1, offset_deg: 0, joint: joint_a2}
//     ...
//
// controller value = sign * q + offset, q activecal's joint value; sign is
// +1 or -1; the offset is given as offset_deg or offset_rad (revolute) or
// offset_mm or offset_m (prismatic), default 0; `joint` (optional) is the
// robot's joint name, checked, so that a file cannot be applied to the
// wrong robot or order. Units in the programs: URScript radians (metres),
// KRL and RAPID degrees (millimetres). KRL and RAPID take six robot axes;
// joints 7 to 12 go to the external axes (E1..E6, eax_a..eax_f), as a
// seventh axis on those controllers is.

#ifndef ACTIVECAL_IO_CONTROLLER_PROGRAMS_H_
#define ACTIVECAL_IO_CONTROLLER_PROGRAMS_H_

#include <string>
#include <vector>

#include "activecal/core/robot_model.h"
#include "activecal/io/csv_files.h"

namespace activecal {

enum class ProgramLanguage { kUrScript, kKrl, kRapid };
// "urscript", "krl", "rapid".
const char* ProgramLanguageToString(ProgramLanguage language);
bool StringToProgramLanguage(const std::string& text,
                             ProgramLanguage* language);

struct ControllerJoint {
  std::string name;     // the controller's name (A1, J1, rax_1 ...)
  double sign = 1.0;    // +1 or -1
  double offset = 0.0;  // rad (revolute) or m (prismatic)
};

struct ControllerConvention {
  std::string controller;               // what the file says it is for
  std::vector<ControllerJoint> joints;  // one per robot joint
};

// The controller counts as activecal does (sign +1, offset 0), names
// J1..Jn.
ControllerConvention IdentityConvention(const RobotModel& model);

// Reads the YAML above for `model`. On failure returns false with
// "<source>:<line>:<column>: <field>: <what>".
bool ParseControllerConvention(const std::string& text,
                               const std::string& source,
                               const RobotModel& model,
                               ControllerConvention* convention,
                               std::string* error);
bool ReadControllerConvention(const std::string& path, const RobotModel& model,
                              ControllerConvention* convention,
                              std::string* error);

// Joint j (0-based) at activecal's value q in the controller's convention
// and in the program's unit (rad / m for URScript, deg / mm otherwise).
double ControllerJointValue(const RobotModel& model,
                            const ControllerConvention& convention,
                            ProgramLanguage language, int j, double q);

struct ControllerProgramOptions {
  ProgramLanguage language = ProgramLanguage::kUrScript;
  // The program's (and for KRL the file's) name: a letter, then letters,
  // digits and '_', at most 24 characters (KRL's limit).
  std::string name = "activecal_poses";
  // The wait at each pose for the measurement (s), >= 0.
  double wait_s = 2.0;
  // Joint speed and acceleration as a fraction, in [0.01, 1]: of movej's
  // defaults for URScript (a = 1.4 rad/s^2, v = 1.05 rad/s, themselves
  // below a UR's maximum), of every axis's maximum for KRL (BAS(#VEL_PTP),
  // BAS(#ACC_PTP) and, for joints 7 to 12, $VEL_EXTAX, $ACC_EXTAX, in
  // whole percent), of v1000 for RAPID (VelSet).
  double speed_fraction = 0.1;
  std::string comment;  // one line, written as a comment at the top

  bool IsValid(std::string* error) const;
};

// The program: a move to each pose of `poses` in order (its pose_indices in
// a comment), each followed by the wait. Values are written to 1e-9 (rad,
// m) or 1e-6 (deg, mm), a pose at a joint limit at or inside it (rounded
// toward the range). False with *error for bad options, a convention of
// another joint count, or more joints than the language holds.
bool ControllerProgramText(const RobotModel& model,
                           const ControllerConvention& convention,
                           const PoseList& poses,
                           const ControllerProgramOptions& options,
                           std::string* text, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_CONTROLLER_PROGRAMS_H_
