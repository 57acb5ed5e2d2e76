// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/calibration_outputs.h"

#include "activecal/core/text_table.h"
#include "activecal/io/frames_file.h"
#include "activecal/io/robot_file.h"

namespace activecal {

std::vector<std::pair<std::string, std::string>>
CalibrationOutputOptions::Paths() const {
  std::vector<std::pair<std::string, std::string>> paths;
  for (const auto& [path, option] :
       {std::pair<std::string, std::string>{model_out, "model_out"},
        {urdf_out, "urdf_out"},
        {frames_out, "frames_out"},
        {ur_calibration_out, "ur_calibration_out"},
        {json_out, "json_out"},
        {report_html, "report_html"}}) {
    if (!path.empty()) paths.push_back({path, option});
  }
  return paths;
}

bool MakeCalibrationOutputs(const CalibrationSummary& summary,
                            const std::vector<Measurement>& check,
                            const CalibrationOutputOptions& o,
                            CalibrationOutputs* outputs, std::string* error) {
  *outputs = CalibrationOutputs();
  const std::string p =
      o.text.option_spelling == OptionSpelling::kFlags ? "--" : "";
  const Eigen::VectorXd& calibrated = summary.identification.parameters;
  const LearnedResidualSummary& learned = summary.learned;
  const bool learned_kept =
      summary.options.learned_residual.mode != LearnedResidualMode::kOff &&
      learned.kept;
  const std::string calibrated_from =
      "Calibrated by " + o.program + " from " + o.source;
  std::vector<OutputFile> files;
  std::string why;
  auto fail = [&](const std::string& option) {
    *error = p + option + ": " + why;
    return false;
  };
  if (!o.model_out.empty()) {
    RobotFileOptions file;
    file.angle_unit = o.text.angle_unit;
    const std::string note = HeldFixedNote(summary, o.text);
    file.comment = calibrated_from + "\n" +
                   std::to_string(summary.identification.num_measurements) +
                   " measurements, RMS residual " +
                   std::to_string(summary.identification.rms_m) + " m" +
                   (note.empty() ? "" : "\n" + note);
    if (learned_kept) {
      file.learned_correction = &learned.correction;
      file.comment +=
          "\nWith its learned residual (" +
          std::string(LearnedResidualModeToString(
              summary.options.learned_residual.mode)) +
          "): applied by activecal_evaluate and activecal_compensate";
    }
    files.push_back(
        {o.model_out, RobotFileText(summary.model, calibrated, file)});
  }
  if (!o.urdf_out.empty()) {
    CalibratedUrdfOptions urdf_options = o.urdf;
    urdf_options.output_path = o.urdf_out;
    CalibratedUrdf urdf;
    const bool ok = MakeCalibratedUrdf(summary.model, calibrated, check,
                                       urdf_options, &urdf, &why);
    if (!urdf.text.empty()) {
      for (const std::string& w : urdf.warnings) {
        outputs->notes_before += "  " + p + "urdf_out: " + w + "\n";
      }
    }
    if (!ok) return fail("urdf_out");
    files.push_back({o.urdf_out, urdf.text});
    outputs->notes_after += "  " + p + "urdf_out: wrote " + o.urdf_out +
                            "; reloaded, it predicts every measured point "
                            "within " +
                            FormatNumber("%.1e", urdf.worst_m) +
                            " m of the calibrated model\n";
    if (learned_kept) {
      outputs->notes_after +=
          "  " + p + "urdf_out: the URDF holds the geometry only, not the " +
          "learned correction (" + p +
          "model_out has it): alone it predicts held-out poses with RMS " +
          FormatNumber("%.4f", learned.held_out_rms_parametric_m * 1e3) +
          " mm (nested CV), " +
          FormatNumber("%.4f", learned.held_out_rms_hybrid_m * 1e3) +
          " mm with the correction\n";
    }
  }
  if (!o.ur_calibration_out.empty()) {
    UrCalibration ur;
    if (!MakeUrCalibration(summary.model, calibrated, check, calibrated_from,
                           &ur, &why)) {
      return fail("ur_calibration_out");
    }
    files.push_back({o.ur_calibration_out, ur.text});
    outputs->notes_after +=
        "  " + p + "ur_calibration_out: wrote " + o.ur_calibration_out +
        "; rebuilt as ur_description does, tool0 is within " +
        FormatNumber("%.1e", ur.worst_m) + " m and " +
        FormatNumber("%.1e", ur.worst_rad) + " rad of the calibrated model\n";
  }
  if (!o.frames_out.empty()) {
    files.push_back(
        {o.frames_out, FramesFileText(summary.model, calibrated,
                                      "Metrology frames identified "
                                      "by " +
                                          o.program + " from " + o.source)});
  }
  if (!o.json_out.empty()) {
    files.push_back({o.json_out, CalibrationJson(summary, o.json)});
  }
  outputs->files = std::move(files);
  return true;
}

}  // namespace activecal
