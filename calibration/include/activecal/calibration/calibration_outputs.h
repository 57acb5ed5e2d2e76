// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The files a calibration writes (what activecal_identify's --model_out,
// --urdf_out, --ur_calibration_out, --frames_out and --json_out give), all
// made and checked before any is written: a run that fails writes nothing.
// The caller writes them as one set (io/output_files.h).
//
//   CalibrationOutputOptions options;
//   options.model_out = "calibrated.yaml";
//   options.source = "measurements.csv";
//   CalibrationOutputs outputs;
//   const bool ok =
//       MakeCalibrationOutputs(summary, measurements, options, &outputs,
//                              &error);
//   std::cout << outputs.notes_before;  // also when !ok
//   if (!ok) ...error...
//   ...write outputs.files, then print outputs.notes_after...

#ifndef ACTIVECAL_CALIBRATION_CALIBRATION_OUTPUTS_H_
#define ACTIVECAL_CALIBRATION_CALIBRATION_OUTPUTS_H_

#include <string>
#include <utility>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_export.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/core/measurement.h"
#include "activecal/io/output_files.h"

namespace activecal {

struct CalibrationOutputOptions {
  // The paths; empty: not written.
  std::string model_out;           // the calibrated robot file (YAML)
  std::string urdf_out;            // as URDF (MakeCalibratedUrdf)
  std::string ur_calibration_out;  // the UR driver's kinematics
  std::string frames_out;          // the metrology frames
  std::string json_out;            // the JSON report (CalibrationJson)
  // The HTML report (report/html_report.h: MakeCalibrationOutputsAndReport
  // makes it; MakeCalibrationOutputs does not) and the robot file it names.
  std::string report_html;
  std::string robot_file;
  // The files' comments: "Calibrated by <program> from <source>".
  std::string program = "activecal_identify";
  std::string source;  // the measurements file, or "simulated measurements"
  // The option spelling of the messages ("--urdf_out: ...") and the robot
  // file's angle unit (with model_out set, the held-fixed note names it).
  CalibrationTextOptions text;
  // The URDF the robot was loaded from (source_path, empty: not a URDF
  // robot) and its chain; output_path is set from urdf_out.
  CalibratedUrdfOptions urdf;
  CalibrationJsonOptions json;

  // Each path set and its option ("model_out", "urdf_out", "frames_out",
  // "ur_calibration_out", "json_out", "report_html"), to check before the
  // work.
  std::vector<std::pair<std::string, std::string>> Paths() const;
};

struct CalibrationOutputs {
  // In the order model_out, urdf_out, ur_calibration_out, frames_out,
  // json_out.
  std::vector<OutputFile> files;
  // To print before the files are written (also when the call fails): what
  // the URDF cannot hold ("  --urdf_out: <warning>" lines).
  std::string notes_before;
  // To print once they are written: the reload checks of the URDF and the
  // UR kinematics ("  --urdf_out: wrote <path>; reloaded, ...").
  std::string notes_after;
};

// The files of a successful calibration `summary` (stage kDone), the URDF
// and UR kinematics checked against `check` (the measurements). False with
// *error ("--urdf_out: ...", "--ur_calibration_out: ...") and no files.
bool MakeCalibrationOutputs(const CalibrationSummary& summary,
                            const std::vector<Measurement>& check,
                            const CalibrationOutputOptions& options,
                            CalibrationOutputs* outputs, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_CALIBRATION_OUTPUTS_H_
