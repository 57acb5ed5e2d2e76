// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Notes on a calibration's 6D pose data (orientation_check.h) that
// activecal_identify prints and the Python module's identify returns as
// warnings: the hint that the orientations were read in the wrong
// convention, and what the default rotation weight did.
//
//   std::cout << OrientationHintText(summary, measurements, "", text);
//   if (rotation_weight_not_given) {
//     std::cout << RotationWeightNote(model, measurements, summary, text);
//   }

#ifndef ACTIVECAL_CALIBRATION_CALIBRATION_NOTES_H_
#define ACTIVECAL_CALIBRATION_CALIBRATION_NOTES_H_

#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// "<program>: warning: <OrientationHint>\n" when the pose rows of
// `measurements` fit badly (OrientationFitsBadly) at the calibrated
// parameters, or at the registration baseline when the calibration stopped
// before its validation; "" otherwise. `columns` names the orientation
// columns and convention read (ColumnMapOrientationText); empty: the
// measurements file's own (rotation vector, roll/pitch/yaw).
std::string OrientationHintText(const CalibrationSummary& summary,
                                const std::vector<Measurement>& measurements,
                                const std::string& columns,
                                const CalibrationTextOptions& options);

// For 6D data calibrated with the default rotation weight
// (defaults::kRotationWeightMPerRad, the caller knows it was not given):
// "<program>: note: --rotation_weight not given: ..." naming the weight
// used and the parameters kept, the weight the fit's own residuals suggest
// (PoseFitOf: distance mismatch over angle mismatch, rounded to 2
// digits) and the parameters Calibrate keeps with it (a second
// calibration of `model` on `measurements` with summary.options, no
// learned residual): forgetting the weight can change the kept set. Empty
// when the calibration did not finish its fit or the data have fewer than
// 2 poses or no mismatch.
std::string RotationWeightNote(const RobotModel& model,
                               const std::vector<Measurement>& measurements,
                               const CalibrationSummary& summary,
                               const CalibrationTextOptions& options);

// What a program prints after Calibrate, in order, and where it fails.
struct CalibrationPrintout {
  // CalibrationStagesText.
  std::string stages;
  // The model selection ran (passed, not kNone): its curve
  // (SelectionCurveRows) can be drawn here, after `stages`.
  bool has_selection_curve = false;
  // OrientationHintText; once validated CalibrationResultText, with
  // rotation_weight_note the RotationWeightNote and, when done,
  // LearnedResidualText.
  std::string report;
  // Not empty: the calibration failed (CalibrationFailureText), to report
  // after `report`.
  std::string failure;
};

// The printout of `summary`, calibrated from `measurements` on `model`;
// `columns` as OrientationHintText's.
CalibrationPrintout MakeCalibrationPrintout(
    const RobotModel& model, const std::vector<Measurement>& measurements,
    const CalibrationSummary& summary, const std::string& columns,
    bool rotation_weight_note, const CalibrationTextOptions& options);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_CALIBRATION_NOTES_H_
