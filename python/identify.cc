// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The Python module `activecal`: identify and evaluate.

#include <cctype>
#include <sstream>

#include "activecal/calibration/calibration_notes.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/calibration/defaults.h"
#include "activecal/calibration/iso9283_cycles.h"
#include "activecal/core/free_set.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/io/csv_files.h"
#include "common.h"

namespace activecal {
namespace python {

namespace {

using namespace pybind11::literals;  // "name"_a = value

// identify's option `name` taken out of kwargs: `value` when absent or
// None, else the value converted to T or a ValueError naming what T takes.
template <typename T>
T Option(py::kwargs& kwargs, const char* name, T value) {
  if (kwargs.contains(name)) {
    const py::object given = kwargs[name];
    if (!given.is_none()) {
      try {
        value = py::cast<T>(given);
      } catch (const py::cast_error&) {
        const char* want =
            std::is_same<T, std::string>::value ? "a string"
            : std::is_same<T, bool>::value      ? "True or False"
            : std::is_integral<T>::value && std::is_unsigned<T>::value
                ? "a non-negative integer"
            : std::is_integral<T>::value ? "an integer"
                                         : "a number";
        Fail(std::string("identify: option ") + name + ": expected " + want +
             ", got " + Repr(given));
      }
    }
    PyDict_DelItemString(kwargs.ptr(), name);
  }
  return value;
}

// An Estimate's property: the fit's `field` (a copy).
template <typename T>
auto Fitted(T IdentificationSummary::*field) {
  return [field](const EstimateResult& e) -> T { return e.fit().*field; };
}

// An Estimate's property: the calibration's `field` (a copy).
template <typename T>
auto Calibrated(T CalibrationSummary::*field) {
  return [field](const EstimateResult& e) -> T { return e.calibration.*field; };
}

// The value of option `name` (a string) as the library's enum, or a
// ValueError "<name> must be <choices>, got '<text>'".
template <typename Enum>
Enum EnumOption(py::kwargs& kwargs, const char* name, const char* fallback,
                bool (*string_to)(const std::string&, Enum*),
                const char* choices) {
  const std::string text = Option<std::string>(kwargs, name, fallback);
  Enum value;
  if (!string_to(text, &value)) {
    Fail(std::string(name) + " must be " + choices + ", got '" + text + "'");
  }
  return value;
}

std::shared_ptr<EstimateResult> IdentifyPy(const RobotPtr& robot_ptr,
                                           const Measurements& measurements,
                                           py::kwargs kwargs) {
  const Robot& robot = *robot_ptr;
  // A copy: the options are taken out as read, what is left is unknown.
  kwargs = py::reinterpret_steal<py::kwargs>(PyDict_Copy(kwargs.ptr()));
  // As activecal_identify without --rotation_weight: the note on the
  // weight the residuals suggest.
  const bool rotation_weight_given = kwargs.contains("rotation_weight");
  CalibrationOptions options;
  const std::string parameter_set =
      Option<std::string>(kwargs, "parameter_set", "");
  options.register_base = Option(kwargs, "register_base", true);
  options.auto_fix = Option(kwargs, "auto_fix", false);
  options.model_selection =
      EnumOption(kwargs, "model_selection", defaults::kModelSelection,
                 StringToModelSelectionMethod, "auto, none, validation or cv");
  options.selection_rule =
      EnumOption(kwargs, "selection_rule", defaults::kSelectionRule,
                 StringToSelectionRule, "1se_most, min, 1se or ftest");
  options.num_folds = Option(kwargs, "folds", defaults::kFolds);
  options.selection_ranking =
      EnumOption(kwargs, "selection_ranking", defaults::kSelectionRanking,
                 StringToParameterRanking, "significance or jacobian");
  options.validation_fraction = Option(kwargs, "validation_fraction", 0.0);
  IdentificationOptions& fit = options.identification;
  fit.robust_loss = EnumOption(kwargs, "robust_loss", defaults::kRobustLoss,
                               StringToRobustLoss, "none, huber or cauchy");
  fit.robust_scale_m = Option(kwargs, "robust_scale_m", 0.0);
  fit.outlier_probability =
      Option(kwargs, "outlier_probability", fit.outlier_probability);
  fit.rotation_weight_m_per_rad =
      Option(kwargs, "rotation_weight", defaults::kRotationWeightMPerRad);
  fit.default_sigma_m = Option(kwargs, "default_sigma_m", 0.0);
  fit.default_sigma_rad = Option(kwargs, "default_sigma_rad", 0.0);
  fit.prior_std_m = Option(kwargs, "prior_std_m", 0.0);
  fit.prior_std_rad = Option(kwargs, "prior_std_rad", 0.0);
  options.seed = Option<uint64_t>(kwargs, "seed", defaults::kSeed);
  options.num_threads = Option(kwargs, "num_threads", 0);
  LearnedResidualOptions& learned = options.learned_residual;
  learned.mode = EnumOption(kwargs, "learned_residual", "off",
                            StringToLearnedResidualMode, "off, on or auto");
  learned.num_features =
      Option(kwargs, "learned_features", learned.num_features);
  learned.num_standard_errors =
      Option(kwargs, "learned_standard_errors", learned.num_standard_errors);
  py::object validation = py::none();
  if (kwargs.contains("validation")) {
    validation = kwargs["validation"];
    PyDict_DelItemString(kwargs.ptr(), "validation");
  }
  NoUnknownOptions("identify", kwargs,
                   {"parameter_set",
                    "register_base",
                    "auto_fix",
                    "model_selection",
                    "folds",
                    "selection_ranking",
                    "selection_rule",
                    "validation",
                    "validation_fraction",
                    "robust_loss",
                    "robust_scale_m",
                    "outlier_probability",
                    "rotation_weight",
                    "default_sigma_m",
                    "default_sigma_rad",
                    "prior_std_m",
                    "prior_std_rad",
                    "seed",
                    "num_threads",
                    "learned_residual",
                    "learned_features",
                    "learned_standard_errors"});
  if (!validation.is_none()) {
    options.selection_validation =
        MeasurementsArg(validation, "validation").items;
    CheckMarkers(robot.model(), options.selection_validation, "validation");
  }
  if (measurements.items.empty()) Fail("identify: no measurements");
  CheckMarkers(robot.model(), measurements.items, "measurements");
  options.parameter_set = ParameterSetArg(
      robot, parameter_set.empty() ? py::object(py::none())
                                   : py::object(py::str(parameter_set)));

  auto result = std::make_shared<EstimateResult>();
  result->robot = robot_ptr;
  CalibrationSummary& summary = result->calibration;
  CalibrationTextOptions text;
  text.option_spelling = OptionSpelling::kKeywords;
  {
    py::gil_scoped_release release;
    Calibrate(robot.model(), measurements.items, options, &summary);
    // The program's notes, each one line without the trailing newline.
    std::string notes =
        OrientationHintText(summary, measurements.items, "", text);
    if (!rotation_weight_given) {
      notes +=
          RotationWeightNote(robot.model(), measurements.items, summary, text);
    }
    for (size_t at = 0, end; (end = notes.find('\n', at)) != notes.npos;
         at = end + 1) {
      result->notes.push_back(notes.substr(at, end - at));
    }
  }
  if (summary.stage != CalibrationStage::kDone) {
    const std::string message = CalibrationFailureText(summary, text);
    // A solver that did not converge is not a bad argument.
    if (summary.stage == CalibrationStage::kFit &&
        summary.termination_type != TerminationType::kUserFailure) {
      throw std::runtime_error(message);
    }
    Fail(message);
  }
  // What write_urdf checks: the rows identified from and validated on,
  // then the selection's validation rows.
  result->measurements = measurements.items;
  result->measurements.insert(result->measurements.end(),
                              options.selection_validation.begin(),
                              options.selection_validation.end());
  return result;
}

std::string EstimateFileText(const EstimateResult& e) {
  RobotFileOptions options;
  options.angle_unit = e.robot->description.angle_unit;
  options.comment = "Calibrated by activecal (Python) from " +
                    std::to_string(e.fit().num_measurements) +
                    " measurements, RMS residual " +
                    std::to_string(e.fit().rms_m) + " m";
  if (e.calibration.learned.kept &&
      e.calibration.options.learned_residual.mode !=
          LearnedResidualMode::kOff) {
    // As --model_out: the correction travels with the geometry.
    options.learned_correction = &e.calibration.learned.correction;
    options.comment +=
        "\nWith its learned residual (" +
        std::string(LearnedResidualModeToString(
            e.calibration.options.learned_residual.mode)) +
        "): applied by activecal_evaluate and activecal_compensate";
  }
  return RobotFileText(e.model(), e.fit().parameters, options);
}

py::object LearnedResidualPy(const EstimateResult& e) {
  const CalibrationSummary& c = e.calibration;
  if (c.options.learned_residual.mode == LearnedResidualMode::kOff) {
    return py::none();
  }
  const LearnedResidualSummary& l = c.learned;
  // The validation's figures: None without validation rows.
  const bool v = c.learned_validation_count > 0;
  const auto validation = [v](double rms) -> py::object {
    return v ? py::object(py::float_(rms)) : py::object(py::none());
  };
  return py::dict("mode"_a = LearnedResidualModeToString(l.mode),
                  "kept"_a = l.kept,
                  "num_features"_a = l.correction.num_features(),
                  "num_measurements"_a = l.num_measurements,
                  "num_poses"_a = l.num_poses, "num_folds"_a = l.num_folds,
                  "length_scale"_a = l.length_scale, "ridge"_a = l.ridge,
                  "held_out_rms_parametric_m"_a = l.held_out_rms_parametric_m,
                  "held_out_rms_hybrid_m"_a = l.held_out_rms_hybrid_m,
                  "gain_m2"_a = l.gain_m2, "gain_se_m2"_a = l.gain_se_m2,
                  "num_standard_errors"_a = l.num_standard_errors,
                  "training_rms_parametric_m"_a = l.training_rms_parametric_m,
                  "training_rms_hybrid_m"_a = l.training_rms_hybrid_m,
                  "validation_count"_a = c.learned_validation_count,
                  "validation_rms_parametric_m"_a =
                      validation(c.learned_validation_rms_parametric_m),
                  "validation_rms_hybrid_m"_a =
                      validation(c.learned_validation_rms_hybrid_m),
                  "report"_a = LearnedResidualText(c));
}

RobotPtr CalibratedRobot(const EstimateResult& e) {
  auto robot = std::make_shared<Robot>(*e.robot);
  robot->description.model = e.model();
  robot->description.model.nominal = e.fit().parameters;
  return robot;
}

// ------------------------------------------------------------- evaluate

py::dict Stats(const ErrorStatistics& s) {
  return py::dict("count"_a = s.count, "rms"_a = s.rms, "mean"_a = s.mean,
                  "p95"_a = s.p95, "max"_a = s.max);
}

py::dict EvaluatePy(const Robot& robot, const Measurements& measurements,
                    const py::object& parameters) {
  const Eigen::VectorXd p = ParametersArg(robot, parameters);
  CheckMarkers(robot.model(), measurements.items, "measurements");
  EvaluationSummary s;
  {
    py::gil_scoped_release release;
    EvaluateModel(robot.model(), p, measurements.items, &s);
  }
  if (!s.success) Fail(s.message);
  py::dict d;
  d["num_measurements"] = s.num_measurements;
  d["position"] = Stats(s.position);
  d["rotation"] = Stats(s.rotation);
  d["distance"] = Stats(s.distance);
  d["rmse_xyz_m"] = Eigen::Vector3d(s.rmse_xyz_m);
  d["mean_xyz_m"] = Eigen::Vector3d(s.mean_xyz_m);
  Eigen::MatrixXd pe(s.position_errors.size(), 3);
  for (size_t i = 0; i < s.position_errors.size(); ++i) {
    pe.row(i) = s.position_errors[i].transpose();
  }
  d["position_errors_m"] = pe;
  d["rotation_errors_rad"] = py::array(py::cast(s.rotation_errors_rad));
  d["distance_errors_m"] = py::array(py::cast(s.distance_errors_m));
  d["report"] = s.BriefReport();
  return d;
}

py::object Iso9283Py(const Robot& robot, const std::string& path,
                     const py::object& parameters) {
  const Eigen::VectorXd p = ParametersArg(robot, parameters);
  const RobotModel& model = robot.model();
  // As activecal_evaluate --iso9283 (--iso9283_registration=robot): the
  // measurements file with its cycle columns, read by the same readers.
  std::vector<Measurement> items;
  MeasurementsCsvReport report;
  std::vector<CommandedPose> commanded;
  Iso9283CyclesSummary summary;
  std::string error;
  {
    py::gil_scoped_release release;
    if (ReadMeasurementsCsv(path, model, MeasurementsCsvOptions(), &items,
                            &report, &error) &&
        ReadCommandedPosesCsv(path, model, MeasurementsCsvOptions(), &commanded,
                              &error)) {
      if (!EvaluateIso9283Cycles(model, p, items, report.lines, commanded,
                                 &summary)) {
        // "<file>:<line>: <field>: ..." when the message names a line.
        const bool at_line =
            !summary.message.empty() &&
            std::isdigit(static_cast<unsigned char>(summary.message[0]));
        error = path + (at_line ? ":" : ": ") + summary.message;
      }
    }
  }
  if (!error.empty()) Fail(error);
  // The CLI's JSON "iso9283" object, as Python values.
  nlohmann::json j = summary.Json();
  j["registration"] = "robot";
  return py::module_::import("json").attr("loads")(j.dump());
}

}  // namespace

void BindIdentify(py::module_& m) {
  py::class_<EstimateResult, std::shared_ptr<EstimateResult>>(
      m, "Estimate", "An identification result (identify).")
      .def_property_readonly("parameter_names",
                             Fitted(&IdentificationSummary::names),
                             "The identified (free) parameters, in order")
      .def_property_readonly("estimates",
                             Fitted(&IdentificationSummary::estimates))
      .def_property_readonly(
          "std", Fitted(&IdentificationSummary::standard_deviations),
          "Standard deviations of the estimates")
      .def_property_readonly("covariance",
                             Fitted(&IdentificationSummary::covariance))
      .def_property_readonly("correlation",
                             Fitted(&IdentificationSummary::correlation))
      .def_property_readonly(
          "nominal",
          [](const EstimateResult& e) {
            return ExtractFree(e.model(), e.robot->model().nominal);
          },
          "The nominal values of the identified parameters")
      .def_property_readonly("parameters",
                             Fitted(&IdentificationSummary::parameters),
                             "The full parameter vector identified")
      .def_property_readonly(
          "rms_before_m", Fitted(&IdentificationSummary::initial_rms_m),
          "RMS residual norm at the start (nominal, base registered)")
      .def_property_readonly("rms_after_m",
                             Fitted(&IdentificationSummary::rms_m))
      .def_property_readonly(
          "registration_only_rms_m",
          [](const EstimateResult& e) -> py::object {
            if (!e.calibration.have_baseline) return py::none();
            return py::float_(e.calibration.baseline.rms_m);
          },
          "RMS residual with only the base and markers fitted, or None")
      .def_property_readonly("sigma_m", Fitted(&IdentificationSummary::sigma_m))
      .def_property_readonly("iterations",
                             Fitted(&IdentificationSummary::iterations))
      .def_property_readonly("residual_norms",
                             Fitted(&IdentificationSummary::residual_norms))
      .def_property_readonly("outliers",
                             [](const EstimateResult& e) {
                               return py::array(py::cast(e.fit().outliers));
                             })
      .def_property_readonly(
          "termination_type",
          [](const EstimateResult& e) {
            return TerminationTypeToString(e.fit().termination_type);
          })
      .def_property_readonly(
          "held_fixed",
          [](const EstimateResult& e) { return HeldNames(e.calibration.held); },
          "Parameters held at nominal: the parameter set's reduction, "
          "auto_fix, model selection")
      .def_property_readonly("warnings",
                             Calibrated(&CalibrationSummary::warnings))
      .def_property_readonly("registered_base",
                             Calibrated(&CalibrationSummary::registered_base))
      .def_property_readonly(
          "parameter_set",
          [](const EstimateResult& e) {
            return ParameterSetToString(e.calibration.options.parameter_set);
          })
      .def_property_readonly(
          "model_selection_curve",
          [](const EstimateResult& e) {
            py::list curve;
            for (const ModelSelectionPoint& p : e.calibration.selection.curve) {
              curve.append(py::dict("num_kept"_a = p.num_kept,
                                    "added"_a = p.added, "ok"_a = p.ok,
                                    "training_rms_m"_a = p.training_rms_m,
                                    "held_out_rms_m"_a = p.held_out_rms_m));
            }
            return curve;
          })
      .def_property_readonly("learned_residual", &LearnedResidualPy,
                             "learned_residual='on'/'auto': the correction's "
                             "fit and decision (a dict), else None")
      .def_readonly("notes", &EstimateResult::notes,
                    "activecal_identify's notes: the orientation hint, the "
                    "rotation_weight note (when not given)")
      .def_property_readonly(
          "robot", &CalibratedRobot,
          "The calibrated Robot: identified values as nominal")
      .def(
          "save",
          [](const EstimateResult& e, const py::object& path) {
            WriteText(PathArg(path), EstimateFileText(e));
          },
          py::arg("path"),
          "Writes the calibrated robot YAML (as activecal_identify "
          "--model_out); load_robot(path) reads it back.")
      .def("report",
           [](const EstimateResult& e) { return e.fit().BriefReport(); })
      .def("__repr__", [](const EstimateResult& e) {
        std::ostringstream s;
        s << "<activecal.Estimate: " << e.fit().num_free << " parameters, RMS "
          << e.fit().initial_rms_m << " -> " << e.fit().rms_m << " m>";
        return s.str();
      });

  m.def("identify", &IdentifyPy, py::arg("robot"), py::arg("measurements"),
        "identify(robot, measurements, **options) -> Estimate, as "
        "activecal_identify with the same options: parameter_set, "
        "register_base, auto_fix, model_selection ('auto': 'none' for the "
        "robot file's free set, 'cv' for a named set; 'cv', 'validation', "
        "'none'), folds, selection_ranking, selection_rule ('1se_most', "
        "'min', '1se', 'ftest'), validation (Measurements), "
        "validation_fraction (held out at random, seeded), "
        "robust_loss, robust_scale_m, outlier_probability, rotation_weight, "
        "default_sigma_m, default_sigma_rad, prior_std_m, prior_std_rad, "
        "seed, num_threads, learned_residual ('off', 'on', 'auto'), "
        "learned_features, learned_standard_errors. The GIL is released "
        "while it runs.");

  m.def("evaluate", &EvaluatePy, py::arg("robot"), py::arg("measurements"),
        py::arg("parameters") = py::none(),
        "The errors of a model (robot's nominal, or `parameters`) on "
        "measurements, no fitting: a dict of statistics (m, rad).");
  m.def("iso9283", &Iso9283Py, py::arg("robot"), py::arg("path"),
        py::arg("parameters") = py::none(),
        "ISO 9283 pose accuracy and repeatability of the cycles in the "
        "measurements CSV `path` (pose label and commanded_* columns, "
        "docs/iso9283.md), in the base frame of the model (robot's nominal, "
        "or `parameters`): the dict activecal_evaluate --iso9283 writes "
        "under 'iso9283' in --json_out, the same numbers (poses[i].without "
        "/ .with: ap_p_m, rp_l_m, ap_abc_rad, ...). Bad input is a "
        "ValueError naming file, line and field.");
}

}  // namespace python
}  // namespace activecal
