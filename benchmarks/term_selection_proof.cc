// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The rule that keeps a joint error term only where it predicts better
// (term_selection.h), on simulated UR10s with and without each effect:
// geometric errors only, + joint compliance under gravity, + joint-periodic
// errors, + both. For each scenario and seed: Calibrate (the library's
// workflow: the full parameter set reduced to what the data separate, then
// the terms chosen by 5-fold cross-validation by pose), which families it
// kept, and whether each true term's estimate lies within 3 std of the
// truth. Prints a Markdown table (docs/accuracy.md).
//
//   activecal_term_selection_proof [seeds] [poses] [num_standard_errors]
//                                  [effect_scale]
//
// effect_scale (default 1) multiplies the simulated compliances and
// harmonics: below some scale an effect no longer predicts better than the
// noise, and the rule rightly leaves it out (the detection limit).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "activecal/calibration/calibrate.h"
#include "activecal/core/joint_errors.h"
#include "activecal/core/random.h"
#include "activecal/io/urdf_inertials.h"
#include "activecal/io/urdf_robot.h"

namespace activecal {
namespace {

struct Scenario {
  const char* name;
  bool compliance, periodic;
};

int Run(int num_seeds, int num_poses, double num_se, double scale) {
  const std::string path = std::string(ACTIVECAL_DATA_DIR) + "/ur10.urdf";
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  RobotDescription robot;
  GravityModel gravity;
  std::string error;
  if (!LoadUrdfRobot(path, chain, &robot, &error) ||
      !LoadUrdfInertials(path, chain, &gravity, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  gravity.payload_kg = 2.0;
  gravity.payload_com_m = Eigen::Vector3d(0.0, 0.0, 0.05);
  const RobotModel& model = robot.model;
  const JointErrorModel compliance = ComplianceTerms(model, gravity);
  const JointErrorModel periodic = HarmonicTerms(model, 2);
  const Scenario scenarios[] = {{"geometric only", false, false},
                                {"+ compliance", true, false},
                                {"+ periodic", false, true},
                                {"+ both", true, true}};
  std::printf(
      "| simulated effect | seeds | kept compliance | kept periodic | true "
      "terms within 3 std | held-out RMS geometric / chosen (mm, mean) |\n"
      "|---|---|---|---|---|---|\n");
  int false_terms = 0, missed = 0;
  for (const Scenario& sc : scenarios) {
    int kept_c = 0, kept_p = 0, within = 0, total = 0;
    double rms_geo = 0, rms_chosen = 0;
    for (int seed = 1; seed <= num_seeds; ++seed) {
      Random random(Random::StreamSeed(seed, 10));
      // Geometric errors: 0.3 mm, 0.3 mrad on every link correction, the
      // device's frame anywhere near, a marker 0.1 m off the flange.
      Eigen::VectorXd truth = model.nominal;
      for (int b = 1; b <= model.num_joints(); ++b) {
        for (int j = 0; j < 7; ++j) {
          truth[model.block_offset(b) + j] += 3e-4 * random.Gaussian();
        }
      }
      truth.segment(0, 6) << 1.0, -0.5, 0.2, 0.01, -0.02, 0.3;
      truth.segment(model.block_offset(model.marker_block(0)), 3) =
          Eigen::Vector3d(0.03, -0.02, 0.1);
      // The effects: compliances of 1e-6 .. 1e-5 rad/(N m), harmonics of
      // 20 .. 60 urad.
      JointErrorModel effects;
      if (sc.compliance) {
        JointErrorModel c = compliance;
        c.values << 0, 2e-6, 4e-6, 8e-6, 8e-6, 8e-6;
        for (int t = 0; t < c.size(); ++t) {
          c.values[t] *= scale * (0.75 + 0.5 * random.Uniform());
        }
        effects.Append(c);
      }
      if (sc.periodic) {
        JointErrorModel p = periodic;
        for (int t = 0; t < p.size(); ++t) {
          p.values[t] = scale * (20e-6 + 40e-6 * random.Uniform()) *
                        (random.Uniform() < 0.5 ? -1 : 1);
        }
        effects.Append(p);
      }
      Random joints_random(Random::StreamSeed(seed, 11));
      Eigen::MatrixXd joints(num_poses, model.num_joints());
      for (int i = 0; i < num_poses; ++i) {
        for (int j = 0; j < model.num_joints(); ++j) {
          joints(i, j) = -3.0 + 6.0 * joints_random.Uniform();
        }
      }
      std::vector<Measurement> data;
      if (!SimulateWithJointErrors(
              model, truth, model.nominal, effects, MeasurementPlan(joints),
              {2e-5, 0}, Random::StreamSeed(seed, 12), &data, &error)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
      }
      CalibrationOptions options;
      options.parameter_set = ParameterSet::kFull;
      options.model_selection = ModelSelectionMethod::kNone;
      options.seed = seed;
      options.num_threads = 0;
      options.term_standard_errors = num_se;
      options.term_families = {{"compliance", compliance},
                               {"periodic", periodic}};
      CalibrationSummary summary;
      Calibrate(model, data, options, &summary);
      if (summary.termination_type != TerminationType::kConvergence) {
        std::fprintf(stderr, "%s seed %d: %s\n", sc.name, seed,
                     summary.message.c_str());
        return 1;
      }
      bool has_c = false, has_p = false;
      for (const std::string& k : summary.term_selection.kept) {
        has_c = has_c || k == "compliance";
        has_p = has_p || k == "periodic";
      }
      kept_c += has_c;
      kept_p += has_p;
      false_terms += (has_c && !sc.compliance) + (has_p && !sc.periodic);
      missed += (!has_c && sc.compliance) + (!has_p && sc.periodic);
      const TermSelectionSummary& ts = summary.term_selection;
      rms_geo += ts.candidates[0].held_out_rms_m;
      rms_chosen += ts.candidates[ts.chosen].held_out_rms_m;
      // Each true term (of a kept family) against its estimate.
      const IdentificationSummary& id = summary.identification;
      for (int t = 0; t < id.joint_errors.size(); ++t) {
        const JointTerm& term = id.joint_errors.terms[t];
        for (int u = 0; u < effects.size(); ++u) {
          const JointTerm& e = effects.terms[u];
          if (e.joint == term.joint && e.kind == term.kind &&
              e.harmonic == term.harmonic) {
            ++total;
            within += std::abs(id.joint_errors.values[t] - effects.values[u]) <
                      3 * id.term_standard_deviations[t];
          }
        }
      }
    }
    std::printf("| %s | %d | %d | %d | %d / %d | %.4f / %.4f |\n", sc.name,
                num_seeds, kept_c, kept_p, within, total,
                1e3 * rms_geo / num_seeds, 1e3 * rms_chosen / num_seeds);
    std::fflush(stdout);
  }
  std::printf(
      "\nfalse terms kept: %d; effects missed: %d (%d poses, effects x %g, "
      "rule: gain > %.1f SE)\n",
      false_terms, missed, num_poses, scale, num_se);
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 10;
  const int poses = argc > 2 ? std::atoi(argv[2]) : 200;
  const double se = argc > 3 ? std::atof(argv[3]) : 2.0;
  const double scale = argc > 4 ? std::atof(argv[4]) : 1.0;
  if (seeds < 1 || poses < 10 || !(se > 0) || !(scale >= 0)) {
    std::fprintf(stderr,
                 "usage: activecal_term_selection_proof [seeds >= 1] "
                 "[poses >= 10] [num_standard_errors > 0] [effect_scale >= "
                 "0]\n");
    return 2;
  }
  return activecal::Run(seeds, poses, se, scale);
}
