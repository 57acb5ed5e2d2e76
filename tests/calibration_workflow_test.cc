// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The parts of activecal_identify's workflow in the library: the learned
// residual as a stage of Calibrate (calibrate.h), the joint error families
// from plain values (calibration_setup.h), the rotation-weight note and the
// orientation hint (calibration_notes.h), the output files
// (calibration_outputs.h) and all of them in order (report/calibration_run.h).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/calibration/calibration_notes.h"
#include "activecal/calibration/calibration_outputs.h"
#include "activecal/calibration/calibration_report.h"
#include "activecal/calibration/calibration_setup.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/simulation.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "activecal/report/calibration_run.h"
#include "activecal/report/gnuplot_figure.h"
#include "activecal/report/html_report.h"
#include "test_util.h"

namespace activecal {
namespace {

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0;
}

// 80 simulated PUMA positions with a smooth non-geometric error (0.2 mm).
std::vector<Measurement> SmoothPuma() {
  const RobotModel model = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(model, 5, &lattice, &error)) << error;
  std::vector<int64_t> poses;
  std::vector<Measurement> data;
  EXPECT_TRUE(SimulateAtRandomLatticePoses(model, Puma560TrueParameters(),
                                           lattice, 80, 1e-6, 3, &poses, &data,
                                           &error))
      << error;
  for (Measurement& m : data) {
    const Eigen::VectorXd& q = m.joints;
    m.position.x() += 2e-4 * std::sin(q[0]) * std::cos(q[1]);
    m.position.y() += 2e-4 * std::cos(q[1] + q[2]);
  }
  return data;
}

// The PUMA, SmoothPuma() and their calibration with the default options.
class DefaultCalibrationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    Calibrate(model_, data_, CalibrationOptions(), &summary_);
    ASSERT_EQ(summary_.stage, CalibrationStage::kDone) << summary_.message;
  }
  const RobotModel model_ = Puma560PaperModel();
  const std::vector<Measurement> data_ = SmoothPuma();
  CalibrationSummary summary_;
};

TEST(CalibrationWorkflowTest, LearnedResidualIsAStageOfCalibrate) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = SmoothPuma();
  CalibrationOptions options;
  options.validation_fraction = 0.25;
  options.num_threads = 2;
  options.learned_residual.mode = LearnedResidualMode::kOn;
  options.learned_residual.num_features = 50;
  CalibrationSummary summary;
  Calibrate(model, data, options, &summary);
  ASSERT_EQ(summary.stage, CalibrationStage::kDone) << summary.message;
  EXPECT_EQ(summary.learned.termination_type, TerminationType::kConvergence);
  EXPECT_TRUE(summary.learned.kept);
  EXPECT_EQ(summary.learned.num_folds, options.num_folds);
  EXPECT_EQ(summary.learned_validation_count, 20);
  EXPECT_GT(summary.learned_validation_rms_parametric_m, 0.0);
  EXPECT_LT(summary.learned_validation_rms_hybrid_m,
            summary.learned_validation_rms_parametric_m);
  const std::string text = LearnedResidualText(summary);
  EXPECT_TRUE(StartsWith(text, "learned residual (on): 50 random Fourier"))
      << text;
  EXPECT_NE(text.find("  validation (20 held-out position measurements): RMS "),
            std::string::npos)
      << text;

  // Off: nothing fitted, no text.
  options.learned_residual.mode = LearnedResidualMode::kOff;
  CalibrationSummary off;
  Calibrate(model, data, options, &off);
  ASSERT_EQ(off.stage, CalibrationStage::kDone);
  EXPECT_FALSE(off.learned.kept);
  EXPECT_EQ(LearnedResidualText(off), "");
  EXPECT_EQ(off.BriefReport(), summary.BriefReport());
}

TEST(CalibrationWorkflowTest, LearnedResidualFailureAfterTheFit) {
  const RobotModel model = Puma560PaperModel();
  std::vector<Measurement> data = SmoothPuma();
  data.resize(40);
  CalibrationOptions options;
  options.num_folds = 41;  // more folds than poses
  options.learned_residual.mode = LearnedResidualMode::kAuto;
  options.learned_residual.num_features = 20;
  CalibrationSummary summary;
  Calibrate(model, data, options, &summary);
  ASSERT_EQ(summary.stage, CalibrationStage::kLearnedResidual)
      << summary.message;
  EXPECT_TRUE(summary.Passed(CalibrationStage::kValidation));
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  // The fit's report, then the failure.
  const std::string report = summary.BriefReport();
  EXPECT_TRUE(StartsWith(report, summary.identification.BriefReport()));
  EXPECT_NE(report.find("calibration failed (learned_residual): "
                        "learned_residual: "),
            std::string::npos)
      << report;
  CalibrationTextOptions text;
  EXPECT_TRUE(StartsWith(CalibrationFailureText(summary, text),
                         "--learned_residual: "));
}

TEST(CalibrationWorkflowTest, LearnedResidualOptionsNamedInEitherSpelling) {
  CalibrationOptions options;
  std::string error;
  EXPECT_TRUE(options.LearnedResidualIsValid(&error));
  options.learned_residual.mode = LearnedResidualMode::kAuto;
  options.learned_residual.num_features = 0;
  EXPECT_FALSE(options.LearnedResidualIsValid(&error));
  EXPECT_FALSE(options.IsValid(nullptr));
  CalibrationTextOptions flags, keywords;
  keywords.option_spelling = OptionSpelling::kKeywords;
  EXPECT_EQ(OptionsErrorText(error, flags),
            "--learned_residual: num_features must be in [1, 5000], got 0");
  EXPECT_EQ(OptionsErrorText(error, keywords),
            "learned_residual: num_features must be in [1, 5000], got 0");
  options.learned_residual.num_features = 10;
  options.num_folds = 2;
  EXPECT_FALSE(options.LearnedResidualIsValid(&error));
  EXPECT_EQ(OptionsErrorText(error, flags),
            "--learned_residual: num_folds must be >= 3 (nested "
            "cross-validation), got 2");
  options.num_folds = 5;
  options.term_families.push_back(
      {"periodic", HarmonicTerms(Puma560PaperModel(), 1)});
  EXPECT_FALSE(options.LearnedResidualIsValid(&error));
  EXPECT_EQ(OptionsErrorText(error, flags),
            "--learned_residual with --compliance or --harmonics: not "
            "supported (the correction is learned on the geometry's "
            "residuals alone; use one or the other)");
}

TEST(CalibrationWorkflowTest, TermFamiliesFromPlainValues) {
  const RobotModel model = Puma560PaperModel();
  std::vector<TermFamily> families;
  std::string error;
  TermFamilyOptions o;
  EXPECT_TRUE(
      MakeTermFamilies(model, o, OptionSpelling::kFlags, &families, &error));
  EXPECT_TRUE(families.empty());
  o.harmonics = 2;
  ASSERT_TRUE(
      MakeTermFamilies(model, o, OptionSpelling::kFlags, &families, &error));
  ASSERT_EQ(families.size(), 1u);
  EXPECT_EQ(families[0].name, "periodic");
  o.harmonics = 9;
  EXPECT_FALSE(
      MakeTermFamilies(model, o, OptionSpelling::kFlags, &families, &error));
  EXPECT_EQ(error, "--harmonics must be in [0, 8], got 9");
  o.harmonics = 0;
  o.payload_com_m = "0,0,1";
  EXPECT_FALSE(
      MakeTermFamilies(model, o, OptionSpelling::kKeywords, &families, &error));
  EXPECT_EQ(error,
            "payload_com_m needs payload_kg > 0 (a payload without mass)");
  o.payload_com_m = "";
  o.payload_kg = 2;
  EXPECT_FALSE(
      MakeTermFamilies(model, o, OptionSpelling::kFlags, &families, &error));
  EXPECT_EQ(error, "--payload_kg is used by --compliance only");
  o.compliance = true;
  o.gravity = "0,0";
  EXPECT_FALSE(
      MakeTermFamilies(model, o, OptionSpelling::kFlags, &families, &error));
  EXPECT_EQ(error, "--gravity: expected 'x,y,z' in m/s^2, got '0,0'");
  o.gravity = "0,0,-9.81";
  ASSERT_TRUE(
      MakeTermFamilies(model, o, OptionSpelling::kFlags, &families, &error))
      << error;
  ASSERT_EQ(families.size(), 1u);
  EXPECT_EQ(families[0].name, "compliance");
  o.payload_kg = 0;
  o.robot_path = "puma.yaml";
  EXPECT_FALSE(
      MakeTermFamilies(model, o, OptionSpelling::kFlags, &families, &error));
  EXPECT_EQ(error,
            "--compliance needs link masses: --robot puma.yaml is not a URDF "
            "with <inertial> elements; give a URDF or --payload_kg");
  Eigen::Vector3d v;
  EXPECT_TRUE(ParseVector3("1,2.5,-3", &v));
  EXPECT_EQ(v, Eigen::Vector3d(1, 2.5, -3));
  EXPECT_FALSE(ParseVector3("1,2,3,4", &v));
  EXPECT_FALSE(ParseVector3("1,2,nan", &v));
}

TEST(CalibrationWorkflowTest, RotationWeightNoteAndOrientationHint) {
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(testing::LoadShippedUr("ur10e.urdf", &robot, &error)) << error;
  std::vector<Measurement> data;
  ASSERT_TRUE(ReadMeasurementsCsv(
      std::string(ACTIVECAL_DATA_DIR) + "/figaroh_ur10e/measurements.csv",
      robot.model, &data, &error))
      << error;
  CalibrationOptions options;
  options.parameter_set = ParameterSet::kFull;
  options.model_selection = ModelSelectionMethod::kNone;
  CalibrationSummary summary;
  Calibrate(robot.model, data, options, &summary);
  ASSERT_EQ(summary.stage, CalibrationStage::kDone) << summary.message;
  CalibrationTextOptions text;
  text.program = "prog";
  const std::string note = RotationWeightNote(robot.model, data, summary, text);
  EXPECT_TRUE(StartsWith(note,
                         "prog: note: --rotation_weight not given: the "
                         "orientations of the pose rows were weighted 1 "
                         "m/rad and 30 parameters kept; their residuals "
                         "(between 23 poses: "))
      << note;
  EXPECT_NE(note.find("with which the calibration keeps 30 parameters"),
            std::string::npos)
      << note;
  // The device's own orientations fit: no hint.
  EXPECT_EQ(OrientationHintText(summary, data, "", text), "");
  // Turned orientations fit badly: the hint names the columns given.
  std::vector<Measurement> turned = data;
  for (size_t i = 0; i < turned.size(); ++i) {
    // A different turn at every pose (a rotation vector).
    turned[i].rotation += Eigen::Vector3d(0.3 * static_cast<double>(i % 5),
                                          -0.2 * static_cast<double>(i % 3), 0);
  }
  const std::string hint =
      OrientationHintText(summary, turned, "a, b, c as XYZ", text);
  EXPECT_TRUE(StartsWith(hint, "prog: warning: orientations fit badly"))
      << hint;
  EXPECT_NE(hint.find("(a, b, c as XYZ)"), std::string::npos) << hint;
}

TEST_F(DefaultCalibrationTest, OutputsMadeAndCheckedBeforeWriting) {
  CalibrationOutputOptions o;
  o.model_out = "m.yaml";
  o.urdf_out = "m.urdf";
  o.frames_out = "f.yaml";
  o.json_out = "r.json";
  o.source = "data.csv";
  CalibrationOutputs outputs;
  std::string error;
  ASSERT_TRUE(MakeCalibrationOutputs(summary_, data_, o, &outputs, &error))
      << error;
  ASSERT_EQ(outputs.files.size(), 4u);
  EXPECT_EQ(outputs.files[0].path, "m.yaml");
  EXPECT_TRUE(StartsWith(outputs.files[0].text,
                         "# Calibrated by activecal_identify from data.csv\n"))
      << outputs.files[0].text.substr(0, 80);
  EXPECT_EQ(outputs.files[1].path, "m.urdf");
  EXPECT_EQ(outputs.files[2].path, "f.yaml");
  // The report of this fit: its measurements, residual and parameters.
  EXPECT_EQ(outputs.files[3].path, "r.json");
  const nlohmann::json report = nlohmann::json::parse(outputs.files[3].text);
  EXPECT_EQ(report["num_measurements"].get<int>(),
            static_cast<int>(data_.size()));
  EXPECT_DOUBLE_EQ(report["rms_residual_m"].get<double>(),
                   summary_.identification.rms_m);
  EXPECT_GT(report["rms_residual_m"].get<double>(), 0.0);
  EXPECT_EQ(report["parameters"].size(),
            summary_.identification.estimates.size());
  EXPECT_TRUE(StartsWith(outputs.notes_after,
                         "  --urdf_out: wrote m.urdf; reloaded, it predicts "
                         "every measured point within "))
      << outputs.notes_after;
  // Not a UR: no file at all, the option named.
  o.ur_calibration_out = "ur.yaml";
  EXPECT_FALSE(MakeCalibrationOutputs(summary_, data_, o, &outputs, &error));
  EXPECT_TRUE(outputs.files.empty());
  EXPECT_TRUE(StartsWith(error, "--ur_calibration_out: ")) << error;
}

TEST(CalibrationWorkflowTest, SelectionCurvePlotAndOutputPaths) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = SmoothPuma();
  CalibrationOptions options;
  options.parameter_set = ParameterSet::kFull;
  options.model_selection = ModelSelectionMethod::kCrossValidation;
  options.num_threads = 2;
  CalibrationSummary summary;
  Calibrate(model, data, options, &summary);
  ASSERT_EQ(summary.stage, CalibrationStage::kDone) << summary.message;
  const std::vector<std::vector<double>> rows = SelectionCurveRows(summary);
  ASSERT_FALSE(rows.empty());
  const ModelSelectionPoint& first = summary.selection.curve[0];
  ASSERT_TRUE(first.ok);
  EXPECT_EQ(rows[0], (std::vector<double>{static_cast<double>(first.num_kept),
                                          first.training_rms_m * 1e3,
                                          first.held_out_rms_m * 1e3}));
  const std::string kept = std::to_string(summary.selection.best_num_kept);
  const std::string script = SelectionCurveGnuplot(summary);
  EXPECT_TRUE(StartsWith(script,
                         "set title 'Model selection (cv): RMS "
                         "against parameters kept'\n"))
      << script;
  EXPECT_NE(script.find("set arrow from " + kept + ", graph 0 to " + kept),
            std::string::npos)
      << script;

  CalibrationOutputOptions o;
  o.json_out = "r.json";
  o.model_out = "m.yaml";
  o.ur_calibration_out = "u.yaml";
  using Paths = std::vector<std::pair<std::string, std::string>>;
  EXPECT_EQ(o.Paths(), (Paths{{"m.yaml", "model_out"},
                              {"u.yaml", "ur_calibration_out"},
                              {"r.json", "json_out"}}));
  o.report_html = "r.html";  // checked last
  EXPECT_EQ(o.Paths().back(),
            (std::pair<std::string, std::string>{"r.html", "report_html"}));
}

TEST(CalibrationWorkflowTest, OptionsCheckedBeforeReadingAFile) {
  CalibrationOptions options;
  CalibrationTextOptions text;
  std::string error;
  EXPECT_TRUE(CheckOptionsBeforeReading(options, false, text, &error));
  EXPECT_FALSE(CheckOptionsBeforeReading(options, true, text, &error));
  EXPECT_EQ(error, "--validation is used by --model_selection=validation only");
  options.model_selection = ModelSelectionMethod::kValidation;
  EXPECT_TRUE(CheckOptionsBeforeReading(options, true, text, &error));
  EXPECT_FALSE(CheckOptionsBeforeReading(options, false, text, &error));
  EXPECT_EQ(error, "--model_selection=validation needs --validation=FILE");
  text.option_spelling = OptionSpelling::kKeywords;
  EXPECT_FALSE(CheckOptionsBeforeReading(options, false, text, &error));
  EXPECT_EQ(error, "model_selection=validation needs validation=FILE");
  // The learned residual first, named in the caller's spelling.
  options.learned_residual.mode = LearnedResidualMode::kOn;
  options.learned_residual.num_features = 0;
  text.option_spelling = OptionSpelling::kFlags;
  EXPECT_FALSE(CheckOptionsBeforeReading(options, true, text, &error));
  EXPECT_TRUE(StartsWith(error, "--learned_residual")) << error;
}

TEST(CalibrationWorkflowTest, SimulatedMeasurementsWithoutAFile) {
  RobotDescription robot;
  robot.model = Puma560PaperModel();
  CalibrationSimulationOptions sim;
  sim.num_poses = 12;
  std::vector<int64_t> poses;
  std::vector<Measurement> data;
  std::string notes, error;
  // No true values to simulate from.
  EXPECT_FALSE(SimulateCalibrationMeasurements(
      robot, sim, OptionSpelling::kFlags, &poses, &data, &notes, &error));
  EXPECT_TRUE(StartsWith(error,
                         "no --measurements given and --robot has no "
                         "true values"))
      << error;
  robot.true_parameters = Puma560TrueParameters();
  ASSERT_TRUE(SimulateCalibrationMeasurements(
      robot, sim, OptionSpelling::kFlags, &poses, &data, &notes, &error))
      << error;
  EXPECT_EQ(data.size(), 12u);
  EXPECT_EQ(poses.size(), 12u);
  // The same draw as SimulateAtRandomLatticePoses on that lattice.
  JointLattice lattice;
  ASSERT_TRUE(JointLattice::Create(robot.model, sim.levels, &lattice, &error));
  std::vector<int64_t> same_poses;
  std::vector<Measurement> same;
  ASSERT_TRUE(SimulateAtRandomLatticePoses(robot.model, robot.true_parameters,
                                           lattice, 12, sim.noise_m, sim.seed,
                                           &same_poses, &same, &error));
  EXPECT_EQ(poses, same_poses);
  EXPECT_EQ(data[11].position, same[11].position);
  sim.levels = 1;
  EXPECT_FALSE(SimulateCalibrationMeasurements(
      robot, sim, OptionSpelling::kFlags, &poses, &data, &notes, &error));
  EXPECT_TRUE(StartsWith(error, "--levels=1: ")) << error;
  sim.levels = 5;
  sim.num_poses = 0;
  EXPECT_FALSE(SimulateCalibrationMeasurements(
      robot, sim, OptionSpelling::kKeywords, &poses, &data, &notes, &error));
  EXPECT_TRUE(StartsWith(error, "num_poses must be in [1, ")) << error;
}

TEST_F(DefaultCalibrationTest, PrintoutInOrderAndWhereToFail) {
  CalibrationTextOptions text;
  const CalibrationPrintout done =
      MakeCalibrationPrintout(model_, data_, summary_, "", false, text);
  EXPECT_EQ(done.stages, CalibrationStagesText(summary_, text));
  EXPECT_FALSE(done.has_selection_curve);  // a file set: no selection
  EXPECT_EQ(done.report, OrientationHintText(summary_, data_, "", text) +
                             CalibrationResultText(summary_, text));
  EXPECT_TRUE(done.failure.empty());
  // A failed validation: the hint, no result, the failure.
  CalibrationSummary failed = summary_;
  failed.stage = CalibrationStage::kValidation;
  failed.message = "validation: failed";
  const CalibrationPrintout f =
      MakeCalibrationPrintout(model_, data_, failed, "", true, text);
  EXPECT_EQ(f.report, OrientationHintText(failed, data_, "", text));
  EXPECT_EQ(f.failure, CalibrationFailureText(failed, text));
  EXPECT_FALSE(f.failure.empty());
  // The learned residual failed: the fit's report, then the failure.
  failed.stage = CalibrationStage::kLearnedResidual;
  const CalibrationPrintout l =
      MakeCalibrationPrintout(model_, data_, failed, "", false, text);
  EXPECT_NE(l.report.find(CalibrationResultText(failed, text)),
            std::string::npos);
  EXPECT_FALSE(l.failure.empty());
}

TEST_F(DefaultCalibrationTest, HtmlReportWithTheOtherOutputs) {
  CalibrationOutputOptions o;
  o.json_out = "r.json";
  o.report_html = "r.html";
  o.source = "data.csv";
  CalibrationOutputs outputs;
  std::string error;
  ASSERT_TRUE(
      MakeCalibrationOutputsAndReport(summary_, data_, o, &outputs, &error))
      << error;
  ASSERT_EQ(outputs.files.size(), 2u);
  EXPECT_EQ(outputs.files[0].path, "r.json");
  EXPECT_EQ(outputs.files[1].path, "r.html");
  EXPECT_NE(outputs.files[1].text.find("built-in PUMA 560"), std::string::npos);
  EXPECT_NE(outputs.files[1].text.find("data.csv"), std::string::npos);
  // Without report_html: MakeCalibrationOutputs' files alone.
  o.report_html.clear();
  ASSERT_TRUE(
      MakeCalibrationOutputsAndReport(summary_, data_, o, &outputs, &error));
  EXPECT_EQ(outputs.files.size(), 1u);
}

// Calibrate's summary of `data` on `model` with `options`.
CalibrationSummary CalibratedWith(const RobotModel& model,
                                  const std::vector<Measurement>& data,
                                  const CalibrationOptions& options) {
  CalibrationSummary summary;
  Calibrate(model, data, options, &summary);
  return summary;
}

TEST(CalibrationWorkflowTest, CalibrationRunPrintsAndWritesInOrder) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = SmoothPuma();
  const CalibrationOptions options;
  const CalibrationSummary summary = CalibratedWith(model, data, options);
  ASSERT_EQ(summary.stage, CalibrationStage::kDone) << summary.message;
  CalibrationRunOptions o;
  o.outputs.json_out = "r.json";
  o.outputs.report_html = "r.html";
  o.outputs.source = "data.csv";
  o.selection_plot = "curve.png";  // no model selection ran: no figure
  CalibrationRunOutputs run;
  MakeCalibrationRunOutputs(model, data, summary, o, &run);
  EXPECT_TRUE(run.failure.empty()) << run.failure;
  const CalibrationPrintout printout =
      MakeCalibrationPrintout(model, data, summary, "", false, o.outputs.text);
  CalibrationOutputs outputs;
  std::string error;
  ASSERT_TRUE(MakeCalibrationOutputsAndReport(summary, data, o.outputs,
                                              &outputs, &error))
      << error;
  EXPECT_EQ(run.printed,
            printout.stages + printout.report + outputs.notes_before);
  ASSERT_EQ(run.files.size(), 2u);
  EXPECT_EQ(run.files[0].path, "r.json");
  EXPECT_EQ(run.files[0].text, outputs.files[0].text);
  EXPECT_EQ(run.files[1].path, "r.html");
  EXPECT_EQ(run.notes_after, outputs.notes_after);
  // A calibration that failed: its failure after the report, no files.
  CalibrationSummary failed = summary;
  failed.stage = CalibrationStage::kValidation;
  failed.message = "validation: failed";
  MakeCalibrationRunOutputs(model, data, failed, o, &run);
  const CalibrationPrintout f =
      MakeCalibrationPrintout(model, data, failed, "", false, o.outputs.text);
  EXPECT_EQ(run.failure, f.failure);
  EXPECT_FALSE(run.failure.empty());
  EXPECT_EQ(run.printed, f.stages + f.report);
  EXPECT_TRUE(run.files.empty());
}

TEST(CalibrationWorkflowTest, CalibrationRunDrawsTheSelectionCurveFirst) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> data = SmoothPuma();
  CalibrationOptions options;
  options.model_selection = ModelSelectionMethod::kCrossValidation;
  options.num_folds = 2;
  options.num_threads = 2;
  const CalibrationSummary summary = CalibratedWith(model, data, options);
  ASSERT_EQ(summary.stage, CalibrationStage::kDone) << summary.message;
  CalibrationRunOptions o;
  o.outputs.json_out = "r.json";
  o.selection_plot = ::testing::TempDir() + "program_outputs_curve.png";
  CalibrationRunOutputs run;
  MakeCalibrationRunOutputs(model, data, summary, o, &run);
  ASSERT_TRUE(run.failure.empty()) << run.failure;
  const CalibrationPrintout printout =
      MakeCalibrationPrintout(model, data, summary, "", false, o.outputs.text);
  ASSERT_TRUE(printout.has_selection_curve);
  const std::string note =
      GnuplotAvailable()
          ? "  --selection_plot: wrote " + o.selection_plot + "\n"
          : "  --selection_plot: gnuplot is not installed; no plot\n";
  EXPECT_EQ(run.printed.substr(0, printout.stages.size() + note.size()),
            printout.stages + note);
  ASSERT_EQ(run.files.size(), GnuplotAvailable() ? 2u : 1u);
  if (GnuplotAvailable()) {
    EXPECT_EQ(run.files[0].path, o.selection_plot);
    EXPECT_EQ(run.files[0].text.substr(1, 3), "PNG");
  }
  EXPECT_EQ(run.files.back().path, "r.json");
  // Named in the keywords' spelling; a folder refused before any file.
  if (!GnuplotAvailable()) return;
  o.outputs.text.option_spelling = OptionSpelling::kKeywords;
  o.selection_plot = ::testing::TempDir() + "program_outputs_folder";
  std::filesystem::create_directories(o.selection_plot);
  MakeCalibrationRunOutputs(model, data, summary, o, &run);
  EXPECT_EQ(run.failure, "selection_plot: cannot write '" + o.selection_plot +
                             "': it is a directory");
  EXPECT_EQ(run.printed, printout.stages);
  EXPECT_TRUE(run.files.empty());
}

TEST(CalibrationWorkflowTest, EvaluationHtmlNamesTheFilesAndErrors) {
  RobotDescription robot;
  robot.model = Puma560PaperModel();
  const std::vector<Measurement> data = SmoothPuma();
  EvaluateOptions options;
  options.robot_path = "r.yaml";
  options.measurements_path = "m.csv";
  options.training_path = "t.csv";
  options.before = BeforeBaseline::kNone;
  EvaluateSummary summary;
  Evaluate(robot, data, options, &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  std::string html, error;
  ASSERT_TRUE(EvaluationHtmlText(robot, data, options, summary, &html, &error))
      << error;
  EXPECT_NE(html.find("activecal evaluation report"), std::string::npos);
  EXPECT_NE(html.find("m.csv (80)"), std::string::npos);
  EXPECT_NE(html.find("t.csv"), std::string::npos);
  EXPECT_NE(html.find("after.evaluated"), std::string::npos);
  EXPECT_EQ(html.find("before.evaluated"), std::string::npos);  // none
}

}  // namespace
}  // namespace activecal
