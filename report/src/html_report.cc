// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/report/html_report.h"

#include <glog/logging.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "activecal/calibration/calibration_report.h"
#include "activecal/core/free_set.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/text_table.h"
#include "activecal/report/iso9283_section.h"
#include "activecal/report/svg_figures.h"

namespace activecal {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = 180.0 / kPi;

Eigen::Matrix3d Rotation(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  if (angle == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

// Signed mean of `v`.
double Mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / v.size();
}

// One table row: count, RMS, mean, p95, max of a quantity (scale: SI to
// shown), the mean signed for an axis.
std::string StatisticsRow(const std::string& key, const std::string& what,
                          const std::vector<double>& signed_values,
                          bool is_axis, double scale) {
  std::vector<double> magnitudes;
  for (double x : signed_values) magnitudes.push_back(std::abs(x));
  const ErrorStatistics s = ComputeErrorStatistics(magnitudes);
  const double mean = is_axis ? Mean(signed_values) : s.mean;
  return "<tr><th>" + HtmlEscape(what) + "</th><td class=\"num\">" +
         std::to_string(s.count) + "</td>" +
         HtmlNumberCell(key + ".rms", s.rms, scale * s.rms) +
         HtmlNumberCell(key + ".mean", mean, scale * mean) +
         HtmlNumberCell(key + ".p95", s.p95, scale * s.p95) +
         HtmlNumberCell(key + ".max", s.max, scale * s.max) + "</tr>\n";
}

std::string ErrorsTable(const ReportErrors& e) {
  const EvaluationSummary& s = e.errors;
  std::string html = "<table class=\"errors\" data-key=\"" + HtmlEscape(e.key) +
                     "\"><caption>" + HtmlEscape(e.label) +
                     "</caption>\n<tr><th></th><th>count</th><th>RMS</th>"
                     "<th>mean</th><th>p95</th><th>max</th></tr>\n";
  // rotation_vectors: NaN in x marks a distance (no measured point), NaN
  // in y a measurement without orientation (ComputeReportErrors).
  std::vector<double> norm, axis[3], angle, rot_axis[3], distance;
  int poses = 0;
  for (int i = 0; i < s.num_measurements; ++i) {
    const Eigen::Vector3d& r = e.rotation_vectors[i];
    if (std::isnan(r[0])) {
      distance.push_back(s.distance_errors_m[i]);
      continue;
    }
    const Eigen::Vector3d& p = s.position_errors[i];
    norm.push_back(p.norm());
    for (int a = 0; a < 3; ++a) axis[a].push_back(p[a]);
    if (std::isnan(r[1])) continue;
    ++poses;
    angle.push_back(s.rotation_errors_rad[i]);
    for (int a = 0; a < 3; ++a) rot_axis[a].push_back(r[a]);
  }
  const char* names[3] = {"x", "y", "z"};
  if (!norm.empty()) {
    html += StatisticsRow(e.key + ".position.norm", "position |e| (mm)", norm,
                          false, 1e3);
    for (int a = 0; a < 3; ++a) {
      html += StatisticsRow(e.key + ".position." + names[a],
                            std::string("position ") + names[a] + " (mm)",
                            axis[a], true, 1e3);
    }
  }
  if (poses > 0) {
    html += StatisticsRow(e.key + ".orientation.angle",
                          "orientation angle (deg)", angle, false, kDeg);
    for (int a = 0; a < 3; ++a) {
      html += StatisticsRow(e.key + ".orientation." + names[a],
                            std::string("orientation ") + names[a] + " (deg)",
                            rot_axis[a], true, kDeg);
    }
  }
  if (!distance.empty()) {
    html += StatisticsRow(e.key + ".distance", "distance (mm)", distance, false,
                          1e3);
  }
  return html + "</table>\n";
}

std::vector<double> PositionNormsMm(const ReportErrors& e) {
  std::vector<double> out;
  for (int i = 0; i < e.errors.num_measurements; ++i) {
    if (std::isnan(e.rotation_vectors[i][0])) continue;
    out.push_back(1e3 * e.errors.position_errors[i].norm());
  }
  return out;
}

std::vector<double> AnglesDeg(const ReportErrors& e) {
  std::vector<double> out;
  for (int i = 0; i < e.errors.num_measurements; ++i) {
    if (std::isnan(e.rotation_vectors[i][1])) continue;
    out.push_back(kDeg * e.errors.rotation_errors_rad[i]);
  }
  return out;
}

const char* kColours[] = {"#d95f02", "#1b9e77", "#7570b3", "#e7298a"};

std::string ParameterUnitLabel(const std::string& unit) {
  return unit == "m" ? "mm" : unit == "rad" ? "mrad" : "per mille";
}

const char* kStyle = R"(
body { font-family: sans-serif; margin: 2em; color: #222; max-width: 60em; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; margin-top: 1.5em;
  border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.5em 0 1em 0; }
caption { text-align: left; font-weight: bold; padding: 0.2em 0; }
td, th { border: 1px solid #ccc; padding: 0.15em 0.5em; }
th { text-align: left; font-weight: normal; background: #f4f4f4; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.warning { color: #a00; } svg { display: block; margin: 0.5em 0; }
@media print { body { margin: 0; } h2 { break-after: avoid; }
  svg, table { break-inside: avoid; } }
)";

// The fit's errors: on 6D data position and rotation apart (the RMS
// residual weights the rotations, calibration_report.h), else the residual.
std::string FitErrors(const CalibrationSummary& s) {
  const IdentificationSummary& id = s.identification;
  const PoseErrorRms split =
      id.joint_errors.empty()
          ? PoseErrorRmsOf(s.model, id.parameters, s.training)
          : PoseErrorRms();
  if (split.num_poses > 0) {
    return "; position RMS " + FormatNumber("%.3f", 1e3 * split.position_m) +
           " mm, rotation RMS " +
           FormatNumber("%.3f", 1e3 * split.rotation_rad) +
           " mrad (the RMS residual " + FormatNumber("%.3f", 1e3 * id.rms_m) +
           " mm weights the rotations " +
           FormatNumber("%g",
                        s.options.identification.rotation_weight_m_per_rad) +
           " m/rad), sigma per row " + FormatNumber("%.3f", 1e3 * id.sigma_m) +
           " mm";
  }
  return "; RMS residual " + FormatNumber("%.3f", 1e3 * id.rms_m) +
         " mm, sigma per row " + FormatNumber("%.3f", 1e3 * id.sigma_m) + " mm";
}

}  // namespace

bool ComputeReportErrors(const RobotModel& model,
                         const Eigen::VectorXd& parameters,
                         const std::vector<Measurement>& measurements,
                         const std::string& key, const std::string& label,
                         ReportErrors* out, std::string* error) {
  out->key = key;
  out->label = label;
  out->rotation_vectors.clear();
  if (!EvaluateModel(model, parameters, measurements, &out->errors)) {
    *error = out->errors.message;
    return false;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Measurement& m : measurements) {
    // NaN in x: no measured point (a distance); NaN in y: no orientation.
    Eigen::Vector3d v(0, nan, 0);
    if (m.type == MeasurementType::kDistance) v.setConstant(nan);
    if (m.type == MeasurementType::kPose) {
      const Measurement predicted = PredictMeasurement(model, parameters, m);
      const Eigen::Matrix3d r =
          Rotation(m.rotation).transpose() * Rotation(predicted.rotation);
      const Eigen::AngleAxisd aa(r);
      v = aa.angle() * aa.axis();
    }
    out->rotation_vectors.push_back(v);
  }
  return true;
}

bool CalibrationHtmlReport(const CalibrationSummary& s,
                           const CalibrationHtmlOptions& o, HtmlReport* report,
                           std::string* error) {
  CHECK(s.termination_type == TerminationType::kConvergence);
  HtmlReport& r = *report;
  r = HtmlReport();
  const RobotModel& model = s.model;
  const IdentificationSummary& id = s.identification;
  const CalibrationOptions& options = s.options;
  std::map<std::string, int> types;
  for (const Measurement& m : s.training) types[MeasurementTypeName(m.type)]++;
  for (const Measurement& m : s.validation) {
    types[MeasurementTypeName(m.type)]++;
  }
  std::string device;
  for (const auto& [type, count] : types) {
    device += (device.empty() ? "" : ", ") + std::to_string(count) + " " +
              type + (type == "pose" ? " (6D)" : "");
  }
  r.setup = {
      {"robot", model.name + " (" + std::to_string(model.num_joints()) +
                    " joints), " + o.robot_file},
      {"measurements", o.measurements_file},
      {"device (measurement types)", device},
      {"poses",
       std::to_string(s.training.size()) + " for the fit, " +
           std::to_string(s.validation.size()) + " held out" +
           (s.validation.empty()
                ? ""
                : " (validation fraction " +
                      FormatNumber("%.2f", options.validation_fraction) +
                      ", seed " + std::to_string(options.seed) + ")")},
      {"parameter set",
       std::string(ParameterSetToString(options.parameter_set)) + ": " +
           std::to_string(s.num_free_in_set) + " free in the set, " +
           std::to_string(id.num_free) + " identified"},
      {"model choice",
       std::string(ModelSelectionMethodToString(s.model_selection)) +
           (s.selection.curve.empty()
                ? ""
                : ", rule " +
                      std::string(
                          SelectionRuleToString(options.selection_rule)) +
                      ", " + std::to_string(s.selection.best_num_kept) +
                      " kept")},
      {"base frame", s.registered_base ? s.registration_message
                                       : "as given (not registered)"},
      {"rotation weight (m per rad)",
       FormatNumber("%g", options.identification.rotation_weight_m_per_rad)},
      {"fit", id.message + FitErrors(s)},
      {"program", o.program},
  };
  struct Set {
    const char* key;
    const char* label;
    const std::vector<Measurement>* data;
  };
  std::vector<Set> sets = {{"training", "fitted poses", &s.training}};
  if (!s.validation.empty()) {
    sets.push_back({"held_out", "held-out poses", &s.validation});
  }
  for (const Set& set : sets) {
    if (s.have_baseline) {
      ReportErrors before;
      if (!ComputeReportErrors(
              model, s.baseline.parameters, *set.data,
              std::string("before.") + set.key,
              std::string("before (registration only), ") + set.label, &before,
              error)) {
        return false;
      }
      r.errors.push_back(before);
    }
    ReportErrors after;
    if (!ComputeReportErrors(
            model, id.parameters, *set.data, std::string("after.") + set.key,
            std::string("after (calibrated), ") + set.label, &after, error)) {
      return false;
    }
    r.errors.push_back(after);
  }
  if (!s.validation.empty()) {
    const std::vector<PostureGroup> groups =
        ClassifyPostures(model, s.training, s.validation);
    for (PostureGroup g : {PostureGroup::kRepeated, PostureGroup::kNew,
                           PostureGroup::kOutOfRange}) {
      std::vector<Measurement> subset;
      for (size_t i = 0; i < groups.size(); ++i) {
        if (groups[i] == g) subset.push_back(s.validation[i]);
      }
      if (subset.empty()) continue;
      ReportErrors e;
      const std::string name = PostureGroupName(g);
      if (!ComputeReportErrors(model, id.parameters, subset, "group." + name,
                               "after, held out, " + name + " postures", &e,
                               error)) {
        return false;
      }
      r.groups.push_back(e);
    }
  }
  const std::vector<int> free = model.FreeParameterIndices();
  for (size_t k = 0; k < free.size(); ++k) {
    const int i = free[k];
    r.parameters.push_back({id.names[k], model.ParameterUnit(i),
                            model.nominal[i], id.estimates[k],
                            id.standard_deviations[k]});
  }
  r.correlation = id.correlation;
  std::map<HoldStage, std::vector<std::string>> held;
  for (const HeldParameter& h : s.held) held[h.stage].push_back(h.name);
  for (const auto& [stage, names] : held) {
    const std::string why =
        stage == HoldStage::kParameterSet
            ? "the parameter set's reduction: combinations of the others, "
              "the data cannot separate them"
        : stage == HoldStage::kAutoFix
            ? "auto-fix: not identifiable from these measurements"
            : "model selection: the held-out error did not support them";
    r.held.push_back({why, names});
  }
  r.selection = s.selection;
  r.selection_method = ModelSelectionMethodToString(s.model_selection);
  r.warnings = s.warnings;
  for (int k : id.outliers) {
    r.warnings.push_back(
        "measurement " + std::to_string(s.training_index[k]) +
        " (index in the input) is an outlier: residual " +
        FormatNumber("%.3f", 1e3 * id.residual_norms[k]) +
        " mm, d^2 = " + FormatNumber("%.1f", id.outlier_d2[k]) + " > " +
        FormatNumber("%.1f", id.outlier_threshold[k]));
  }
  return true;
}

std::string RenderHtml(const HtmlReport& r) {
  std::string h =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta "
      "charset=\"utf-8\">\n<title>" +
      HtmlEscape(r.title) + "</title>\n<style>" + kStyle +
      "</style>\n</head>\n<body>\n<h1>" + HtmlEscape(r.title) + "</h1>\n";
  h += "<h2 id=\"setup\">Set-up</h2>\n<table class=\"setup\">\n";
  for (const auto& [what, value] : r.setup) {
    h += "<tr><th>" + HtmlEscape(what) + "</th><td>" + HtmlEscape(value) +
         "</td></tr>\n";
  }
  h += "</table>\n";
  h += "<h2 id=\"warnings\">Warnings</h2>\n";
  if (r.warnings.empty()) {
    h += "<p class=\"no-warnings\">none</p>\n";
  } else {
    h += "<ul class=\"warnings\">\n";
    for (const std::string& w : r.warnings) {
      h += "<li class=\"warning\">" + HtmlEscape(w) + "</li>\n";
    }
    h += "</ul>\n";
  }
  for (const std::string& n : r.notes) {
    h += "<p class=\"note\">" + HtmlEscape(n) + "</p>\n";
  }
  if (!r.iso9283.poses.empty()) h += Iso9283Section(r.iso9283);
  h += "<h2 id=\"errors\">Errors before and after</h2>\n";
  h += "<p>Position errors in mm, orientation errors in degrees: the norm "
       "and each axis (the mean of an axis is signed: a bias).</p>\n";
  for (const ReportErrors& e : r.errors) h += ErrorsTable(e);
  // Histograms: the errors of one data set, before and after, on shared log
  // bins.
  std::map<std::string, std::vector<const ReportErrors*>> by_set;
  std::vector<std::string> order;
  for (const ReportErrors& e : r.errors) {
    const std::string set = e.key.substr(e.key.find('.') + 1);
    if (!by_set.count(set)) order.push_back(set);
    by_set[set].push_back(&e);
  }
  for (const std::string& set : order) {
    std::vector<HistogramSeries> position, angle;
    for (size_t k = 0; k < by_set[set].size(); ++k) {
      const ReportErrors& e = *by_set[set][k];
      const std::string label = e.key.substr(0, e.key.find('.'));
      const std::vector<double> p = PositionNormsMm(e), a = AnglesDeg(e);
      if (!p.empty()) position.push_back({label, p, kColours[k % 4]});
      if (!a.empty()) angle.push_back({label, a, kColours[k % 4]});
    }
    const std::string which = set == "training"   ? "fitted"
                              : set == "held_out" ? "held-out"
                                                  : set;
    if (!position.empty()) {
      h += SvgHistogram(position, 20, "position error |e| (mm)",
                        "Position errors, " + which + " poses");
    }
    if (!angle.empty()) {
      h += SvgHistogram(angle, 20, "orientation error (deg)",
                        "Orientation errors, " + which + " poses");
    }
  }
  if (!r.groups.empty()) {
    h += "<h2 id=\"groups\">Posture groups</h2>\n<p>Held-out poses by where "
         "they lie relative to the fitted ones: repeated (every joint within "
         "0.01 rad of a fitted pose), new (inside the fitted range), out of "
         "range (extrapolation).</p>\n";
    for (const ReportErrors& e : r.groups) h += ErrorsTable(e);
  }
  h += "<h2 id=\"parameters\">Parameters</h2>\n";
  // An evaluation of a given model estimates none: a sentence, not a
  // table of its header alone.
  if (r.parameters.empty()) {
    h += "<p class=\"no-parameters\">No parameters were estimated here: the "
         "model was evaluated as given.</p>\n";
  } else {
    h += "<table class=\"parameters\">\n<tr><th>parameter</th><th>unit</th>"
         "<th>nominal</th><th>estimate</th><th>correction</th><th>std</th>"
         "</tr>\n";
  }
  for (const ReportParameter& p : r.parameters) {
    const double scale = 1e3;
    h += "<tr><th>" + HtmlEscape(p.name) + "</th><td>" +
         ParameterUnitLabel(p.unit) + "</td>" +
         HtmlNumberCell("parameter." + p.name + ".nominal", p.nominal,
                        scale * p.nominal) +
         HtmlNumberCell("parameter." + p.name + ".estimate", p.estimate,
                        scale * p.estimate) +
         HtmlNumberCell("parameter." + p.name + ".correction",
                        p.estimate - p.nominal,
                        scale * (p.estimate - p.nominal)) +
         HtmlNumberCell("parameter." + p.name + ".std", p.std, scale * p.std) +
         "</tr>\n";
  }
  if (!r.parameters.empty()) h += "</table>\n";
  if (r.correlation.rows() > 1 &&
      r.correlation.rows() == static_cast<int>(r.parameters.size())) {
    std::vector<std::string> names;
    for (const ReportParameter& p : r.parameters) names.push_back(p.name);
    h += SvgHeatmap(r.correlation, names,
                    "Correlation of the estimates (red +1, blue -1)");
  }
  if (!r.held.empty()) {
    h += "<h3>Held fixed at their start values</h3>\n<table "
         "class=\"held\">\n";
    for (const auto& [why, names] : r.held) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      h += "<tr><th>" + HtmlEscape(why) + " (" + std::to_string(names.size()) +
           ")</th><td>" + HtmlEscape(list) + "</td></tr>\n";
    }
    h += "</table>\n";
  }
  if (!r.selection.curve.empty()) {
    h += "<h2 id=\"model-selection\">Model selection (" +
         HtmlEscape(r.selection_method) + ")</h2>\n";
    CurveSeries training{"training RMS", {}, {}, {}, kColours[1]};
    CurveSeries held_out{"held-out RMS +- SE", {}, {}, {}, kColours[0]};
    h += "<table class=\"selection\">\n<tr><th>kept</th><th>added</th>"
         "<th>training RMS (mm)</th><th>held-out RMS (mm)</th><th>+- SE "
         "(mm)</th></tr>\n";
    for (const ModelSelectionPoint& pt : r.selection.curve) {
      training.x.push_back(pt.num_kept);
      training.y.push_back(1e3 * pt.training_rms_m);
      held_out.x.push_back(pt.num_kept);
      held_out.y.push_back(pt.ok ? 1e3 * pt.held_out_rms_m
                                 : std::numeric_limits<double>::quiet_NaN());
      held_out.error.push_back(pt.ok ? 1e3 * pt.held_out_se_m : 0.0);
      const std::string key = "selection." + std::to_string(pt.num_kept);
      h += "<tr" +
           std::string(pt.num_kept == r.selection.best_num_kept
                           ? " class=\"kept\""
                           : "") +
           "><td class=\"num\">" + std::to_string(pt.num_kept) +
           (pt.num_kept == r.selection.best_num_kept ? " (kept)" : "") +
           "</td><td>" + HtmlEscape(pt.added) + "</td>" +
           HtmlNumberCell(key + ".training_rms", pt.training_rms_m,
                          1e3 * pt.training_rms_m) +
           (pt.ok ? HtmlNumberCell(key + ".held_out_rms", pt.held_out_rms_m,
                                   1e3 * pt.held_out_rms_m) +
                        HtmlNumberCell(key + ".held_out_se", pt.held_out_se_m,
                                       1e3 * pt.held_out_se_m)
                  : std::string("<td>failed</td><td></td>")) +
           "</tr>\n";
    }
    h += "</table>\n";
    h += SvgCurve({training, held_out}, "parameters kept", "RMS (mm)",
                  r.selection.best_num_kept,
                  "Model selection: RMS against parameters kept");
  }
  h += "</body>\n</html>\n";
  return h;
}

bool MakeCalibrationOutputsAndReport(const CalibrationSummary& summary,
                                     const std::vector<Measurement>& check,
                                     const CalibrationOutputOptions& options,
                                     CalibrationOutputs* outputs,
                                     std::string* error) {
  if (!MakeCalibrationOutputs(summary, check, options, outputs, error)) {
    return false;
  }
  if (options.report_html.empty()) return true;
  CalibrationHtmlOptions html;
  html.robot_file =
      options.robot_file.empty() ? "built-in PUMA 560" : options.robot_file;
  html.measurements_file = options.source;
  html.program = options.program;
  HtmlReport report;
  if (!CalibrationHtmlReport(summary, html, &report, error)) {
    *error =
        (options.text.option_spelling == OptionSpelling::kFlags ? "--" : "") +
        std::string("report_html: ") + *error;
    outputs->files.clear();
    return false;
  }
  outputs->files.push_back({options.report_html, RenderHtml(report)});
  return true;
}

bool EvaluationHtmlText(const RobotDescription& robot,
                        const std::vector<Measurement>& measurements,
                        const EvaluateOptions& options,
                        const EvaluateSummary& summary, std::string* html,
                        std::string* error) {
  const RobotModel& model = robot.model;
  HtmlReport report;
  report.title = "activecal evaluation report";
  report.setup = {
      {"robot", model.name + " (" + std::to_string(model.num_joints()) +
                    " joints), " + options.robot_path},
      {"measurements", options.measurements_path + " (" +
                           std::to_string(measurements.size()) + ")"},
      {"after", robot.learned_correction.empty()
                    ? std::string("--robot as given (no fitting)")
                    : "--robot's geometry as given (no fitting); the "
                      "report's errors are without its learned correction "
                      "(the printed and JSON errors have it)"},
      {"before", summary.have_before ? summary.description : "none"},
      {"program", "activecal_evaluate"}};
  if (!options.training_path.empty()) {
    report.setup.push_back({"training", options.training_path});
  }
  ReportErrors e;
  const auto add = [&](const RobotModel& m, const Eigen::VectorXd& values,
                       const std::vector<Measurement>& data,
                       const std::string& key, const std::string& label,
                       std::vector<ReportErrors>* to) {
    if (!ComputeReportErrors(m, values, data, key, label, &e, error)) {
      *error = "--measurements: " + *error;
      return false;
    }
    to->push_back(e);
    return true;
  };
  if (summary.have_before &&
      !add(summary.nominal, summary.baseline.parameters, measurements,
           "before.evaluated", "before, evaluated poses", &report.errors)) {
    return false;
  }
  if (!add(model, model.nominal, measurements, "after.evaluated",
           "after, evaluated poses", &report.errors)) {
    return false;
  }
  for (PostureGroup g : {PostureGroup::kRepeated, PostureGroup::kNew,
                         PostureGroup::kOutOfRange}) {
    if (summary.groups.empty()) break;
    const std::vector<Measurement> subset =
        PostureGroupSubset(measurements, summary.groups, g);
    if (subset.empty()) continue;
    const std::string name = PostureGroupName(g);
    if (!add(model, model.nominal, subset, "group." + name,
             "after, " + name + " postures", &report.groups)) {
      return false;
    }
  }
  if (options.iso9283) report.iso9283 = summary.iso9283;
  *html = RenderHtml(report);
  return true;
}

}  // namespace activecal
