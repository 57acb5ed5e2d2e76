// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// What a calibration program prints and writes after Calibrate, in one
// call: the printout (calibration/calibration_notes.h), the model
// selection's curve drawn with gnuplot, and the output files with the HTML
// report (MakeCalibrationOutputsAndReport), in the order a program prints
// them and with the first failure. activecal_identify is this call between
// its options and its writes:
//
//   CalibrationRunOptions run_options;
//   run_options.outputs.model_out = "calibrated.yaml";
//   CalibrationRunOutputs run;
//   MakeCalibrationRunOutputs(model, measurements, summary, run_options,
//                             &run);
//   std::cout << run.printed;  // also on failure
//   if (!run.failure.empty()) ...fail with it, writing nothing...
//   ...write run.files as one set (io/output_files.h), then print
//   run.notes_after and CalibrationResultLine(summary)...

#ifndef ACTIVECAL_REPORT_CALIBRATION_RUN_H_
#define ACTIVECAL_REPORT_CALIBRATION_RUN_H_

#include <optional>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_outputs.h"
#include "activecal/core/measurement.h"
#include "activecal/core/robot_model.h"
#include "activecal/io/column_map.h"
#include "activecal/io/output_files.h"

namespace activecal {

struct CalibrationRunOptions {
  // The files and the texts' options (outputs.text: the option spelling,
  // the program's name, ...).
  CalibrationOutputOptions outputs;
  // The measurements' column map: with an orientation, its columns and
  // convention (ColumnMapOrientationText) are what the orientation hint
  // names; none: the measurements file's own. Then whether to add the
  // rotation-weight note (MakeCalibrationPrintout).
  std::optional<ColumnMap> column_map;
  bool rotation_weight_note = false;
  // If set: a PNG of the model selection's curve (SelectionCurveRows,
  // SelectionCurveGnuplot), drawn by gnuplot when the selection ran; the
  // option named selection_plot in the texts.
  std::string selection_plot;
};

struct CalibrationRunOutputs {
  // To print before the files are written, also on failure, in order: the
  // stages, the curve's note ("  --selection_plot: wrote <path>", or
  // "...: gnuplot is not installed; no plot"), the report and the outputs'
  // notes_before; each up to where the run failed.
  std::string printed;
  // Not empty: the run failed (gnuplot's error as "--selection_plot:
  // <why>", the calibration's failure, or the outputs' error), and
  // `files` is empty: nothing is to be written.
  std::string failure;
  // The curve's PNG first, then the files of MakeCalibrationOutputsAndReport.
  std::vector<OutputFile> files;
  // To print once the files are written (CalibrationOutputs::notes_after).
  std::string notes_after;
};

// The outputs of `summary`, calibrated from `measurements` on `model`.
void MakeCalibrationRunOutputs(const RobotModel& model,
                               const std::vector<Measurement>& measurements,
                               const CalibrationSummary& summary,
                               const CalibrationRunOptions& options,
                               CalibrationRunOutputs* run);

}  // namespace activecal

#endif  // ACTIVECAL_REPORT_CALIBRATION_RUN_H_
