// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/calibration_notes.h"

#include "activecal/calibration/defaults.h"
#include "activecal/core/text_table.h"
#include "activecal/estimation/orientation_check.h"

namespace activecal {

std::string OrientationHintText(const CalibrationSummary& summary,
                                const std::vector<Measurement>& measurements,
                                const std::string& columns,
                                const CalibrationTextOptions& options) {
  const Eigen::VectorXd& parameters =
      summary.Passed(CalibrationStage::kValidation)
          ? summary.identification.parameters
          : summary.baseline.parameters;
  if (parameters.size() != summary.model.num_parameters()) return "";
  const PoseFit fit = PoseFitOf(summary.model, parameters, measurements);
  if (!OrientationFitsBadly(fit)) return "";
  const std::string what =
      !columns.empty()
          ? columns
          : "the file's rx_rad,ry_rad,rz_rad are a rotation vector, "
            "roll/pitch/yaw are R = Rz(yaw) Ry(pitch) Rx(roll); a device's "
            "Euler angles need " +
                std::string(options.option_spelling == OptionSpelling::kFlags
                                ? "--column_map"
                                : "column_map");
  return options.program + ": warning: " + OrientationHint(fit, what) + "\n";
}

std::string RotationWeightNote(const RobotModel& model,
                               const std::vector<Measurement>& measurements,
                               const CalibrationSummary& summary,
                               const CalibrationTextOptions& options) {
  if (!summary.Passed(CalibrationStage::kValidation)) return "";
  const PoseFit fit =
      PoseFitOf(summary.model, summary.identification.parameters, measurements);
  if (fit.num_poses < 2 || !(fit.rotation_rms_rad > 0) ||
      !(fit.position_rms_m > 0)) {
    return "";
  }
  const std::string rounded =
      FormatNumber("%.2g", fit.position_rms_m / fit.rotation_rms_rad);
  CalibrationOptions with = summary.options;
  with.identification.rotation_weight_m_per_rad = std::stod(rounded);
  with.selection_progress = nullptr;
  with.learned_residual = CalibrationOptions::LearnedResidualOff();
  CalibrationSummary other;
  Calibrate(model, measurements, with, &other);
  std::string effect = "the fit with it failed";
  if (other.stage == CalibrationStage::kDone) {
    effect = "keeps " + std::to_string(other.identification.estimates.size()) +
             " parameters";
  }
  const bool flags = options.option_spelling == OptionSpelling::kFlags;
  return options.program + ": note: " + (flags ? "--" : "") +
         "rotation_weight not given: the orientations of the pose rows were "
         "weighted " +
         FormatNumber("%g", defaults::kRotationWeightMPerRad) + " m/rad and " +
         std::to_string(summary.identification.estimates.size()) +
         " parameters kept; their residuals (between " +
         std::to_string(fit.num_poses) + " poses: distances " +
         FormatNumber("%.3f", fit.position_rms_m * 1e3) + " mm, angles " +
         FormatNumber("%.3f", fit.rotation_rms_rad * 1e3) +
         " mrad RMS) have the ratio " + rounded +
         " m/rad, with which the calibration " + effect +
         "; set it to sigma_position / sigma_rotation of the device\n";
}

CalibrationPrintout MakeCalibrationPrintout(
    const RobotModel& model, const std::vector<Measurement>& measurements,
    const CalibrationSummary& summary, const std::string& columns,
    bool rotation_weight_note, const CalibrationTextOptions& options) {
  CalibrationPrintout out;
  out.stages = CalibrationStagesText(summary, options);
  out.has_selection_curve =
      summary.Passed(CalibrationStage::kModelSelection) &&
      summary.model_selection != ModelSelectionMethod::kNone;
  out.report = OrientationHintText(summary, measurements, columns, options);
  if (summary.Passed(CalibrationStage::kValidation)) {
    out.report += CalibrationResultText(summary, options);
    if (rotation_weight_note) {
      out.report += RotationWeightNote(model, measurements, summary, options);
    }
  }
  // The learned residual's failure comes after the fit's report.
  if (summary.stage != CalibrationStage::kDone) {
    out.failure = CalibrationFailureText(summary, options);
  } else {
    out.report += LearnedResidualText(summary);
  }
  return out;
}

}  // namespace activecal
