// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/report/calibration_run.h"

#include "activecal/calibration/calibration_notes.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/report/gnuplot_figure.h"
#include "activecal/report/html_report.h"

namespace activecal {

void MakeCalibrationRunOutputs(const RobotModel& model,
                               const std::vector<Measurement>& measurements,
                               const CalibrationSummary& summary,
                               const CalibrationRunOptions& options,
                               CalibrationRunOutputs* run) {
  *run = CalibrationRunOutputs();
  const CalibrationTextOptions& text = options.outputs.text;
  const std::optional<ColumnMap>& map = options.column_map;
  const CalibrationPrintout printout = MakeCalibrationPrintout(
      model, measurements, summary,
      map && map->has_orientation ? ColumnMapOrientationText(*map) : "",
      options.rotation_weight_note, text);
  run->printed = printout.stages;
  if (!options.selection_plot.empty() && printout.has_selection_curve) {
    const std::string flag =
        (text.option_spelling == OptionSpelling::kFlags ? "--" : "") +
        std::string("selection_plot");
    OutputFile png;
    std::string note, error;
    if (!MakeGnuplotFigure(
            GnuplotDataBlock("curve", SelectionCurveRows(summary)) +
                SelectionCurveGnuplot(summary),
            options.selection_plot, flag, &png, &note, &error)) {
      run->failure = error;
      return;
    }
    if (!png.path.empty()) run->files.push_back(png);
    run->printed += note;
  }
  run->printed += printout.report;
  if (!printout.failure.empty()) {
    run->failure = printout.failure;
    run->files.clear();
    return;
  }
  CalibrationOutputs outputs;
  std::string error;
  const bool made = MakeCalibrationOutputsAndReport(
      summary, measurements, options.outputs, &outputs, &error);
  run->printed += outputs.notes_before;
  if (!made) {
    run->failure = error;
    run->files.clear();
    return;
  }
  run->files.insert(run->files.end(), outputs.files.begin(),
                    outputs.files.end());
  run->notes_after = outputs.notes_after;
}

}  // namespace activecal
