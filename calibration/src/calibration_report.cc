// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/calibration_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>

#include "activecal/core/text_table.h"
#include "activecal/estimation/evaluation.h"

namespace activecal {
namespace {

// Shorthands of the one number formatter (text_table.h).
std::string N(size_t n) { return std::to_string(n); }
std::string N(int n) { return std::to_string(n); }
std::string Mm(double metres) { return FormatNumber("%.3f", 1e3 * metres); }

// An option as the caller spells it.
std::string Option(const CalibrationTextOptions& o, const std::string& name) {
  return (o.option_spelling == OptionSpelling::kFlags ? "--" : "") + name;
}

// A boolean option set to `value`.
std::string Option(const CalibrationTextOptions& o, const std::string& name,
                   bool value) {
  if (o.option_spelling == OptionSpelling::kKeywords) {
    return name + (value ? "=True" : "=False");
  }
  return "--" + name + (value ? "" : "=false");
}

bool Reduced(const CalibrationSummary& s) {
  return s.options.parameter_set != ParameterSet::kFile;
}

std::string SetLabel(const CalibrationSummary& s,
                     const CalibrationTextOptions& o) {
  return Option(o, "parameter_set=") +
         ParameterSetToString(s.options.parameter_set);
}

// "<program>: <label>: the N measurements cannot identify K of M free
// parameters; holding them at their nominal values: a, b".
std::string FixedNote(const CalibrationSummary& s,
                      const CalibrationTextOptions& o,
                      const std::vector<std::string>& fixed,
                      const std::string& label) {
  if (fixed.empty()) return "";
  std::string list;
  for (const std::string& f : fixed) list += (list.empty() ? "" : ", ") + f;
  return o.program + ": " + label + ": the " +
         std::to_string(s.training.size()) + " measurements cannot identify " +
         std::to_string(fixed.size()) + " of " +
         std::to_string(s.num_free_in_set) +
         " free parameters; holding them at their nominal values: " + list +
         "\n";
}

// A matrix as a JSON array of its rows (element by element: Eigen matrices
// are column-major, so a row is not contiguous in memory).
nlohmann::json MatrixJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < m.rows(); ++r) {
    std::vector<double> row(m.cols());
    for (int c = 0; c < m.cols(); ++c) row[c] = m(r, c);
    rows.push_back(row);
  }
  return rows;
}

bool HasTruth(const CalibrationSummary& s, const Eigen::VectorXd& truth) {
  return truth.size() == s.model.num_parameters();
}

// Inserts `prefix` before every whole-word occurrence of `name` in `text`.
void PrefixWord(const std::string& name, const std::string& prefix,
                std::string* text) {
  auto word = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  };
  for (size_t at = text->find(name); at != std::string::npos;
       at = text->find(name, at + 1)) {
    const size_t end = at + name.size();
    if ((at > 0 && word((*text)[at - 1])) ||
        (end < text->size() && word((*text)[end]))) {
      continue;
    }
    text->insert(at, prefix);
    at += prefix.size();
  }
}

// The model selection's report: its message and the curve (RMS in mm
// beside the count kept), the parameters it held named once (as the rows
// after the kept one when they are those).
std::string SelectionText(const ModelSelectionSummary& selection) {
  std::string text = selection.message + "\n";
  if (selection.curve.empty()) return text;
  TextTable table({{"kept", ColumnAlign::kRight},
                   {"added"},
                   {"training RMS (mm)", ColumnAlign::kRight},
                   {"held-out RMS (mm)", ColumnAlign::kRight},
                   {"+- SE (mm)", ColumnAlign::kRight},
                   {""}});
  std::set<std::string> after_kept;
  for (const ModelSelectionPoint& pt : selection.curve) {
    std::string mark;
    if (pt.num_kept == selection.best_num_kept) mark += "<- kept";
    if (pt.num_kept == selection.minimum_num_kept &&
        selection.best_num_kept != selection.minimum_num_kept) {
      mark += mark.empty() ? "<- minimum" : "  <- minimum";
    }
    if (pt.num_kept > selection.best_num_kept && !pt.added.empty()) {
      after_kept.insert(pt.added);
    }
    table.AddRow({std::to_string(pt.num_kept),
                  pt.added.empty() ? "(registration)" : pt.added,
                  FormatNumber("%.4f", pt.training_rms_m * 1e3),
                  FormatNumber("%.4f", pt.held_out_rms_m * 1e3),
                  FormatNumber("%.4f", pt.held_out_se_m * 1e3), mark});
  }
  text += table.ToString(2);
  const std::vector<std::string>& dropped = selection.dropped;
  if (dropped.empty()) return text;
  if (std::set<std::string>(dropped.begin(), dropped.end()) == after_kept) {
    text += "  the " + N(dropped.size()) +
            " parameters added after '<- kept' are held at their start "
            "values\n";
  } else {
    text += "  held at their start values:";
    for (const std::string& d : dropped) text += " " + d;
    text += "\n";
  }
  return text;
}

}  // namespace

std::string CalibrationStagesText(const CalibrationSummary& s,
                                  const CalibrationTextOptions& o) {
  std::string text;
  if (s.registered_base) text += "  " + s.registration_message + "\n";
  if (Reduced(s)) {
    // Each parameter the reduction held, named once with its reason.
    const std::vector<std::string> held = s.HeldAt(HoldStage::kParameterSet);
    if (s.Passed(CalibrationStage::kParameterSet) && !held.empty()) {
      text += "  " + SetLabel(s, o) + ": the " + N(s.training.size()) +
              " measurements cannot identify " + N(held.size()) + " of " +
              N(s.num_free_in_set) +
              " free parameters; held fixed at their nominal values:\n";
      TextTable table({{"held fixed"}, {"reason"}});
      for (const HeldParameter& h : s.held) {
        if (h.stage == HoldStage::kParameterSet) {
          table.AddRow({h.name, h.reason});
        }
      }
      text += table.ToString(4);
    }
  } else if (s.options.auto_fix &&
             s.Passed(CalibrationStage::kIdentifiability)) {
    text +=
        FixedNote(s, o, s.HeldAt(HoldStage::kAutoFix), Option(o, "auto_fix"));
  }
  if (s.Passed(CalibrationStage::kModelSelection) &&
      s.model_selection != ModelSelectionMethod::kNone) {
    text += SelectionText(s.selection);
  }
  if (s.Passed(CalibrationStage::kTermSelection) &&
      !s.options.term_families.empty()) {
    text += s.term_selection.BriefReport();
  }
  return text;
}

std::string HeldFixedNote(const CalibrationSummary& s,
                          const CalibrationTextOptions& o) {
  if (s.held.empty()) return "";
  std::string label = Reduced(s) ? SetLabel(s, o) : Option(o, "auto_fix");
  const std::vector<std::string> dropped = s.HeldAt(HoldStage::kModelSelection);
  if (!dropped.empty()) {
    const std::string selection =
        Option(o, "model_selection=") +
        ModelSelectionMethodToString(s.model_selection);
    label = s.held.size() > dropped.size() ? label + " and " + selection
                                           : selection;
  }
  std::string note =
      label + ": held fixed at their nominal values (not in 'free'";
  if (o.model_out) note += " of " + Option(o, "model_out");
  note += "):";
  for (const HeldParameter& h : s.held) note += " " + h.name;
  return note;
}

PoseErrorRms PoseErrorRmsOf(const RobotModel& model,
                            const Eigen::VectorXd& parameters,
                            const std::vector<Measurement>& data) {
  PoseErrorRms rms;
  const int poses = static_cast<int>(std::count_if(
      data.begin(), data.end(),
      [](const Measurement& m) { return m.type == MeasurementType::kPose; }));
  if (poses == 0 || parameters.size() != model.num_parameters()) return rms;
  EvaluationSummary e;
  if (!EvaluateModel(model, parameters, data, &e)) return rms;
  rms.num_poses = poses;
  rms.position_m = e.position.rms;
  rms.rotation_rad = e.rotation.rms;
  return rms;
}

namespace {

// PoseErrorRmsOf for a calibration: none (the weighted output stays) when
// joint error terms were kept, which the geometric prediction lacks.
PoseErrorRms SplitOf(const CalibrationSummary& s,
                     const Eigen::VectorXd& parameters,
                     const std::vector<Measurement>& data) {
  if (!s.identification.joint_errors.empty()) return PoseErrorRms();
  return PoseErrorRmsOf(s.model, parameters, data);
}

// "K of M free parameters held fixed ...: a by <stage>, b by <stage>, named
// above": the count of what was held, each group by its stage.
std::string HeldCountNote(const CalibrationSummary& s,
                          const CalibrationTextOptions& o) {
  if (s.held.empty()) return "";
  std::string groups;
  auto group = [&](HoldStage stage, const std::string& by) {
    const size_t n = s.HeldAt(stage).size();
    if (n == 0) return;
    groups += (groups.empty() ? "" : ", ") + std::to_string(n) + " by " + by;
  };
  group(HoldStage::kParameterSet, SetLabel(s, o));
  group(HoldStage::kAutoFix, Option(o, "auto_fix"));
  group(HoldStage::kModelSelection,
        Option(o, "model_selection=") +
            ModelSelectionMethodToString(s.model_selection));
  std::string note =
      N(s.held.size()) + " of " + N(s.num_free_in_set) +
      " free parameters held fixed at their nominal values (not in 'free'";
  if (o.model_out) note += " of " + Option(o, "model_out");
  return note + "): " + groups + ", named above";
}

}  // namespace

namespace {

// The table of a constraint's identified values: `first` (the value's
// name), unit, estimate, std, std again in the unit of the "in" column.
TextTable ConstraintTable(const std::string& first) {
  return TextTable({{first},
                    {"unit"},
                    {"estimate", ColumnAlign::kRight},
                    {"std", ColumnAlign::kRight},
                    {"std", ColumnAlign::kRight},
                    {"in"}});
}

// The fixed points' identified coordinates (type=point rows), a table of
// point.<label>.<axis> rows; empty without fixed points.
std::string FixedPointsText(const IdentificationSummary& id) {
  if (id.point_labels.empty()) return "";
  TextTable table = ConstraintTable("fixed point");
  const bool have_std =
      id.point_standard_deviations.size() == id.point_coordinates.size();
  for (size_t k = 0; k < id.point_labels.size(); ++k) {
    for (int a = 0; a < 3; ++a) {
      const int i = 3 * static_cast<int>(k) + a;
      const double sd = have_std ? id.point_standard_deviations[i] : 0.0;
      table.AddRow({"point." + id.point_labels[k] + "." + "xyz"[a], "m",
                    FormatNumber("%.6f", id.point_coordinates[i]),
                    FormatNumber("%.6f", sd), FormatNumber("%.3f", 1e3 * sd),
                    "mm"});
    }
  }
  return table.ToString();
}

// The planes' identified parameters (type=plane rows): plane.<label>.n
// (the unit normal, its std the two tangent angles' in mrad) and
// plane.<label>.d (the offset, n . x = d); empty without planes.
std::string PlanesText(const IdentificationSummary& id) {
  if (id.plane_labels.empty()) return "";
  TextTable table = ConstraintTable("plane");
  const bool have_std = id.plane_standard_deviations.size() ==
                        3 * static_cast<Eigen::Index>(id.plane_labels.size());
  for (size_t k = 0; k < id.plane_labels.size(); ++k) {
    const Eigen::Vector4d p = id.plane_parameters.segment<4>(4 * k);
    const Eigen::Vector3d sd =
        have_std
            ? Eigen::Vector3d(id.plane_standard_deviations.segment<3>(3 * k))
            : Eigen::Vector3d::Zero();
    table.AddRow(
        {"plane." + id.plane_labels[k] + ".n", "1",
         FormatNumber("%.6f", p[0]) + ", " + FormatNumber("%.6f", p[1]) + ", " +
             FormatNumber("%.6f", p[2]),
         FormatNumber("%.6f", sd[0]) + ", " + FormatNumber("%.6f", sd[1]),
         FormatNumber("%.3f", 1e3 * sd[0]) + ", " +
             FormatNumber("%.3f", 1e3 * sd[1]),
         "mrad"});
    table.AddRow({"plane." + id.plane_labels[k] + ".d", "m",
                  FormatNumber("%.6f", p[3]), FormatNumber("%.6f", sd[2]),
                  FormatNumber("%.3f", 1e3 * sd[2]), "mm"});
  }
  return table.ToString();
}

}  // namespace

std::string CalibrationResultText(const CalibrationSummary& s,
                                  const CalibrationTextOptions& o) {
  const IdentificationSummary& id = s.identification;
  const RobotModel& model = s.model;
  const bool has_truth = HasTruth(s, o.true_parameters);
  const std::vector<int> free = model.FreeParameterIndices();
  // Stated sigmas the residuals contradict: the std the implied noise
  // gives, beside the stated ones (identification.h).
  const bool scaled = !id.chi_square_plausible;
  std::vector<TextColumn> columns = {{"parameter"},
                                     {"unit"},
                                     {"nominal", ColumnAlign::kRight},
                                     {"estimate", ColumnAlign::kRight},
                                     {"std", ColumnAlign::kRight}};
  if (scaled) columns.push_back({"std_scaled", ColumnAlign::kRight});
  if (has_truth) {
    columns.push_back({"true", ColumnAlign::kRight});
    columns.push_back({"error", ColumnAlign::kRight});
    columns.push_back({"err/std", ColumnAlign::kRight});
  }
  // Beside the SI (or the file's) units: the correction and its std in mm
  // or deg, the units a person reads.
  columns.push_back({"change", ColumnAlign::kRight});
  columns.push_back({"std", ColumnAlign::kRight});
  columns.push_back({"in"});
  TextTable table(columns);
  int outside = 0;
  for (size_t k = 0; k < free.size(); ++k) {
    const int i = free[k];
    const double sd = id.standard_deviations[k];
    const std::string unit = model.ParameterUnit(i);
    const bool degrees = unit == "rad" && o.angle_unit == AngleUnit::kDegree;
    const double u = degrees ? 180.0 / M_PI : 1.0;
    std::vector<std::string> row = {id.names[k], degrees ? "deg" : unit,
                                    FormatNumber("%.6f", u * model.nominal[i]),
                                    FormatNumber("%.6f", u * id.estimates[k]),
                                    FormatNumber("%.6f", u * sd)};
    if (scaled) {
      row.push_back(FormatNumber("%.6f", u * id.scaled_standard_deviations[k]));
    }
    if (has_truth) {
      const double truth = o.true_parameters[i];
      const double err = id.estimates[k] - truth;
      if (std::abs(err) > 4 * sd) ++outside;
      row.push_back(FormatNumber("%.6f", u * truth));
      row.push_back(FormatNumber("%.6f", u * err));
      row.push_back(FormatNumber("%.2f", err / sd));
    }
    const double change = id.estimates[k] - model.nominal[i];
    if (unit == "m") {
      row.push_back(FormatNumber("%.3f", 1e3 * change));
      row.push_back(FormatNumber("%.3f", 1e3 * sd));
      row.push_back("mm");
    } else if (unit == "rad") {
      row.push_back(FormatNumber("%.4f", change * 180.0 / M_PI));
      row.push_back(FormatNumber("%.4f", sd * 180.0 / M_PI));
      row.push_back("deg");
    } else {
      row.insert(row.end(), {"", "", ""});
    }
    table.AddRow(row);
  }
  std::string text = table.ToString() + FixedPointsText(id) + PlanesText(id);
  const std::string fit = id.BriefReport();
  text += "\n" + fit;
  if (has_truth) {
    text += "  " + N(outside) + " of " + N(free.size()) +
            " estimates lie more than 4 std from the truth\n";
    if (!s.held.empty()) {
      text +=
          "  (parameters held fixed keep their nominal values, so the kept "
          "ones that explain them also take up their true errors: compare "
          "those with care)\n";
    }
  }
  // On 6D data the residual above mixes metres and weighted radians:
  // position and rotation apart, at the estimate, registration only and
  // held out.
  const PoseErrorRms after = SplitOf(s, id.parameters, s.training);
  if (after.num_poses > 0) {
    text +=
        "  6D poses (" + N(after.num_poses) + "): position RMS " +
        Mm(after.position_m) + " mm, rotation RMS " + Mm(after.rotation_rad) +
        " mrad (" + FormatNumber("%.4f", after.rotation_rad * 180.0 / M_PI) +
        " deg) at the estimate; the RMS residual above weights the "
        "rotations " +
        FormatNumber("%g", s.options.identification.rotation_weight_m_per_rad) +
        " m/rad\n";
  }
  // The baseline, validation and warning lines of the brief report.
  text += s.FitReportTail();
  if (after.num_poses > 0 && s.have_baseline) {
    const PoseErrorRms before = SplitOf(s, s.baseline.parameters, s.training);
    text += "  registration only: position RMS " + Mm(before.position_m) +
            " mm, rotation RMS " + Mm(before.rotation_rad) + " mrad -> " +
            Mm(after.position_m) + " mm, " + Mm(after.rotation_rad) +
            " mrad calibrated\n";
  }
  const PoseErrorRms held_out = SplitOf(s, id.parameters, s.validation);
  if (held_out.num_poses > 0) {
    const PoseErrorRms nominal = SplitOf(s, s.registered_start, s.validation);
    text += "  held out: position RMS " + Mm(held_out.position_m) +
            " mm, rotation RMS " + Mm(held_out.rotation_rad) +
            " mrad calibrated (" + Mm(nominal.position_m) + " mm, " +
            Mm(nominal.rotation_rad) + " mrad nominal)\n";
  }
  const std::string held = HeldCountNote(s, o);
  if (!held.empty()) text += "  " + held + "\n";
  if (!id.outliers.empty()) {
    text += "  outliers (measurement index in the input):";
    for (int k : id.outliers) text += " " + N(s.training_index[k]);
    text += "\n";
  }
  return text;
}

std::string CalibrationResultLine(const CalibrationSummary& s) {
  const IdentificationSummary& id = s.identification;
  const PoseErrorRms after = SplitOf(s, id.parameters, s.training);
  if (after.num_poses > 0) {
    std::string line = N(static_cast<int>(id.estimates.size())) + " of " +
                       N(s.num_free_in_set) + " parameters identified from " +
                       N(id.num_measurements) + " measurements, RMS position " +
                       Mm(after.position_m) + " mm, rotation " +
                       Mm(after.rotation_rad) + " mrad";
    if (s.have_baseline) {
      const PoseErrorRms before = SplitOf(s, s.baseline.parameters, s.training);
      line += " (registration only " + Mm(before.position_m) + " mm, " +
              Mm(before.rotation_rad) + " mrad)";
    }
    const PoseErrorRms held_out = SplitOf(s, id.parameters, s.validation);
    if (held_out.num_poses > 0) {
      line += ", held out: " + Mm(held_out.position_m) + " mm, " +
              Mm(held_out.rotation_rad) + " mrad RMS on " +
              N(static_cast<int>(s.validation.size())) + " measurements";
    }
    return line;
  }
  std::string line = N(static_cast<int>(id.estimates.size())) + " of " +
                     N(s.num_free_in_set) + " parameters identified from " +
                     N(id.num_measurements) + " measurements, RMS " +
                     Mm(id.rms_m) + " mm";
  if (s.have_baseline) {
    line += " (registration only " + Mm(s.baseline.rms_m) + " mm)";
  }
  const ValidationErrors& v = s.validation_errors;
  if (v.count > 0) {
    line += ", held out: " + Mm(v.rms_calibrated_m) + " mm RMS on " +
            N(v.count) + " measurements";
  }
  return line;
}

std::string OptionsErrorText(const std::string& message,
                             const CalibrationTextOptions& o) {
  const std::string prefix = Option(o, "");
  std::string text = message;
  for (const char* name :
       {"validation_fraction", "prior_std_m", "prior_std_rad",
        "model_selection", "folds", "learned_residual"}) {
    PrefixWord(name, prefix, &text);
  }
  if (message.rfind("learned_residual with ", 0) == 0) {
    for (const char* name : {"compliance", "harmonics"}) {
      PrefixWord(name, prefix, &text);
    }
  }
  return text;
}

std::string LearnedResidualText(const CalibrationSummary& s) {
  if (s.options.learned_residual.mode == LearnedResidualMode::kOff) return "";
  std::string text = s.learned.BriefReport();
  if (s.learned_validation_count > 0) {
    text += "  validation (" + std::to_string(s.learned_validation_count) +
            " held-out position measurements): RMS " +
            FormatNumber("%.4f", s.learned_validation_rms_parametric_m * 1e3) +
            " mm parametric, " +
            FormatNumber("%.4f", s.learned_validation_rms_hybrid_m * 1e3) +
            " mm with the correction\n";
  }
  return text;
}

std::vector<std::vector<double>> SelectionCurveRows(
    const CalibrationSummary& s) {
  std::vector<std::vector<double>> rows;
  for (const ModelSelectionPoint& pt : s.selection.curve) {
    if (!pt.ok) continue;
    rows.push_back({static_cast<double>(pt.num_kept), pt.training_rms_m * 1e3,
                    pt.held_out_rms_m * 1e3});
  }
  return rows;
}

std::string SelectionCurveGnuplot(const CalibrationSummary& s) {
  const std::string kept = N(s.selection.best_num_kept);
  return std::string("set title 'Model selection (") +
         ModelSelectionMethodToString(s.model_selection) +
         "): RMS against parameters kept'\n"
         "set xlabel 'free parameters kept'\nset ylabel 'RMS error (mm)'\n"
         "set logscale y\nset grid\nset key top right\n"
         "set arrow from " +
         kept + ", graph 0 to " + kept +
         ", graph 1 nohead dt 2 lc rgb 'gray40'\n"
         "plot $curve using 1:2 with linespoints pt 7 title 'training', "
         "$curve using 1:3 with linespoints pt 5 title 'held out'\n";
}

std::string CalibrationFailureText(const CalibrationSummary& s,
                                   const CalibrationTextOptions& o) {
  const std::string prefix = Option(o, "");
  std::string text = s.message;
  switch (s.stage) {
    case CalibrationStage::kOptions:
      return OptionsErrorText(text, o);
    case CalibrationStage::kRegistration:
      return text + " (or give the base in a " + prefix +
             "frames file and pass " + Option(o, "register_base", false) + ")";
    case CalibrationStage::kParameterSet:
    case CalibrationStage::kBaseline:
    case CalibrationStage::kModelSelection:
    case CalibrationStage::kLearnedResidual:
      return prefix + text;
    case CalibrationStage::kIdentifiability:
      if (text.rfind("measurements: ", 0) == 0) return prefix + text;
      if (s.auto_fix_would_help) {
        text +=
            ". Fix them in the robot file (remove them from 'free') or "
            "pass " +
            Option(o, "auto_fix", true);
      }
      return text;
    default:
      return text;
  }
}

std::string CalibrationJson(const CalibrationSummary& s,
                            const CalibrationJsonOptions& o) {
  const CalibrationOptions& options = s.options;
  const IdentificationSummary& id = s.identification;
  const RobotModel& model = s.model;
  const bool has_truth = HasTruth(s, o.true_parameters);
  nlohmann::json j;
  j["parameter_set"] = ParameterSetToString(options.parameter_set);
  nlohmann::json held = nlohmann::json::array();
  for (const HeldParameter& h : s.held) {
    if (h.stage != HoldStage::kParameterSet || !Reduced(s)) continue;
    held.push_back({{"name", h.name}, {"reason", h.reason}});
  }
  j["held_fixed"] = held;
  j["registered_base"] = s.registered_base;
  j["robot"] = model.name;
  j["measurements"] = o.simulated ? "simulated" : o.measurements;
  nlohmann::json params = nlohmann::json::array();
  const std::vector<int> free = model.FreeParameterIndices();
  for (size_t k = 0; k < free.size(); ++k) {
    const int i = free[k];
    nlohmann::json entry = {{"name", id.names[k]},
                            {"nominal", model.nominal[i]},
                            {"estimate", id.estimates[k]},
                            {"std", id.standard_deviations[k]}};
    if (!id.chi_square_plausible) {
      entry["std_scaled"] = id.scaled_standard_deviations[k];
    }
    if (has_truth) entry["true"] = o.true_parameters[i];
    params.push_back(entry);
  }
  j["parameters"] = params;
  if (!id.point_labels.empty()) {
    // The fixed points' coordinates (base frame, m) and their covariance.
    nlohmann::json points = nlohmann::json::array();
    for (size_t k = 0; k < id.point_labels.size(); ++k) {
      for (int a = 0; a < 3; ++a) {
        const int i = 3 * static_cast<int>(k) + a;
        points.push_back(
            {{"name", "point." + id.point_labels[k] + "." + "xyz"[a]},
             {"estimate", id.point_coordinates[i]},
             {"std", id.point_standard_deviations.size() > i
                         ? id.point_standard_deviations[i]
                         : 0.0}});
      }
    }
    j["points"] = points;
    j["points_covariance"] = MatrixJson(id.point_covariance);
  }
  if (!id.plane_labels.empty()) {
    // The planes (base frame): unit normal, offset (n . x = d, m), the std
    // of the normal's two tangent angles (rad) and of the offset (m).
    nlohmann::json planes = nlohmann::json::array();
    for (size_t k = 0; k < id.plane_labels.size(); ++k) {
      const Eigen::Vector4d p = id.plane_parameters.segment<4>(4 * k);
      nlohmann::json e = {{"label", id.plane_labels[k]},
                          {"normal", {p[0], p[1], p[2]}},
                          {"offset_m", p[3]}};
      if (id.plane_standard_deviations.size() >=
          3 * static_cast<Eigen::Index>(k + 1)) {
        e["normal_std_rad"] = {id.plane_standard_deviations[3 * k],
                               id.plane_standard_deviations[3 * k + 1]};
        e["offset_std_m"] = id.plane_standard_deviations[3 * k + 2];
      }
      planes.push_back(e);
    }
    j["planes"] = planes;
    j["planes_covariance"] = MatrixJson(id.plane_covariance);
  }
  j["correlation"] = MatrixJson(id.correlation);
  j["covariance"] = MatrixJson(id.covariance);
  nlohmann::json residuals = nlohmann::json::array();
  std::vector<int> outlier_inputs;
  for (int k : id.outliers) outlier_inputs.push_back(s.training_index[k]);
  for (size_t k = 0; k < s.training.size(); ++k) {
    residuals.push_back(
        {{"index", s.training_index[k]},
         {"type", MeasurementTypeName(s.training[k].type)},
         {"initial_norm_m", id.initial_residual_norms[k]},
         {"norm_m", id.residual_norms[k]},
         {"outlier", std::binary_search(id.outliers.begin(), id.outliers.end(),
                                        static_cast<int>(k))}});
  }
  j["residuals"] = residuals;
  j["outliers"] = outlier_inputs;
  j["initial_rms_residual_m"] = id.initial_rms_m;
  j["rms_residual_m"] = id.rms_m;
  j["sigma_m"] = id.sigma_m;
  j["iterations"] = id.iterations;
  j["converged"] = id.termination_type == TerminationType::kConvergence;
  j["termination_type"] = TerminationTypeToString(id.termination_type);
  j["num_measurements"] = id.num_measurements;
  j["auto_fixed"] = HeldNames(s.held);
  j["robust_loss"] = RobustLossToString(options.identification.robust_loss);
  const ValidationErrors& v = s.validation_errors;
  j["validation"] = {{"count", v.count},
                     {"fraction", options.validation_fraction},
                     {"rms_error_nominal_m", v.rms_nominal_m},
                     {"rms_error_calibrated_m", v.rms_calibrated_m},
                     {"max_error_nominal_m", v.max_nominal_m},
                     {"max_error_calibrated_m", v.max_calibrated_m}};
  if (s.have_baseline) {
    j["validation"]["rms_error_registration_only_m"] =
        s.validation_baseline.rms_nominal_m;
    j["validation"]["max_error_registration_only_m"] =
        s.validation_baseline.max_nominal_m;
    j["registration_only"] = {{"rms_residual_m", s.baseline.rms_m},
                              {"parameters", s.baseline.names},
                              {"improvement_percent", s.ImprovementPercent()}};
  } else {
    j["registration_only"] = nullptr;
  }
  // 6D data: position and rotation apart (rms_residual_m weights the
  // rotations).
  const PoseErrorRms after = SplitOf(s, id.parameters, s.training);
  if (after.num_poses > 0) {
    auto split = [](const PoseErrorRms& r) {
      return nlohmann::json{{"num_poses", r.num_poses},
                            {"position_rms_m", r.position_m},
                            {"rotation_rms_rad", r.rotation_rad}};
    };
    nlohmann::json pose_errors = {{"calibrated", split(after)}};
    if (s.have_baseline) {
      pose_errors["registration_only"] =
          split(SplitOf(s, s.baseline.parameters, s.training));
    }
    const PoseErrorRms held_out = SplitOf(s, id.parameters, s.validation);
    if (held_out.num_poses > 0) {
      pose_errors["held_out_calibrated"] = split(held_out);
      pose_errors["held_out_nominal"] =
          split(SplitOf(s, s.registered_start, s.validation));
    }
    j["pose_errors"] = pose_errors;
  }
  j["weighted"] = id.weighted;
  j["degrees_of_freedom"] = id.degrees_of_freedom;
  j["chi_square"] = id.chi_square;
  j["chi_square_per_dof"] = id.chi_square_per_dof;
  j["implied_sigma_m"] = id.implied_sigma_m;
  if (id.weighted) {
    j["chi_square_per_dof_interval"] = {id.chi_square_per_dof_low,
                                        id.chi_square_per_dof_high};
  }
  j["chi_square_plausible"] = id.chi_square_plausible;
  j["prior"] = {{"std_m", options.identification.prior_std_m},
                {"std_rad", options.identification.prior_std_rad},
                {"reference_sigma_m", s.prior_reference_sigma_m}};
  j["warnings"] = s.warnings;
  const ModelSelectionSummary& selection = s.selection;
  nlohmann::json ms;
  ms["method"] = ModelSelectionMethodToString(s.model_selection);
  ms["requested"] = ModelSelectionMethodToString(options.model_selection);
  ms["rule"] = SelectionRuleToString(options.selection_rule);
  ms["minimum_kept"] = selection.minimum_num_kept;
  ms["ranking"] = selection.ranking;
  ms["ranked_by"] = ParameterRankingToString(options.selection_ranking);
  ms["num_registration"] = selection.num_registration;
  ms["kept"] = selection.best_num_kept;
  ms["dropped"] = selection.dropped;
  if (s.model_selection == ModelSelectionMethod::kCrossValidation) {
    ms["folds"] = options.num_folds;
    ms["num_poses"] = selection.num_poses;
  }
  if (!o.validation.empty()) ms["validation"] = o.validation;
  nlohmann::json curve = nlohmann::json::array();
  for (const ModelSelectionPoint& pt : selection.curve) {
    nlohmann::json c = {{"num_kept", pt.num_kept},
                        {"added", pt.added},
                        {"ok", pt.ok},
                        {"training_rms_m", pt.training_rms_m},
                        {"f_test_p_value", pt.f_test_p_value}};
    // NaN is not JSON: a failed point has null.
    if (pt.ok) {
      c["held_out_rms_m"] = pt.held_out_rms_m;
      c["held_out_se_m"] = pt.held_out_se_m;
      c["within_one_se"] = pt.within_one_se;
    } else {
      c["held_out_rms_m"] = nullptr;
    }
    curve.push_back(c);
  }
  ms["curve"] = curve;
  j["model_selection"] = ms;
  if (!options.term_families.empty()) {
    // The joint error terms (term_selection.h): each candidate's held-out
    // error, the families kept, the identified terms.
    const TermSelectionSummary& ts = s.term_selection;
    nlohmann::json terms;
    terms["rule_standard_errors"] = options.term_standard_errors;
    terms["kept"] = ts.kept;
    terms["not_identifiable"] = ts.dropped_terms;
    nlohmann::json candidates = nlohmann::json::array();
    for (const TermCandidate& c : ts.candidates) {
      nlohmann::json cj = {{"name", c.name},
                           {"num_terms", c.num_terms},
                           {"ok", c.ok},
                           {"chosen", c.chosen}};
      if (c.ok) {
        cj["held_out_rms_m"] = c.held_out_rms_m;
        cj["held_out_se_m"] = c.held_out_se_m;
        cj["training_rms_m"] = c.training_rms_m;
        cj["gain_m2"] = c.gain_m2;
        cj["gain_se_m2"] = c.gain_se_m2;
      }
      candidates.push_back(cj);
    }
    terms["candidates"] = candidates;
    nlohmann::json values = nlohmann::json::array();
    const JointErrorModel& je = id.joint_errors;
    for (int t = 0; t < je.size(); ++t) {
      values.push_back({{"name", id.term_names[t]},
                        {"value", je.values[t]},
                        {"std", id.term_standard_deviations.size() > t
                                    ? id.term_standard_deviations[t]
                                    : 0.0},
                        {"unit", je.Unit(s.model, t)}});
    }
    terms["terms"] = values;
    j["joint_error_terms"] = terms;
  }
  j["seed"] = options.seed;
  if (o.simulated) {
    j["pose_indices"] = o.simulated_poses;
    j["noise_m"] = o.noise_m;
  }
  return j.dump(2) + "\n";
}

}  // namespace activecal
