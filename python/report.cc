// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: Estimate.write_report, the HTML report of
// activecal_identify --report_html through the same library call
// (report/html_report.h: CalibrationHtmlReport, RenderHtml).

#include "activecal/report/html_report.h"
#include "common.h"

namespace activecal {
namespace python {

void BindReport(py::module_& m) {
  py::object estimate = m.attr("Estimate");
  estimate.attr("write_report") = py::cpp_function(
      [](const EstimateResult& e, const py::object& path,
         const std::string& measurements) {
        CalibrationHtmlOptions options;
        options.robot_file =
            e.robot->path.empty() ? "built-in PUMA 560" : e.robot->path;
        options.measurements_file = measurements;
        options.program = "activecal (Python)";
        HtmlReport report;
        std::string error;
        if (!CalibrationHtmlReport(e.calibration, options, &report, &error)) {
          throw py::value_error("write_report: " + error);
        }
        WriteText(PathArg(path), RenderHtml(report));
      },
      py::name("write_report"), py::is_method(estimate), py::arg("path"),
      py::arg("measurements") = "given to identify",
      "Writes the calibration report as activecal_identify --report_html: "
      "one self-contained HTML file (set-up, errors before and after in mm "
      "and deg, log-bin histograms, posture groups, parameters in mm / mrad "
      "with std and correlations, model selection, warnings). "
      "`measurements` names the data in the set-up.");
}

}  // namespace python
}  // namespace activecal
