// activecal_identify: simulate position measurements of the paper's PUMA 560
// at random lattice poses and identify its 27 parameters.

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>
#include <iostream>

#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/residuals/identification.h"
#include "app_common.h"

DEFINE_int32(num_poses, 30,
             "Number of distinct random lattice poses to measure.");
DEFINE_int32(levels, 5, "Lattice values per joint (both range ends included).");
DEFINE_uint64(seed, 1, "Seed for the pose draw and the measurement noise.");
DEFINE_double(noise_m, 0.01,
              "Standard deviation of the measurement noise on each axis (m).");
DEFINE_int32(threads, 1,
             "Threads for the solver (the result does not depend "
             "on it).");
DEFINE_string(json_out, "", "If set, write the identification report here.");

namespace activecal {
namespace {

int Main() {
  const RobotModel model = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  const JointLattice lattice = app::MakeLatticeOrDie(model, FLAGS_levels);
  if (FLAGS_num_poses <= 0 || FLAGS_num_poses > lattice.size()) {
    app::Fail("--num_poses must be in [1, " + std::to_string(lattice.size()) +
              "], got " + std::to_string(FLAGS_num_poses));
  }
  Random random(Random::StreamSeed(FLAGS_seed, 0));
  const std::vector<int64_t> poses =
      random.SampleWithoutReplacement(lattice.size(), FLAGS_num_poses);
  Eigen::MatrixXd joints(poses.size(), model.num_joints());
  for (size_t i = 0; i < poses.size(); ++i) {
    joints.row(i) = lattice.JointValues(poses[i]).transpose();
  }
  std::vector<PositionMeasurement> measurements;
  std::string error;
  if (!SimulatePositionMeasurements(model, truth, joints, FLAGS_noise_m,
                                    Random::StreamSeed(FLAGS_seed, 1),
                                    &measurements, &error)) {
    app::Fail(error);
  }
  IdentificationOptions options;
  options.num_threads = FLAGS_threads;
  IdentificationSummary summary;
  if (!Identify(model, measurements, model.nominal, options, &summary)) {
    app::Fail("identification failed: " + summary.message);
  }

  const std::vector<int> free = model.FreeParameterIndices();
  std::printf("%-10s %12s %12s %12s %12s %12s %8s\n", "parameter", "true",
              "nominal", "estimate", "error", "std", "err/std");
  int outside = 0;
  nlohmann::json params = nlohmann::json::array();
  for (size_t k = 0; k < free.size(); ++k) {
    const int i = free[k];
    const double err = summary.estimates[k] - truth[i];
    const double sd = summary.standard_deviations[k];
    if (std::abs(err) > 4 * sd) ++outside;
    std::printf("%-10s %12.6f %12.6f %12.6f %12.6f %12.6f %8.2f\n",
                summary.names[k].c_str(), truth[i], model.nominal[i],
                summary.estimates[k], err, sd, err / sd);
    params.push_back({{"name", summary.names[k]},
                      {"true", truth[i]},
                      {"nominal", model.nominal[i]},
                      {"estimate", summary.estimates[k]},
                      {"std", sd}});
  }
  std::printf("\n%s", summary.BriefReport().c_str());
  std::printf("  %d of %zu estimates lie more than 4 std from the truth\n",
              outside, free.size());
  if (!FLAGS_json_out.empty()) {
    nlohmann::json j;
    j["parameters"] = params;
    j["rms_residual_m"] = summary.rms_m;
    j["initial_rms_residual_m"] = summary.initial_rms_m;
    j["sigma_m"] = summary.sigma_m;
    j["iterations"] = summary.iterations;
    j["converged"] = summary.converged;
    j["num_measurements"] = summary.num_measurements;
    j["pose_indices"] = poses;
    j["seed"] = FLAGS_seed;
    j["noise_m"] = FLAGS_noise_m;
    app::WriteJsonOrDie(FLAGS_json_out, j);
  }
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Simulates noisy 3D position measurements of the Sun & Hollerbach PUMA "
      "560 at random lattice poses and identifies its 27 kinematic "
      "parameters from the nominal values (Ceres, Levenberg-Marquardt).\n"
      "Prints per parameter: true, nominal, estimate, error and standard "
      "deviation.\n  activecal_identify --num_poses=30 --seed=1 "
      "--json_out=out.json");
  return activecal::Main();
}
