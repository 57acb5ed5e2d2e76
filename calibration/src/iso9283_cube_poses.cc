// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/iso9283_cube_poses.h"

#include <string>

#include "activecal/calibration/cell_planning.h"

namespace activecal {

bool MakeIso9283CubePoses(const RobotModel& model,
                          const Iso9283CubePosesOptions& options,
                          Iso9283CubePoses* poses) {
  *poses = Iso9283CubePoses();
  Iso9283CubeOptions cube;
  if (!ParseIso9283Cube(options.cube, options.orientation, &cube,
                        &poses->message)) {
    return false;
  }
  if (options.checker != nullptr) {
    cube.check = CellCompensationCheck(*options.checker);
  }
  const bool ok =
      DesignIso9283Cube(model, model.nominal, cube, &poses->summary);
  poses->table = poses->summary.TableText();
  if (!ok) {
    poses->message = "--iso9283_cube: " + poses->summary.message;
    return false;
  }
  poses->poses_csv = Iso9283CubePosesCsvText(model, poses->summary);
  poses->targets_csv = Iso9283CubeTargetsCsvText(model, poses->summary);
  poses->ok = true;
  return true;
}

}  // namespace activecal
