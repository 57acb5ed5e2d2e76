// activecal_evaluate: how well a robot model predicts a measurements file,
// with no fitting at all (the model as given, e.g. a calibrated one on
// poses it was not fitted to).

#include <gflags/gflags.h>

#include <cstdio>

#include "activecal/core/csv_files.h"
#include "activecal/core/evaluation.h"
#include "app_common.h"

DEFINE_string(measurements, "",
              "Measurements CSV (docs/formats.md) to predict. Required.");
DEFINE_string(json_out, "",
              "If set, write the report here: rmse_m, rmse_xyz_m, mean_m, "
              "p95_m, max_m, num_measurements, orientation and distance "
              "errors, and the error of every measurement.");

namespace activecal {
namespace {

nlohmann::json StatisticsJson(const ErrorStatistics& s) {
  return {{"count", s.count},
          {"rms", s.rms},
          {"mean", s.mean},
          {"p95", s.p95},
          {"max", s.max}};
}

int Main() {
  if (FLAGS_measurements.empty()) app::Fail("--measurements is required");
  const RobotDescription robot = app::LoadRobotOrDie();
  const RobotModel& model = robot.model;
  const std::vector<Measurement> measurements =
      app::ReadMeasurementsOrDie(FLAGS_measurements, model);
  EvaluationSummary summary;
  if (!EvaluateModel(model, model.nominal, measurements, &summary)) {
    app::Fail("--measurements: " + summary.message);
  }
  std::printf("%s", summary.BriefReport().c_str());
  if (model.base.convention == LinkConvention::kFrame &&
      model.nominal.head(6).isZero(0) && FLAGS_frames.empty()) {
    std::printf(
        "  note: the robot's base frame is the identity (no --frames): the "
        "errors include where the device stands relative to the robot\n");
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
      if (m.type == MeasurementType::kDistance) {
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
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
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
  return activecal::Main();
}
