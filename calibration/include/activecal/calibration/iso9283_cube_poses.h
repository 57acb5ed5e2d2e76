// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The ISO 9283 (6.8) cube's five test poses as activecal_select
// --iso9283_cube makes them: the cube and orientation parsed, the poses
// solved (checked against the cell if one is given) and the texts of the
// poses CSV and the targets CSV.
//
//   Iso9283CubePosesOptions options;
//   options.cube = "0.5,0,0.4,0.2";
//   Iso9283CubePoses poses;
//   if (!MakeIso9283CubePoses(model, options, &poses)) ... poses.message
#ifndef ACTIVECAL_CALIBRATION_ISO9283_CUBE_POSES_H_
#define ACTIVECAL_CALIBRATION_ISO9283_CUBE_POSES_H_

#include <string>

#include "activecal/calibration/iso9283_cube.h"
#include "activecal/cell/cell_checker.h"
#include "activecal/core/robot_model.h"

namespace activecal {

struct Iso9283CubePosesOptions {
  std::string cube;         // ParseIso9283Cube's cube
  std::string orientation;  // and its orientation (empty: the default)
  // If set, every pose is checked against it (CellCompensationCheck).
  const CellChecker* checker = nullptr;
};

struct Iso9283CubePoses {
  bool ok = false;
  std::string message;  // why not, when !ok: one line
  // The table of the five poses (Iso9283CubeSummary::TableText), also
  // when a pose is not solved; empty when the options do not parse.
  std::string table;
  std::string poses_csv;    // Iso9283CubePosesCsvText, when ok
  std::string targets_csv;  // Iso9283CubeTargetsCsvText, when ok
  Iso9283CubeSummary summary;
};

// False with the message ("--iso9283_cube: " and why for a pose not
// solved) when the cube or orientation does not parse or a pose fails.
bool MakeIso9283CubePoses(const RobotModel& model,
                          const Iso9283CubePosesOptions& options,
                          Iso9283CubePoses* poses);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_ISO9283_CUBE_POSES_H_
