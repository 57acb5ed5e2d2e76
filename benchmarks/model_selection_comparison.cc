// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Which way of choosing the parameters predicts new poses best: keeping
// every identifiable parameter, model selection by cross-validation or by a
// validation session, or a MAP fit with priors. Prints a table of test RMS
// errors (mean over seeds) for simulated robots whose truth holds errors
// the kinematic model cannot express (joint gains, which the 'full' set
// leaves fixed) plus noise, and for FIGAROH's UR10e data split by poses.
//
//   build/benchmarks/activecal_model_selection_comparison [seeds]
//
// docs/accuracy.md holds its output.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "activecal/core/parameter_sets.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/estimation/model_selection.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/estimation/registration.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/residuals/jacobians.h"

namespace activecal {
namespace {

struct Data {
  std::vector<Measurement> training, validation, test;
};

struct Method {
  std::string name;
  ModelSelectionMethod selection = ModelSelectionMethod::kNone;
  double prior_m = 0, prior_rad = 0;
  ParameterRanking ranking = ParameterRanking::kSignificance;
  SelectionRule rule = SelectionRule::kMinimum;
};

constexpr auto kCv = ModelSelectionMethod::kCrossValidation;
constexpr auto kVal = ModelSelectionMethod::kValidation;
constexpr auto kSig = ParameterRanking::kSignificance;
const std::vector<Method> kMethods = {
    {"all identifiable", ModelSelectionMethod::kNone, 0, 0},
    {"cv, min", kCv, 0, 0},
    {"cv, 1se", kCv, 0, 0, kSig, SelectionRule::kFewestWithinOneSe},
    {"cv, 1se_most", kCv, 0, 0, kSig, SelectionRule::kMostWithinOneSe},
    {"F test 1 %", kCv, 0, 0, kSig, SelectionRule::kFTest},
    {"validation, min", kVal, 0, 0},
    {"validation, 1se_most", kVal, 0, 0, kSig, SelectionRule::kMostWithinOneSe},
    {"cv, Jacobian, min", kCv, 0, 0, ParameterRanking::kJacobian},
    {"MAP 0.5 mm/0.5 mrad", ModelSelectionMethod::kNone, 5e-4, 5e-4},
    {"MAP 2 mm/2 mrad", ModelSelectionMethod::kNone, 2e-3, 2e-3},
    {"MAP 10 mm/10 mrad", ModelSelectionMethod::kNone, 1e-2, 1e-2},
};

// Test RMS (m) of one method, or NaN if it failed.
double Run(const RobotModel& robot, const Data& data, const Method& method,
           double rotation_weight, int* kept) {
  RobotModel model = robot;
  Eigen::VectorXd start = model.nominal;
  if (model.base.convention == LinkConvention::kFrame) {
    RegistrationSummary reg;
    if (!RegisterBaseFrame(model, data.training, &start, &reg)) return NAN;
  }
  std::vector<HeldParameter> dropped;
  FreeSet free;
  std::string error;
  if (!ReduceParameterSet(model, ParameterSet::kFull, data.training,
                          rotation_weight, &start, &free, &dropped, &error)) {
    return NAN;
  }
  model = WithFreeSet(model, free);
  IdentificationOptions options;
  options.rotation_weight_m_per_rad = rotation_weight;
  ModelSelectionOptions selection;
  selection.method = method.selection;
  selection.ranking = method.ranking;
  selection.rule = method.rule;
  selection.identification = options;
  selection.num_threads = 2;
  ModelSelectionSummary summary;
  SelectModel(model, start, data.training, data.validation, selection,
              &summary);
  if (summary.termination_type != TerminationType::kConvergence) return NAN;
  model = WithFreeSet(model, summary.free);
  if (method.prior_m > 0) {
    IdentificationSummary plain;
    Identify(model, data.training, start, options, &plain);
    if (plain.termination_type != TerminationType::kConvergence) return NAN;
    options.prior_std_m = method.prior_m;
    options.prior_std_rad = method.prior_rad;
    options.prior_reference_sigma_m = plain.sigma_m;
  }
  IdentificationSummary fit;
  Identify(model, data.training, start, options, &fit);
  if (fit.termination_type != TerminationType::kConvergence) return NAN;
  *kept = model.num_free();
  Eigen::VectorXd norms;
  if (!MeasurementErrors(model, fit.parameters, data.test, rotation_weight,
                         &norms, &error)) {
    return NAN;
  }
  return std::sqrt(norms.squaredNorm() / norms.size());
}

std::vector<Measurement> Plan(const RobotModel& m, int n, MeasurementType type,
                              Random* random) {
  Eigen::MatrixXd joints(n, m.num_joints());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m.num_joints(); ++j) {
      const Link& l = m.links[j];
      const double lo = std::max(l.joint_min, -2.8);
      const double hi = std::min(l.joint_max, 2.8);
      joints(i, j) = lo + (hi - lo) * random->Uniform();
    }
  }
  return MeasurementPlan(joints, type);
}

// Truth: nominal + a device frame + geometric errors (1 mm, 1 mrad) on
// every link parameter + joint gain errors (5e-4, not in the model).
Data Simulate(const RobotModel& m, uint64_t seed, MeasurementType type,
              int num_training) {
  Random random(seed);
  Eigen::VectorXd truth = m.nominal;
  if (m.base.convention == LinkConvention::kFrame) {
    truth.head(6) << 1.0, -0.5, 0.2, 0.1, -0.2, 1.5;
  }
  for (int b = 1; b <= m.num_joints(); ++b) {
    for (int j = 0; j < m.block_size(b); ++j) {
      const int i = m.block_offset(b) + j;
      switch (m.Kind(i)) {
        case ParameterKind::kLength:
          truth[i] += 1e-3 * random.Gaussian();
          break;
        case ParameterKind::kAngle:
          truth[i] += 1e-3 * random.Gaussian();
          break;
        case ParameterKind::kGain:
          truth[i] += 5e-4 * random.Gaussian();
          break;
      }
    }
  }
  SimulationNoise noise{5e-4, 5e-4};
  Data d;
  std::string error;
  auto sim = [&](int n, uint64_t s, std::vector<Measurement>* out) {
    if (!SimulateMeasurements(m, truth, Plan(m, n, type, &random), noise, s,
                              out, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      std::exit(1);
    }
  };
  sim(num_training, seed + 1, &d.training);
  sim(num_training, seed + 2, &d.validation);
  sim(300, seed + 3, &d.test);
  return d;
}

void Table(const char* title, const RobotModel& m,
           const std::vector<Data>& sets, double rotation_weight) {
  std::printf("\n%s (%zu data sets)\n", title, sets.size());
  std::printf("  %-22s %14s %10s %8s\n", "method", "test RMS (mm)", "params",
              "failed");
  for (const Method& method : kMethods) {
    double sum = 0, params = 0;
    int ok = 0;
    for (const Data& d : sets) {
      int kept = 0;
      const double rms = Run(m, d, method, rotation_weight, &kept);
      if (std::isnan(rms)) continue;
      sum += rms;
      params += kept;
      ++ok;
    }
    std::printf("  %-22s %14.4f %10.1f %8d\n", method.name.c_str(),
                ok ? 1e3 * sum / ok : NAN, ok ? params / ok : NAN,
                static_cast<int>(sets.size()) - ok);
  }
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  using namespace activecal;
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 5;
  const std::string data_dir = ACTIVECAL_DATA_DIR;
  RobotDescription ur, iiwa;
  std::string error;
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  UrdfChainOptions iiwa_chain;
  iiwa_chain.tip_link = "flange";
  if (!LoadUrdfRobot(data_dir + "/ur10e.urdf", chain, &ur, &error) ||
      !LoadUrdfRobot(data_dir + "/kuka_iiwa14.urdf", iiwa_chain, &iiwa,
                     &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  // A tracker reflector 0.1 m off the flange.
  iiwa.model.nominal[iiwa.model.ParameterIndex("tool.x")] = 0.03;
  iiwa.model.nominal[iiwa.model.ParameterIndex("tool.y")] = -0.02;
  iiwa.model.nominal[iiwa.model.ParameterIndex("tool.z")] = 0.1;
  const RobotModel puma = Puma560PaperModel();
  for (int n : {20, 40}) {
    std::vector<Data> puma_sets, ur_sets, iiwa_sets;
    for (int s = 0; s < seeds; ++s) {
      puma_sets.push_back(
          Simulate(puma, 1000 + s, MeasurementType::kPosition, n));
      ur_sets.push_back(
          Simulate(ur.model, 2000 + s, MeasurementType::kPose, n));
      iiwa_sets.push_back(
          Simulate(iiwa.model, 4000 + s, MeasurementType::kPosition, n));
    }
    const std::string tail = ", " + std::to_string(n) + " training + " +
                             std::to_string(n) + " validation poses";
    Table(("PUMA 560, position" + tail).c_str(), puma, puma_sets, 1.0);
    Table(("UR10e, 6D pose (w = 0.5 m/rad)" + tail).c_str(), ur.model, ur_sets,
          0.5);
    Table(("iiwa 14, position" + tail).c_str(), iiwa.model, iiwa_sets, 1.0);
  }
  // FIGAROH's UR10e: 23 poses; train on 15, validate on 4, test on 4,
  // over several seeded splits.
  std::vector<Measurement> all;
  if (!ReadMeasurementsCsv(data_dir + "/figaroh_ur10e/measurements.csv",
                           ur.model, &all, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  std::vector<Data> figaroh;
  for (int s = 0; s < 2 * std::max(seeds, 5); ++s) {
    Random random(3000 + s);
    const std::vector<int64_t> order =
        random.SampleWithoutReplacement(all.size(), all.size());
    Data d;
    for (size_t k = 0; k < order.size(); ++k) {
      (k < 15   ? d.training
       : k < 19 ? d.validation
                : d.test)
          .push_back(all[order[k]]);
    }
    figaroh.push_back(d);
  }
  Table(
      "FIGAROH UR10e (real, 6D, w = 0.1 m/rad), 15 training / 4 "
      "validation / 4 test poses",
      ur.model, figaroh, 0.1);
  return 0;
}
