// The Python module `activecal`: identify and evaluate.

#include "activecal/estimation/residual_scale.h"
#include "common.h"

namespace activecal {
namespace python {

std::shared_ptr<EstimateResult> IdentifyPy(const RobotPtr& robot_ptr,
                                           const Measurements& measurements,
                                           py::kwargs kwargs) {
  const Robot& robot = *robot_ptr;
  // A copy: the options are taken out as read, what is left is unknown.
  kwargs = py::reinterpret_steal<py::kwargs>(PyDict_Copy(kwargs.ptr()));
  const std::string parameter_set_name =
      Option<std::string>(kwargs, "parameter_set", "");
  const bool register_base = Option(kwargs, "register_base", true);
  const bool auto_fix = Option(kwargs, "auto_fix", false);
  const std::string model_selection_arg =
      Option<std::string>(kwargs, "model_selection", "auto");
  const std::string rule =
      Option<std::string>(kwargs, "selection_rule", "1se_most");
  const int folds = Option(kwargs, "folds", 5);
  const std::string ranking =
      Option<std::string>(kwargs, "selection_ranking", "significance");
  const std::string robust_loss =
      Option<std::string>(kwargs, "robust_loss", "none");
  const double robust_scale_m = Option(kwargs, "robust_scale_m", 0.0);
  const double outlier_threshold = Option(kwargs, "outlier_threshold", 4.0);
  const double rotation_weight = Option(kwargs, "rotation_weight", 1.0);
  const double default_sigma_m = Option(kwargs, "default_sigma_m", 0.0);
  const double default_sigma_rad = Option(kwargs, "default_sigma_rad", 0.0);
  const double prior_std_m = Option(kwargs, "prior_std_m", 0.0);
  const double prior_std_rad = Option(kwargs, "prior_std_rad", 0.0);
  const uint64_t seed = Option<uint64_t>(kwargs, "seed", 1);
  const int num_threads = Option(kwargs, "num_threads", 0);
  py::object validation_obj = py::none();
  if (kwargs.contains("validation")) {
    validation_obj = kwargs["validation"];
    PyDict_DelItemString(kwargs.ptr(), "validation");
  }
  NoUnknownOptions(
      "identify", kwargs,
      {"parameter_set", "register_base", "auto_fix", "model_selection", "folds",
       "selection_ranking", "selection_rule", "validation", "robust_loss",
       "robust_scale_m", "outlier_threshold", "rotation_weight",
       "default_sigma_m", "default_sigma_rad", "prior_std_m", "prior_std_rad",
       "seed", "num_threads"});
  std::vector<Measurement> selection_validation;
  if (!validation_obj.is_none()) {
    selection_validation = MeasurementsArg(validation_obj, "validation").items;
    CheckMarkers(robot.model(), selection_validation, "validation");
  }

  auto result = std::make_shared<EstimateResult>();
  result->robot = robot_ptr;
  RobotModel model = robot.model();
  const std::vector<Measurement>& training = measurements.items;
  if (training.empty()) Fail("identify: no measurements");
  CheckMarkers(model, training, "measurements");

  IdentificationOptions options;
  if (!ParseRobustLoss(robust_loss, &options.robust_loss)) {
    Fail("robust_loss must be none, huber or cauchy, got '" + robust_loss +
         "'");
  }
  options.robust_scale_m = robust_scale_m;
  options.outlier_threshold = outlier_threshold;
  options.rotation_weight_m_per_rad = rotation_weight;
  options.default_sigma_m = default_sigma_m;
  options.default_sigma_rad = default_sigma_rad;
  if (!(prior_std_m >= 0 && std::isfinite(prior_std_m) && prior_std_rad >= 0 &&
        std::isfinite(prior_std_rad))) {
    Fail("prior_std_m and prior_std_rad must be finite and >= 0");
  }
  const bool map_fit = prior_std_m > 0 || prior_std_rad > 0;
  const ParameterSet set =
      ParameterSetArg(robot, parameter_set_name.empty()
                                 ? py::object(py::none())
                                 : py::object(py::str(parameter_set_name)));
  // auto: the free set the robot file names is identified as listed (as
  // activecal_identify does).
  const std::string model_selection =
      model_selection_arg != "auto"           ? model_selection_arg
      : set == ParameterSet::kFile || map_fit ? "none"
                                              : "cv";
  ModelSelectionOptions selection_options;
  if (!ParseModelSelectionMethod(model_selection, &selection_options.method)) {
    Fail("model_selection must be auto, none, validation or cv, got '" +
         model_selection_arg + "'");
  }
  if (!ParseSelectionRule(rule, &selection_options.rule)) {
    Fail("selection_rule must be 1se_most, min, 1se or ftest, got '" + rule +
         "'");
  }
  if (selection_options.method == ModelSelectionMethod::kValidation &&
      selection_validation.empty()) {
    Fail("model_selection='validation' needs validation=<Measurements>");
  }
  if (map_fit && selection_options.method != ModelSelectionMethod::kNone) {
    Fail(
        "prior_std_m/prior_std_rad (a MAP fit) and model_selection are two "
        "answers to the same question: choose one (model_selection='none')");
  }
  {
    std::string error;
    if (!options.IsValid(&error)) Fail(error);
  }
  if (!ParseParameterRanking(ranking, &selection_options.ranking)) {
    Fail("selection_ranking must be significance or jacobian, got '" + ranking +
         "'");
  }
  result->parameter_set = ParameterSetName(set);
  result->model_selection = model_selection;

  std::string failure;
  bool solver_failure = false;
  {
    py::gil_scoped_release release;
    [&] {
      Eigen::VectorXd initial = model.nominal;
      if (register_base && model.base.convention == LinkConvention::kFrame) {
        RegistrationSummary registration;
        result->registered_base =
            RegisterBaseFrame(model, training, &initial, &registration);
        if (!result->registered_base) {
          failure = registration.message +
                    " (or give the base in a frames file and pass "
                    "register_base=False)";
          return;
        }
      }
      std::vector<DroppedParameter> dropped;
      Eigen::MatrixXd J;
      std::string error;
      const bool reduce = set != ParameterSet::kFile;
      if (!ApplyAndReduceParameterSet(set, training, rotation_weight, &model,
                                      &initial, &dropped, &error)) {
        failure = "parameter_set=" + std::string(ParameterSetName(set)) + ": " +
                  error;
        return;
      }
      if (!StackedJacobian(model, initial, training, rotation_weight, &J,
                           &error)) {
        failure = "measurements: " + error;
        return;
      }
      const std::string what =
          "the " + std::to_string(training.size()) + " measurements";
      IdentifiabilityReport report;
      std::vector<int> fixed_columns;
      if (reduce) {
        for (const DroppedParameter& d : dropped) {
          result->held_fixed.push_back(d.name);
        }
        report = AnalyzeIdentifiability(model, J, options.rank_tolerance);
        if (!report.identifiable()) {
          failure = what + ": " + report.Message();
          return;
        }
      } else if (auto_fix) {
        if (!FixUnidentifiableParameters(&model, J, options.rank_tolerance,
                                         &report, &fixed_columns,
                                         &result->held_fixed)) {
          failure = what + ": " + report.Message();
          return;
        }
      } else {
        report = AnalyzeIdentifiability(model, J, options.rank_tolerance);
        if (!report.identifiable()) {
          failure = what + ": " + report.Message();
          if (report.num_equations >= report.num_free) {
            failure +=
                ". Fix them in the robot file (remove them from 'free') or "
                "pass auto_fix=True";
          }
          return;
        }
      }
      // The baseline (registration_fit.h): the base and marker parameters
      // free in the model to calibrate; and the unit check of its residual
      // (residual_scale.h).
      RegistrationFitSummary baseline;
      {
        IdentificationOptions baseline_options = options;
        baseline_options.prior_std_m = baseline_options.prior_std_rad = 0.0;
        FitRegistrationOfFreeSet(model, robot.model().nominal, training,
                                 baseline_options, &baseline);
      }
      result->have_baseline =
          baseline.termination_type == TerminationType::kConvergence;
      result->registration_only_rms_m = baseline.rms_m;
      if ((result->have_baseline ||
           baseline.termination_type == TerminationType::kNoConvergence) &&
          !ResidualWithinReach(model, robot.model().nominal, training,
                               baseline.rms_m, &error)) {
        failure = "measurements: " + error;
        return;
      }
      selection_options.num_folds = folds;
      selection_options.num_threads = num_threads;
      selection_options.seed = Random::StreamSeed(seed, 3);
      selection_options.identification = options;
      ModelSelectionSummary& selection = result->selection;
      SelectModel(&model, initial, training, selection_validation,
                  selection_options, &selection);
      if (selection.termination_type != TerminationType::kConvergence) {
        failure = (selection_validation.empty() ? "model_selection: "
                                                : "validation: ") +
                  selection.message;
        return;
      }
      if (selection_options.method != ModelSelectionMethod::kNone) {
        for (const std::string& name : selection.dropped) {
          result->held_fixed.push_back(name);
        }
      }
      IdentificationSummary& summary = result->summary;
      if (map_fit) {
        IdentificationSummary plain;
        Identify(model, training, initial, options, &plain);
        if (plain.termination_type != TerminationType::kConvergence) {
          failure = "identification failed: " + plain.message;
          solver_failure =
              plain.termination_type != TerminationType::kUserFailure;
          return;
        }
        options.prior_std_m = prior_std_m;
        options.prior_std_rad = prior_std_rad;
        options.prior_reference_sigma_m = plain.weighted ? 0.0 : plain.sigma_m;
      }
      Identify(model, training, initial, options, &summary);
      if (summary.termination_type != TerminationType::kConvergence) {
        failure = "identification failed: " + summary.message;
        solver_failure =
            summary.termination_type != TerminationType::kUserFailure;
        return;
      }
      result->warnings =
          EstimateWarnings(model, summary, EstimateWarningOptions());
    }();
  }
  if (!failure.empty()) {
    if (solver_failure) throw std::runtime_error(failure);
    Fail(failure);
  }
  result->model = model;
  result->measurements = training;
  result->measurements.insert(result->measurements.end(),
                              selection_validation.begin(),
                              selection_validation.end());
  return result;
}

std::string EstimateFileText(const EstimateResult& e) {
  RobotFileOptions options;
  options.angle_unit = e.robot->description.angle_unit;
  options.comment = "Calibrated by activecal (Python) from " +
                    std::to_string(e.summary.num_measurements) +
                    " measurements, RMS residual " +
                    std::to_string(e.summary.rms_m) + " m";
  return RobotFileText(e.model, e.summary.parameters, options);
}

RobotPtr CalibratedRobot(const EstimateResult& e) {
  auto robot = std::make_shared<Robot>(*e.robot);
  robot->description.model = e.model;
  robot->description.model.nominal = e.summary.parameters;
  return robot;
}

// ------------------------------------------------------------- evaluate

py::dict Stats(const ErrorStatistics& s) {
  py::dict d;
  d["count"] = s.count;
  d["rms"] = s.rms;
  d["mean"] = s.mean;
  d["p95"] = s.p95;
  d["max"] = s.max;
  return d;
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

}  // namespace python
}  // namespace activecal
