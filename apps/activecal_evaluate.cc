// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_evaluate: how well a robot model predicts a measurements file,
// with no fitting at all (the model as given, e.g. a calibrated one on
// poses it was not fitted to).

#include <gflags/gflags.h>

#include <cctype>
#include <cmath>
#include <cstdio>

#include "activecal/calibration/iso9283_cycles.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/registration_fit.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "activecal/report/html_report.h"
#include "app_common.h"
#include "gnuplot.h"

DEFINE_string(measurements, "",
              "Measurements CSV (docs/formats.md) to predict. Required.");
DEFINE_string(points, "",
              "Points file (YAML, docs/formats.md) of known distances "
              "between the fixed points of type=point rows: their errors "
              "are reported beside each point's spread.");
DEFINE_string(json_out, "",
              "If set, write the report here: rmse_m, rmse_xyz_m, mean_m, "
              "p95_m, max_m, num_measurements, orientation and distance "
              "errors, and the error of every measurement; 'before' the "
              "same for the registration-only baseline; 'groups' per "
              "posture group with --training.");
DEFINE_string(nominal_robot, "",
              "The uncalibrated robot (same chain flags): the geometry of "
              "the registration-only 'before' report. Empty: --robot's own "
              "geometry (then 'before' is a refit of --robot, not a "
              "registration-only baseline).");
DEFINE_string(training, "",
              "Measurements CSV the model was calibrated on: the report then "
              "gives each posture group (repeated, new, out of range) its "
              "own errors, and with --nominal_robot 'before' is by default "
              "the registration fitted on it (--before).");
DEFINE_string(before, "auto",
              "What 'before' is. training: --nominal_robot's geometry with "
              "the base frame and markers fitted to --training, predicting "
              "--measurements as they are (the registration-only baseline "
              "of a calibration on --training: the fair comparison on new "
              "poses). refit: the geometry of --nominal_robot (default "
              "--robot) with the base frame and markers refitted to "
              "--measurements themselves (what that geometry allows at "
              "best). none: no 'before'. auto (default): training when "
              "--training and --nominal_robot are given, refit otherwise.");
DEFINE_string(plot, "",
              "If set, draw histograms of the position errors before "
              "(registration only) and after here (PNG, gnuplot; skipped "
              "with a note when gnuplot is missing).");
DEFINE_string(report_html, "",
              "Write the evaluation as a report a person reads: one "
              "self-contained HTML file (before and after errors in mm and "
              "deg, histograms on log bins, posture groups).");
DEFINE_bool(iso9283, false,
            "ISO 9283 pose accuracy (AP) and repeatability (RP) of the "
            "measurements as repeated cycles to commanded poses: the file's "
            "'pose' column groups the cycles, commanded_x_m.. (or _mm) and "
            "commanded_qw.. (or commanded_r11..r33) give each commanded pose "
            "in the robot's base frame (docs/iso9283.md). Printed per pose "
            "without the model (as measured) and with it (predicted after "
            "compensation by --robot); 'iso9283' in --json_out and "
            "--report_html.");
DEFINE_string(iso9283_registration, "robot",
              "With --iso9283, where the robot's base frame is in the "
              "device's: robot (--robot's base, e.g. the --frames identify "
              "wrote) or file (--robot's base and markers fitted to these "
              "measurements).");
DEFINE_double(rotation_weight, 1.0,
              "Weight of 6D pose orientation rows (m per rad) in the "
              "registration-only fit of the 'before' report.");

namespace activecal {
namespace {

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

// The fixed points (type=point rows): each one's refitted coordinates and
// the spread of its rows about them.
nlohmann::json PointsJson(const EvaluationSummary& s) {
  nlohmann::json points = nlohmann::json::array();
  for (size_t k = 0; k < s.point_labels.size(); ++k) {
    const Eigen::Vector3d& c = s.point_coordinates[k];
    nlohmann::json p = StatisticsJson(s.point_spread[k]);
    p["label"] = s.point_labels[k];
    p["coordinates_m"] = {c.x(), c.y(), c.z()};
    points.push_back(p);
  }
  return points;
}

// The planes (type=plane rows): each one refitted (unit normal, offset:
// n . x = d) and its flatness, the statistics of its rows' |distance|.
nlohmann::json PlanesJson(const EvaluationSummary& s) {
  nlohmann::json planes = nlohmann::json::array();
  for (size_t k = 0; k < s.plane_labels.size(); ++k) {
    const Eigen::Vector4d& p = s.plane_parameters[k];
    nlohmann::json e = StatisticsJson(s.plane_flatness[k]);
    e["label"] = s.plane_labels[k];
    e["normal"] = {p[0], p[1], p[2]};
    e["offset_m"] = p[3];
    planes.push_back(e);
  }
  return planes;
}

// The measurements of one posture group.
std::vector<Measurement> Subset(const std::vector<Measurement>& all,
                                const std::vector<PostureGroup>& groups,
                                PostureGroup group) {
  std::vector<Measurement> out;
  for (size_t i = 0; i < all.size(); ++i) {
    if (groups[i] == group) out.push_back(all[i]);
  }
  return out;
}

// The one-line result (what --quiet prints): the key figures of "after"
// with units, each the JSON's value (rmse_m, max_m, orientation_rad.rms,
// distance_m.rms) scaled to mm or deg.
std::string EvaluationResultLine(const EvaluationSummary& s) {
  const double deg = 180.0 / M_PI;
  char text[128];
  std::string line = app::ProgramName() + ": " +
                     std::to_string(s.num_measurements) + " measurements";
  if (s.position.count > 0) {
    std::snprintf(text, sizeof(text), ", position RMS %.4f mm, max %.4f mm",
                  s.position.rms * 1e3, s.position.max * 1e3);
    line += text;
  }
  if (s.rotation.count > 0) {
    std::snprintf(text, sizeof(text), ", orientation RMS %.5f deg",
                  s.rotation.rms * deg);
    line += text;
  }
  if (s.distance.count > 0) {
    std::snprintf(text, sizeof(text), ", distance RMS %.4f mm",
                  s.distance.rms * 1e3);
    line += text;
  }
  return line;
}

void PrintLine(const char* label, const EvaluationSummary& s) {
  const double deg = 180.0 / M_PI;
  std::printf("  %-28s", label);
  if (s.position.count > 0) {
    std::printf(
        " position (%d): RMSE %.3f mm (x %.3f, y %.3f, z %.3f), mean %.3f, "
        "p95 %.3f, max %.3f mm",
        s.position.count, s.position.rms * 1e3, s.rmse_xyz_m.x() * 1e3,
        s.rmse_xyz_m.y() * 1e3, s.rmse_xyz_m.z() * 1e3, s.position.mean * 1e3,
        s.position.p95 * 1e3, s.position.max * 1e3);
  }
  if (s.rotation.count > 0) {
    std::printf("; orientation: RMS %.4f deg, p95 %.4f, max %.4f deg",
                s.rotation.rms * deg, s.rotation.p95 * deg,
                s.rotation.max * deg);
  }
  if (s.distance.count > 0) {
    std::printf("; distance (%d): RMS %.3f mm, max %.3f mm", s.distance.count,
                s.distance.rms * 1e3, s.distance.max * 1e3);
  }
  std::printf("\n");
}

void PlotHistograms(const std::vector<Measurement>& measurements,
                    const EvaluationSummary& before,
                    const EvaluationSummary& after) {
  if (after.position.count == 0) {
    app::Fail(
        "--plot: the histograms are of position errors, and the "
        "measurements have none (distances only)");
  }
  if (!app::GnuplotAvailable()) {
    std::printf("  --plot: gnuplot is not installed; no plot\n");
    return;
  }
  std::vector<std::vector<double>> rows;
  double top = 0.0;
  for (size_t i = 0; i < after.position_errors.size(); ++i) {
    // A distance row has no position error (stored as zero): not a 0 mm
    // bar in the histogram.
    if (measurements[i].type == MeasurementType::kDistance) continue;
    const double b = before.position_errors[i].norm() * 1e3;
    const double a = after.position_errors[i].norm() * 1e3;
    rows.push_back({b, a});
    top = std::max(top, std::max(a, b));
  }
  const double width = top > 0 ? top / 30.0 : 1.0;
  char bin[64];
  std::snprintf(bin, sizeof(bin), "%.17g", width);
  const std::string script =
      app::GnuplotData("errors", rows) + "w = " + bin +
      "\nbin(x) = w * (floor(x / w) + 0.5)\n"
      "set title 'Position errors: registration only (before) and "
      "calibrated (after)'\n"
      "set xlabel 'position error (mm)'\nset ylabel 'measurements'\n"
      "set style fill transparent solid 0.5\nset grid\nset boxwidth w\n"
      "set xrange [0:*]\n"
      "plot $errors using (bin($1)):(1.0) smooth frequency with boxes "
      "title 'before (registration only)', $errors using (bin($2)):(1.0) "
      "smooth frequency with boxes title 'after'\n";
  std::string error;
  if (!app::RunGnuplot(script, FLAGS_plot, &error)) {
    app::Fail("--plot: " + error);
  }
  std::printf("  --plot: wrote %s\n", FLAGS_plot.c_str());
}

// The ISO 9283 figures of the cycles (--iso9283), in the base frame of
// --iso9283_registration.
Iso9283CyclesSummary Iso9283OrDie(const RobotModel& model,
                                  const std::vector<Measurement>& measurements,
                                  const std::vector<int>& lines,
                                  const IdentificationOptions& fit_options) {
  const std::vector<CommandedPose> commanded =
      app::ReadCommandedPosesOrDie(FLAGS_measurements, model);
  Eigen::VectorXd parameters = model.nominal;
  if (FLAGS_iso9283_registration == "file") {
    RegistrationFitSummary fit;
    FitRegistration(model, model.nominal, measurements, fit_options, &fit);
    if (fit.termination_type != TerminationType::kConvergence) {
      app::Fail("--iso9283_registration=file: " + fit.message);
    }
    parameters = fit.parameters;
  } else if (FLAGS_iso9283_registration != "robot") {
    app::Fail("--iso9283_registration must be robot or file, got '" +
              FLAGS_iso9283_registration + "'");
  }
  Iso9283CyclesSummary iso;
  if (!EvaluateIso9283Cycles(model, parameters, measurements, lines, commanded,
                             &iso)) {
    // "<file>:<line>: <field>: ..." when the message names a line.
    const bool at_line =
        !iso.message.empty() &&
        std::isdigit(static_cast<unsigned char>(iso.message[0]));
    app::Fail("--iso9283: " + FLAGS_measurements + (at_line ? ":" : ": ") +
              iso.message);
  }
  return iso;
}

// ", with its learned correction (...)" when the robot file has one.
std::string LearnedCorrectionNote(const LearnedCorrection& c) {
  if (c.empty()) return "";
  char text[256];
  std::snprintf(text, sizeof(text),
                ", with its learned correction (%d random Fourier features, "
                "fitted on %d measurements)",
                c.num_features(), c.num_training);
  return text;
}

int Main() {
  if (FLAGS_measurements.empty()) app::Fail("--measurements is required");
  const RobotDescription robot = app::LoadRobotOrDie();
  const RobotModel& model = robot.model;
  // Said first, before any number: without --frames a URDF robot's base
  // is the identity, and every error below includes where the device
  // stands (hundreds of mm).
  if (model.base.convention == LinkConvention::kFrame &&
      model.nominal.head(6).isZero(0) && FLAGS_frames.empty()) {
    std::printf(
        "note: no --frames: the robot's base frame is the identity, so the "
        "errors below include where the device stands relative to the "
        "robot (give the frames identify wrote with --frames_out)\n");
  }
  std::vector<int> lines;
  const std::vector<Measurement> measurements = app::WithPointsFileOrDie(
      FLAGS_points, app::ReadMeasurementsOrDie(FLAGS_measurements, model,
                                               "measurements", &lines));
  // The learned correction of --robot's file (identify
  // --learned_residual), part of "after" when there is one.
  const LearnedCorrection& correction = robot.learned_correction;
  EvaluationSummary summary;
  if (!EvaluateCorrectedModel(model, model.nominal, correction, measurements,
                              &summary)) {
    app::Fail("--measurements: " + summary.message);
  }
  // Before: the registration-only baseline (registration_fit.h).
  RobotDescription nominal = robot;
  if (!FLAGS_nominal_robot.empty()) {
    RobotLoadOptions load;
    load.chain.base_link = FLAGS_base_link;
    load.chain.tip_link = FLAGS_tip_link;
    std::string error;
    if (!LoadRobot(FLAGS_nominal_robot, load, &nominal, &error)) {
      app::Fail("--nominal_robot: " + error);
    }
    const std::vector<std::string> theirs = nominal.model.ParameterNames(),
                                   ours = model.ParameterNames();
    if (theirs != ours) {
      // The first parameter that differs, so that equal joint and marker
      // counts do not read as a contradiction.
      size_t k = 0;
      while (k < theirs.size() && k < ours.size() && theirs[k] == ours[k]) ++k;
      auto name = [](const std::vector<std::string>& v, size_t k) {
        return k < v.size() ? v[k] : std::string("none");
      };
      app::Fail("--nominal_robot: not the same robot as --robot: parameter " +
                std::to_string(k + 1) + " is " + name(theirs, k) +
                " there and " + name(ours, k) + " in --robot (" +
                std::to_string(nominal.model.num_joints()) + " and " +
                std::to_string(model.num_joints()) + " joints, " +
                std::to_string(theirs.size()) + " and " +
                std::to_string(ours.size()) + " parameters)");
    }
  }
  IdentificationOptions fit_options;
  fit_options.rotation_weight_m_per_rad = FLAGS_rotation_weight;
  {
    std::string why;
    if (!fit_options.IsValid(&why)) app::Fail("--rotation_weight: " + why);
  }
  Iso9283CyclesSummary iso;
  if (FLAGS_iso9283)
    iso = Iso9283OrDie(model, measurements, lines, fit_options);
  std::vector<Measurement> training;
  if (!FLAGS_training.empty()) {
    training = app::ReadMeasurementsOrDie(FLAGS_training, model, "training");
  }
  // What 'before' is (--before).
  const bool have_nominal = !FLAGS_nominal_robot.empty();
  std::string before_kind = FLAGS_before;
  if (before_kind == "auto") {
    before_kind = !training.empty() && have_nominal ? "training" : "refit";
  }
  if (before_kind != "training" && before_kind != "refit" &&
      before_kind != "none") {
    app::Fail("--before must be auto, training, refit or none, got '" +
              FLAGS_before + "'");
  }
  if (before_kind == "training" && (training.empty() || !have_nominal)) {
    app::Fail(
        "--before=training needs --training (the measurements the model was "
        "calibrated on) and --nominal_robot (the uncalibrated robot)");
  }
  std::string before_text;
  if (before_kind == "training") {
    before_text =
        "registration only: --nominal_robot's geometry, base and markers "
        "fitted to --training (" +
        std::to_string(training.size()) +
        " measurements), predicting these measurements without refitting";
  } else if (have_nominal) {
    before_text =
        "registration only, refitted: --nominal_robot's geometry, base and "
        "markers fitted to these measurements themselves";
  } else {
    before_text =
        "--robot's own geometry, base and markers refitted to these "
        "measurements (no --nominal_robot: not a registration-only "
        "baseline)";
  }
  RegistrationFitSummary baseline;
  bool have_before = false;
  EvaluationSummary before;
  if (before_kind != "none") {
    FitRegistration(nominal.model, nominal.model.nominal,
                    before_kind == "training" ? training : measurements,
                    fit_options, &baseline);
    // Too few measurements for the fit (fewer rows than base and marker
    // parameters): the report goes on without the baseline, saying why.
    have_before = baseline.termination_type == TerminationType::kConvergence;
    if (have_before && !EvaluateModel(nominal.model, baseline.parameters,
                                      measurements, &before)) {
      app::Fail("--measurements: " + before.message);
    }
  }
  std::printf("%s", summary.BriefReport().c_str());
  std::printf("  after: --robot as given (no fitting)%s\n",
              LearnedCorrectionNote(correction).c_str());
  if (have_before) {
    std::printf("  before: %s\n", before_text.c_str());
    PrintLine(before_kind == "training" ? "before (fitted on --training)"
              : have_nominal            ? "before (refitted to this file)"
                                        : "before (--robot refitted)",
              before);
    PrintLine("after (--robot as given)", summary);
  } else if (before_kind != "none") {
    std::printf("  note: no 'before' (%s): %s\n", before_text.c_str(),
                baseline.message.c_str());
  }
  if (!training.empty() && !have_nominal && FLAGS_before == "auto") {
    std::printf(
        "  note: --training without --nominal_robot: 'before' is a refit of "
        "--robot; give --nominal_robot for the registration-only baseline "
        "fitted on --training\n");
  }
  std::printf("%s", app::PointSpreadText(summary).c_str());
  if (FLAGS_iso9283) std::printf("%s", iso.TableText().c_str());
  // Posture groups relative to the training poses.
  std::vector<PostureGroup> groups;
  nlohmann::json groups_json = nlohmann::json::object();
  if (!training.empty()) {
    groups = ClassifyPostures(model, training, measurements);
    for (PostureGroup g : {PostureGroup::kRepeated, PostureGroup::kNew,
                           PostureGroup::kOutOfRange}) {
      const std::vector<Measurement> subset = Subset(measurements, groups, g);
      EvaluationSummary s;
      if (!subset.empty() && !EvaluateCorrectedModel(model, model.nominal,
                                                     correction, subset, &s)) {
        app::Fail("--measurements: " + s.message);
      }
      const std::string label = std::string("after, ") + PostureGroupName(g);
      if (!subset.empty()) PrintLine(label.c_str(), s);
      nlohmann::json gj = ReportJson(s);
      gj["num_measurements"] = static_cast<int>(subset.size());
      groups_json[PostureGroupName(g)] = gj;
    }
  }
  if (!FLAGS_plot.empty()) {
    if (!have_before) {
      app::Fail("--plot: no 'before' to compare with" +
                (before_kind == "none" ? std::string(" (--before=none)")
                                       : ": " + baseline.message));
    }
    PlotHistograms(measurements, before, summary);
  }
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j;
    j["robot"] = model.name;
    j["measurements"] = FLAGS_measurements;
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
    if (have_before) {
      j["before"] = ReportJson(before);
      j["before"]["kind"] = before_kind;
      j["before"]["description"] = before_text;
      j["before"]["registration_only"] = have_nominal;
      j["before"]["fitted_on"] =
          before_kind == "training" ? FLAGS_training : FLAGS_measurements;
      j["before"]["registration_rms_residual_m"] = baseline.rms_m;
      j["before"]["robot"] =
          FLAGS_nominal_robot.empty() ? FLAGS_robot : FLAGS_nominal_robot;
    } else {
      j["before"] = nullptr;
    }
    j["after"] = ReportJson(summary);
    j["after"]["description"] =
        "--robot as given (no fitting)" + LearnedCorrectionNote(correction);
    j["after"]["learned_correction"] = !correction.empty();
    if (!training.empty()) {
      j["training"] = FLAGS_training;
      j["groups"] = groups_json;
      for (size_t i = 0; i < groups.size(); ++i) {
        j["errors"][i]["group"] = PostureGroupName(groups[i]);
      }
    }
    if (FLAGS_iso9283) {
      j["iso9283"] = iso.Json();
      j["iso9283"]["registration"] = FLAGS_iso9283_registration;
    }
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
  if (!FLAGS_report_html.empty()) {
    HtmlReport report;
    report.title = "activecal evaluation report";
    report.setup = {
        {"robot", model.name + " (" + std::to_string(model.num_joints()) +
                      " joints), " + FLAGS_robot},
        {"measurements",
         FLAGS_measurements + " (" + std::to_string(measurements.size()) + ")"},
        {"after", correction.empty()
                      ? std::string("--robot as given (no fitting)")
                      : "--robot's geometry as given (no fitting); the "
                        "report's errors are without its learned correction "
                        "(the printed and JSON errors have it)"},
        {"before", have_before ? before_text : "none"},
        {"program", "activecal_evaluate"}};
    if (!training.empty()) report.setup.push_back({"training", FLAGS_training});
    std::string error;
    ReportErrors e;
    if (have_before) {
      if (!ComputeReportErrors(nominal.model, baseline.parameters, measurements,
                               "before.evaluated", "before, evaluated poses",
                               &e, &error)) {
        app::Fail("--measurements: " + error);
      }
      report.errors.push_back(e);
    }
    if (!ComputeReportErrors(model, model.nominal, measurements,
                             "after.evaluated", "after, evaluated poses", &e,
                             &error)) {
      app::Fail("--measurements: " + error);
    }
    report.errors.push_back(e);
    for (PostureGroup g : {PostureGroup::kRepeated, PostureGroup::kNew,
                           PostureGroup::kOutOfRange}) {
      if (groups.empty()) break;
      const std::vector<Measurement> subset = Subset(measurements, groups, g);
      if (subset.empty()) continue;
      const std::string name = PostureGroupName(g);
      if (!ComputeReportErrors(model, model.nominal, subset, "group." + name,
                               "after, " + name + " postures", &e, &error)) {
        app::Fail("--measurements: " + error);
      }
      report.groups.push_back(e);
    }
    if (FLAGS_iso9283) report.iso9283 = iso;
    app::WriteTextOrDie(FLAGS_report_html, RenderHtml(report));
  }
  app::PrintResult(EvaluationResultLine(summary));
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Predicts every measurement of a measurements CSV with --robot as "
      "given (no fitting) and reports the errors: position RMSE (norm and "
      "per axis), mean, 95th percentile and max; orientation and distance "
      "errors separately.\n  activecal_evaluate --robot=calibrated.yaml "
      "--measurements=validation.csv --json_out=evaluation.json\n  "
      "activecal_evaluate --robot=cal.urdf --tip_link=tool0 "
      "--frames=frames.yaml --measurements=session2.csv");
  return activecal::app::Finish(activecal::Main());
}
