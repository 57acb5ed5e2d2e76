// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/evaluate.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "activecal/core/enum_name_list.h"
#include "activecal/estimation/identification.h"
#include "activecal/io/robot_loader.h"
#include "printf_text.h"
#include "workflow_fail.h"

namespace activecal {
namespace {

using internal::Printf;

bool Fail(const std::string& message, EvaluateSummary* summary) {
  summary->report.clear();
  summary->outputs.clear();
  return internal::Fail(message, summary, TerminationType::kUserFailure);
}

constexpr PostureGroup kGroups[] = {PostureGroup::kRepeated, PostureGroup::kNew,
                                    PostureGroup::kOutOfRange};

nlohmann::json StatisticsJson(const ErrorStatistics& s) {
  return {{"count", s.count},
          {"rms", s.rms},
          {"mean", s.mean},
          {"p95", s.p95},
          {"max", s.max}};
}

nlohmann::json ReportJson(const EvaluationSummary& s) {
  return {
      {"num_position_measurements", s.position.count},
      {"rmse_m", s.position.rms},
      {"rmse_xyz_m", {s.rmse_xyz_m.x(), s.rmse_xyz_m.y(), s.rmse_xyz_m.z()}},
      {"mean_xyz_m", {s.mean_xyz_m.x(), s.mean_xyz_m.y(), s.mean_xyz_m.z()}},
      {"mean_m", s.position.mean},
      {"p95_m", s.position.p95},
      {"max_m", s.position.max},
      {"orientation_rad", StatisticsJson(s.rotation)},
      {"distance_m", StatisticsJson(s.distance)}};
}

// One object per label: the statistics of its rows (StatisticsJson), its
// "label", and what add(k, &object) puts in.
template <typename Add>
nlohmann::json LabelledJson(const std::vector<std::string>& labels,
                            const std::vector<ErrorStatistics>& statistics,
                            const Add& add) {
  nlohmann::json list = nlohmann::json::array();
  for (size_t k = 0; k < labels.size(); ++k) {
    nlohmann::json e = StatisticsJson(statistics[k]);
    e["label"] = labels[k];
    add(k, &e);
    list.push_back(e);
  }
  return list;
}

// The fixed points (type=point rows): each one's refitted coordinates and
// the spread of its rows about them.
nlohmann::json PointsJson(const EvaluationSummary& s) {
  return LabelledJson(s.point_labels, s.point_spread,
                      [&](size_t k, nlohmann::json* p) {
                        const Eigen::Vector3d& c = s.point_coordinates[k];
                        (*p)["coordinates_m"] = {c.x(), c.y(), c.z()};
                      });
}

// The planes (type=plane rows): each one refitted (unit normal, offset:
// n . x = d) and its flatness, the statistics of its rows' |distance|.
nlohmann::json PlanesJson(const EvaluationSummary& s) {
  return LabelledJson(s.plane_labels, s.plane_flatness,
                      [&](size_t k, nlohmann::json* e) {
                        const Eigen::Vector4d& p = s.plane_parameters[k];
                        (*e)["normal"] = {p[0], p[1], p[2]};
                        (*e)["offset_m"] = p[3];
                      });
}

// The one-line result: the key figures of "after" with units, each the
// JSON's value (rmse_m, max_m, orientation_rad.rms, distance_m.rms) scaled
// to mm or deg.
std::string ResultLine(const std::string& program, const EvaluationSummary& s) {
  const double deg = 180.0 / M_PI;
  std::string line =
      program + ": " + std::to_string(s.num_measurements) + " measurements";
  if (s.position.count > 0) {
    line += Printf(", position RMS %.4f mm, max %.4f mm", s.position.rms * 1e3,
                   s.position.max * 1e3);
  }
  if (s.rotation.count > 0) {
    line += Printf(", orientation RMS %.5f deg", s.rotation.rms * deg);
  }
  if (s.distance.count > 0) {
    line += Printf(", distance RMS %.4f mm", s.distance.rms * 1e3);
  }
  return line;
}

std::string Line(const char* label, const EvaluationSummary& s) {
  const double deg = 180.0 / M_PI;
  std::string text = Printf("  %-28s", label);
  if (s.position.count > 0) {
    text += Printf(
        " position (%d): RMSE %.3f mm (x %.3f, y %.3f, z %.3f), mean %.3f, "
        "p95 %.3f, max %.3f mm",
        s.position.count, s.position.rms * 1e3, s.rmse_xyz_m.x() * 1e3,
        s.rmse_xyz_m.y() * 1e3, s.rmse_xyz_m.z() * 1e3, s.position.mean * 1e3,
        s.position.p95 * 1e3, s.position.max * 1e3);
  }
  if (s.rotation.count > 0) {
    text += Printf("; orientation: RMS %.4f deg, p95 %.4f, max %.4f deg",
                   s.rotation.rms * deg, s.rotation.p95 * deg,
                   s.rotation.max * deg);
  }
  if (s.distance.count > 0) {
    text +=
        Printf("; distance (%d): RMS %.3f mm, max %.3f mm", s.distance.count,
               s.distance.rms * 1e3, s.distance.max * 1e3);
  }
  return text + "\n";
}

// ", with its learned correction (...)" when the robot file has one.
std::string LearnedCorrectionNote(const LearnedCorrection& c) {
  if (c.empty()) return "";
  return Printf(
      ", with its learned correction (%d random Fourier features, "
      "fitted on %d measurements)",
      c.num_features(), c.num_training);
}

// The ISO 9283 figures of the cycles, in the base frame of
// options.iso9283_registration.
bool Iso9283(const RobotModel& model,
             const std::vector<Measurement>& measurements,
             const EvaluateOptions& options,
             const IdentificationOptions& fit_options, EvaluateSummary* s) {
  Eigen::VectorXd parameters = model.nominal;
  if (options.iso9283_registration == Iso9283Registration::kFile) {
    RegistrationFitSummary fit;
    FitRegistration(model, model.nominal, measurements, fit_options, &fit);
    if (fit.termination_type != TerminationType::kConvergence) {
      return Fail("--iso9283_registration=file: " + fit.message, s);
    }
    parameters = fit.parameters;
  }
  Iso9283CyclesSummary& iso = s->iso9283;
  if (!EvaluateIso9283Cycles(model, parameters, measurements, options.lines,
                             options.commanded, &iso)) {
    // "<file>:<line>: <field>: ..." when the message names a line.
    const bool at_line =
        !iso.message.empty() &&
        std::isdigit(static_cast<unsigned char>(iso.message[0]));
    return Fail("--iso9283: " + options.measurements_path +
                    (at_line ? ":" : ": ") + iso.message,
                s);
  }
  return true;
}

// The nominal robot: the same parameters as the robot's.
bool LoadNominal(const RobotModel& model, const EvaluateOptions& options,
                 RobotModel* nominal, std::string* error) {
  RobotLoadOptions load;
  load.chain = options.chain;
  RobotDescription loaded;
  if (!LoadRobot(options.nominal_robot_path, load, &loaded, error)) {
    *error = "--nominal_robot: " + *error;
    return false;
  }
  const std::vector<std::string> theirs = loaded.model.ParameterNames(),
                                 ours = model.ParameterNames();
  if (theirs != ours) {
    // The first parameter that differs, so that equal joint and marker
    // counts do not read as a contradiction.
    size_t k = 0;
    while (k < theirs.size() && k < ours.size() && theirs[k] == ours[k]) ++k;
    auto name = [](const std::vector<std::string>& v, size_t k) {
      return k < v.size() ? v[k] : std::string("none");
    };
    *error = "--nominal_robot: not the same robot as --robot: parameter " +
             std::to_string(k + 1) + " is " + name(theirs, k) + " there and " +
             name(ours, k) + " in --robot (" +
             std::to_string(loaded.model.num_joints()) + " and " +
             std::to_string(model.num_joints()) + " joints, " +
             std::to_string(theirs.size()) + " and " +
             std::to_string(ours.size()) + " parameters)";
    return false;
  }
  *nominal = loaded.model;
  return true;
}

std::string JsonText(const RobotDescription& robot,
                     const std::vector<Measurement>& measurements,
                     const EvaluateOptions& options,
                     const nlohmann::json& groups_json,
                     const EvaluateSummary& s) {
  const EvaluationSummary& summary = s.after;
  nlohmann::json j;
  j["robot"] = robot.model.name;
  j["measurements"] = options.measurements_path;
  j["num_measurements"] = summary.num_measurements;
  j["num_position_measurements"] = summary.position.count;
  j["rmse_m"] = summary.position.rms;
  j["rmse_xyz_m"] = {summary.rmse_xyz_m.x(), summary.rmse_xyz_m.y(),
                     summary.rmse_xyz_m.z()};
  j["mean_xyz_m"] = {summary.mean_xyz_m.x(), summary.mean_xyz_m.y(),
                     summary.mean_xyz_m.z()};
  j["mean_m"] = summary.position.mean;
  j["p95_m"] = summary.position.p95;
  j["max_m"] = summary.position.max;
  j["orientation_rad"] = StatisticsJson(summary.rotation);
  j["distance_m"] = StatisticsJson(summary.distance);
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < summary.num_measurements; ++i) {
    const Measurement& m = measurements[i];
    nlohmann::json row = {{"index", i},
                          {"type", MeasurementTypeName(m.type)},
                          {"marker", m.marker + 1}};
    if (m.type == MeasurementType::kPoint) row["point"] = m.point;
    if (m.type == MeasurementType::kPlane) {
      row["plane"] = m.plane;
      row["probe_radius_m"] = m.probe_radius_m;
      row["plane_distance_m"] = summary.plane_errors_m[i];
      rows.push_back(row);
      continue;
    }
    if (m.type == MeasurementType::kPointDistance) {
      row["points"] = {m.point, m.point2};
    }
    if (m.type == MeasurementType::kDistance ||
        m.type == MeasurementType::kPointDistance) {
      row["distance_error_m"] = summary.distance_errors_m[i];
    } else {
      const Eigen::Vector3d& e = summary.position_errors[i];
      row["error_xyz_m"] = {e.x(), e.y(), e.z()};
      row["error_m"] = e.norm();
    }
    if (m.type == MeasurementType::kPose) {
      row["orientation_error_rad"] = summary.rotation_errors_rad[i];
    }
    rows.push_back(row);
  }
  j["errors"] = rows;
  if (!summary.point_labels.empty()) j["points"] = PointsJson(summary);
  if (!summary.plane_labels.empty()) j["planes"] = PlanesJson(summary);
  const bool have_nominal = !options.nominal_robot_path.empty();
  if (s.have_before) {
    j["before"] = ReportJson(s.before);
    j["before"]["kind"] = BeforeBaselineToString(s.kind);
    j["before"]["description"] = s.description;
    j["before"]["registration_only"] = have_nominal;
    j["before"]["fitted_on"] = s.kind == BeforeBaseline::kTraining
                                   ? options.training_path
                                   : options.measurements_path;
    j["before"]["registration_rms_residual_m"] = s.baseline.rms_m;
    j["before"]["robot"] =
        have_nominal ? options.nominal_robot_path : options.robot_path;
  } else {
    j["before"] = nullptr;
  }
  j["after"] = ReportJson(summary);
  j["after"]["description"] = "--robot as given (no fitting)" +
                              LearnedCorrectionNote(robot.learned_correction);
  j["after"]["learned_correction"] = !robot.learned_correction.empty();
  if (!options.training.empty()) {
    j["training"] = options.training_path;
    j["groups"] = groups_json;
    for (size_t i = 0; i < s.groups.size(); ++i) {
      j["errors"][i]["group"] = PostureGroupName(s.groups[i]);
    }
  }
  if (options.iso9283) {
    j["iso9283"] = s.iso9283.Json();
    j["iso9283"]["registration"] =
        Iso9283RegistrationToString(options.iso9283_registration);
  }
  return j.dump(2) + "\n";
}

bool Run(const RobotDescription& robot,
         const std::vector<Measurement>& measurements,
         const EvaluateOptions& options, EvaluateSummary* s) {
  const RobotModel& model = robot.model;
  // The learned correction of --robot's file (identify
  // --learned_residual), part of "after" when there is one.
  const LearnedCorrection& correction = robot.learned_correction;
  EvaluationSummary& summary = s->after;
  if (!EvaluateCorrectedModel(model, model.nominal, correction, measurements,
                              &summary)) {
    return Fail("--measurements: " + summary.message, s);
  }
  // Before: the registration-only baseline (registration_fit.h).
  const bool have_nominal = !options.nominal_robot_path.empty();
  s->nominal = model;
  std::string error;
  if (have_nominal && !LoadNominal(model, options, &s->nominal, &error)) {
    return Fail(error, s);
  }
  IdentificationOptions fit_options;
  fit_options.rotation_weight_m_per_rad = options.rotation_weight;
  if (!fit_options.IsValid(&error)) {
    return Fail("--rotation_weight: " + error, s);
  }
  if (options.iso9283 && !Iso9283(model, measurements, options, fit_options, s))
    return false;
  const std::vector<Measurement>& training = options.training;
  // What 'before' is (--before).
  BeforeBaseline& kind = s->kind;
  kind = options.before;
  if (kind == BeforeBaseline::kAuto) {
    kind = !training.empty() && have_nominal ? BeforeBaseline::kTraining
                                             : BeforeBaseline::kRefit;
  }
  if (kind == BeforeBaseline::kTraining &&
      (training.empty() || !have_nominal)) {
    return Fail(
        "--before=training needs --training (the measurements the model was "
        "calibrated on) and --nominal_robot (the uncalibrated robot)",
        s);
  }
  if (kind == BeforeBaseline::kTraining) {
    s->description =
        "registration only: --nominal_robot's geometry, base and markers "
        "fitted to --training (" +
        std::to_string(training.size()) +
        " measurements), predicting these measurements without refitting";
  } else if (have_nominal) {
    s->description =
        "registration only, refitted: --nominal_robot's geometry, base and "
        "markers fitted to these measurements themselves";
  } else {
    s->description =
        "--robot's own geometry, base and markers refitted to these "
        "measurements (no --nominal_robot: not a registration-only "
        "baseline)";
  }
  if (kind != BeforeBaseline::kNone) {
    FitRegistration(s->nominal, s->nominal.nominal,
                    kind == BeforeBaseline::kTraining ? training : measurements,
                    fit_options, &s->baseline);
    // Too few measurements for the fit (fewer rows than base and marker
    // parameters): the report goes on without the baseline, saying why.
    s->have_before =
        s->baseline.termination_type == TerminationType::kConvergence;
    if (s->have_before && !EvaluateModel(s->nominal, s->baseline.parameters,
                                         measurements, &s->before)) {
      return Fail("--measurements: " + s->before.message, s);
    }
  }
  std::string& text = s->report;
  text = summary.BriefReport();
  text += "  after: --robot as given (no fitting)" +
          LearnedCorrectionNote(correction) + "\n";
  if (s->have_before) {
    text += "  before: " + s->description + "\n";
    text +=
        Line(kind == BeforeBaseline::kTraining ? "before (fitted on --training)"
             : have_nominal ? "before (refitted to this file)"
                            : "before (--robot refitted)",
             s->before);
    text += Line("after (--robot as given)", summary);
  } else if (kind != BeforeBaseline::kNone) {
    text += "  note: no 'before' (" + s->description +
            "): " + s->baseline.message + "\n";
  }
  if (!training.empty() && !have_nominal &&
      options.before == BeforeBaseline::kAuto) {
    text +=
        "  note: --training without --nominal_robot: 'before' is a refit of "
        "--robot; give --nominal_robot for the registration-only baseline "
        "fitted on --training\n";
  }
  text += summary.PointSpreadText();
  if (options.iso9283) text += s->iso9283.TableText();
  // Posture groups relative to the training poses.
  nlohmann::json groups_json = nlohmann::json::object();
  if (!training.empty()) {
    s->groups = ClassifyPostures(model, training, measurements);
    for (PostureGroup g : kGroups) {
      const std::vector<Measurement> subset =
          PostureGroupSubset(measurements, s->groups, g);
      EvaluationSummary e;
      if (!subset.empty() && !EvaluateCorrectedModel(model, model.nominal,
                                                     correction, subset, &e)) {
        return Fail("--measurements: " + e.message, s);
      }
      const std::string label = std::string("after, ") + PostureGroupName(g);
      if (!subset.empty()) text += Line(label.c_str(), e);
      nlohmann::json gj = ReportJson(e);
      gj["num_measurements"] = static_cast<int>(subset.size());
      groups_json[PostureGroupName(g)] = gj;
    }
  }
  if (!options.json_out.empty()) {
    s->outputs.push_back(
        {options.json_out,
         JsonText(robot, measurements, options, groups_json, *s)});
  }
  s->result_line = ResultLine(options.program, summary);
  s->termination_type = TerminationType::kConvergence;
  return true;
}

}  // namespace

constexpr const char* kBeforeBaselineNames[] = {"auto", "training", "refit",
                                                "none"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(BeforeBaseline, kBeforeBaselineNames)

constexpr const char* kIso9283RegistrationNames[] = {"robot", "file"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(Iso9283Registration, kIso9283RegistrationNames)

std::vector<Measurement> PostureGroupSubset(
    const std::vector<Measurement>& all,
    const std::vector<PostureGroup>& groups, PostureGroup group) {
  std::vector<Measurement> out;
  for (size_t i = 0; i < all.size(); ++i) {
    if (groups[i] == group) out.push_back(all[i]);
  }
  return out;
}

bool BeforeAfterPositionErrorsMm(const std::vector<Measurement>& measurements,
                                 const EvaluateSummary& summary,
                                 std::vector<std::vector<double>>* rows,
                                 std::string* error) {
  rows->clear();
  if (!summary.have_before) {
    *error =
        "no 'before' to compare with" + (summary.kind == BeforeBaseline::kNone
                                             ? std::string(" (--before=none)")
                                             : ": " + summary.baseline.message);
    return false;
  }
  if (summary.after.position.count == 0) {
    *error =
        "the histograms are of position errors, and the measurements have "
        "none (distances only)";
    return false;
  }
  const size_t n = measurements.size();
  if (summary.before.position_errors.size() != n ||
      summary.after.position_errors.size() != n) {
    *error = "the errors before (" +
             std::to_string(summary.before.position_errors.size()) +
             ") and after (" +
             std::to_string(summary.after.position_errors.size()) +
             ") are not one per measurement (" + std::to_string(n) + ")";
    return false;
  }
  for (size_t i = 0; i < n; ++i) {
    // A distance row has no position error (stored as zero): not a 0 mm
    // bar in the histogram.
    if (measurements[i].type == MeasurementType::kDistance) continue;
    rows->push_back({summary.before.position_errors[i].norm() * 1e3,
                     summary.after.position_errors[i].norm() * 1e3});
  }
  return true;
}

std::string PositionErrorHistogramGnuplot(
    const std::vector<std::vector<double>>& rows) {
  double top = 0.0;
  for (const std::vector<double>& row : rows) {
    top = std::max(top, std::max(row[1], row[0]));
  }
  const double width = top > 0 ? top / 30.0 : 1.0;
  return "w = " + internal::Printf("%.17g", width) +
         "\nbin(x) = w * (floor(x / w) + 0.5)\n"
         "set title 'Position errors: registration only (before) and "
         "calibrated (after)'\n"
         "set xlabel 'position error (mm)'\nset ylabel 'measurements'\n"
         "set style fill transparent solid 0.5\nset grid\nset boxwidth w\n"
         "set xrange [0:*]\n"
         "plot $errors using (bin($1)):(1.0) smooth frequency with boxes "
         "title 'before (registration only)', $errors using (bin($2)):(1.0) "
         "smooth frequency with boxes title 'after'\n";
}

std::string NoFramesNote(const RobotModel& model, bool frames_given) {
  if (model.base.convention != LinkConvention::kFrame ||
      !model.nominal.head(6).isZero(0) || frames_given) {
    return "";
  }
  return "note: no --frames: the robot's base frame is the identity, so the "
         "errors below include where the device stands relative to the "
         "robot (give the frames identify wrote with --frames_out)\n";
}

void Evaluate(const RobotDescription& robot,
              const std::vector<Measurement>& measurements,
              const EvaluateOptions& options, EvaluateSummary* summary) {
  *summary = EvaluateSummary();
  Run(robot, measurements, options, summary);
}

}  // namespace activecal
