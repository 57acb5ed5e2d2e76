// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// ISO 9283:1998 7.2 pose accuracy (AP) and repeatability (RP) of a
// measurements file of repeated cycles to commanded poses
// (docs/iso9283.md), with and without the calibrated model:
//
//   Iso9283CyclesSummary summary;
//   EvaluateIso9283Cycles(model, parameters, measurements, lines, commanded,
//                         &summary);
//   std::printf("%s", summary.TableText().c_str());
//
// Input: the measurements of a file (ReadMeasurementsCsv, position or 6D
// pose rows), the file line of each (MeasurementsCsvReport::lines) and the
// commanded pose of each line (ReadCommandedPosesCsv: the `pose` label and
// the commanded point and orientation of the measured target frame, in the
// robot's base frame). The cycles of a pose are the rows of its label.
//
// The base frame: the base block of `parameters` (a full vector of `model`)
// places the robot's base in the device's frame (the registration: the
// --frames identify wrote, or a registration fitted to the file); the
// measured pose y_j, R_j of cycle j becomes x_j = R_B^T (y_j - t_B) and
// R_B^T R_j in the base frame.
//
// Without the model ("without"): the attained poses x_j, R_j as measured,
// against the commanded x_c, R_c (Iso9283Pose).
//
// With the model ("with"): the predicted attained poses of the program
// compensated by the model (`parameters`, the calibrated model), to first
// order. The compensated program runs joints q'_j with model(q'_j) = x_c;
// with the Jacobian J of the real robot and the model alike near q_j,
// real(q'_j) = x_j + J (q'_j - q_j) and x_c = model(q_j) + J (q'_j - q_j),
// so
//   x'_j = x_c + (x_j - model(q_j)),
//   R'_j = (R_j model_R(q_j)^T) R_c          (base frame),
// the commanded pose displaced by the model's own error at the pose: what
// the calibration left. With the true model AP is the measurement noise
// over sqrt(n); RP is that of the cycles (the model does not see the
// scatter the joint readings do not).

#ifndef ACTIVECAL_CALIBRATION_ISO9283_CYCLES_H_
#define ACTIVECAL_CALIBRATION_ISO9283_CYCLES_H_

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/estimation/iso9283.h"
#include "activecal/io/csv_files.h"

namespace activecal {

struct Iso9283PoseReport {
  std::string pose;              // the label
  int first_line = 0;            // the file line of its first cycle
  int marker = 0;                // 0-based: the measured point of its cycles
  bool has_orientation = false;  // 6D pose rows: AP_a,b,c and RP_a,b,c
  Iso9283Sample commanded;       // base frame
  Iso9283PoseResult without;     // attained, as measured
  Iso9283PoseResult with;        // predicted, compensated by the model
};

struct Iso9283CyclesSummary {
  bool ok = false;
  std::string message;  // why not, when !ok
  // One per label, in the order of their first rows.
  std::vector<Iso9283PoseReport> poses;

  // Two aligned tables (without, with the model): pose, cycles, AP_p,
  // AP_x,y,z, RP_l in mm; AP_a,b,c and RP_a,b,c in mrad and the largest
  // of them in deg.
  std::string TableText() const;
  // {"poses": [{pose, first_line, num_cycles, commanded: {position_m,
  // quaternion_wxyz}, without: {...}, with: {...}}]}: SI (m, rad) and
  // mm / mrad / deg beside.
  nlohmann::json Json() const;
};

// False (summary->ok false, one line in message, "<line>: <field>: ..."
// for the caller to put the file before, naming the line and the
// label) for a label with one cycle, a distance row, a row of several
// markers (the wide form), cycles of one label of different markers or
// types, a 6D pose row without a commanded orientation, or sizes that do
// not match.
bool EvaluateIso9283Cycles(const RobotModel& model,
                           const Eigen::VectorXd& parameters,
                           const std::vector<Measurement>& measurements,
                           const std::vector<int>& lines,
                           const std::vector<CommandedPose>& commanded,
                           Iso9283CyclesSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_ISO9283_CYCLES_H_
