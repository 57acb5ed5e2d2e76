// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// activecal_puma_paper: Sun & Hollerbach, "Active Robot Calibration
// Algorithm", Section V, end to end, printed beside the paper's figures.
//
//   1. Jacobians of the 5^6 = 15,625 lattice poses at the nominal values.
//   2. Best of 5,000 random 30-pose designs (Section V-C, Fig. 2).
//   3. Exchange-add-exchange from 12 random poses to 30 (V-D, Figs. 3, 4, 6),
//      optionally again with the eigenvalue OI (Fig. 5).
//   4. Identification from simulated 1 cm measurements at the selected poses
//      (V-E, Tables III and IV).
//
// Writes CSV and JSON files from which the paper's figures can be drawn.

#include <gflags/gflags.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "activecal/calibration/select_workflow.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/random_designs.h"
#include "app_common.h"

DEFINE_uint64(seed, 1,
              "Seed of the random designs, the initial design and "
              "the measurement noise.");
DEFINE_string(out_dir, "paper_out", "Folder for the CSV and JSON files.");
DEFINE_int32(random_designs, 5000, "Random designs drawn (paper: 5,000).");
DEFINE_int32(num_poses, 30, "Poses per design (paper: 30).");
DEFINE_int32(initial_poses, 12, "Random initial poses (paper: 12).");
DEFINE_double(noise_m, 0.01, "Measurement noise per axis, m (paper: 1 cm).");
DEFINE_bool(compare_eigen_oi, false,
            "Also run exchange-add-exchange with the eigenvalue OI (SVD of "
            "each candidate design; tens of seconds) and compare.");
DEFINE_bool(certificate, true,
            "Beyond the paper: solve the approximate design, run Fedorov "
            "exchange, and certify how close the random, exchange-add-"
            "exchange and Fedorov designs are to the best possible "
            "(certificate.csv; about 3 s).");
DEFINE_int32(threads, 0, "Threads (0: all). Results do not depend on it.");

namespace activecal {
namespace {

// The paper's published figures (Section V and Tables III, IV), in the
// free-parameter order of Puma560PaperModel().
constexpr double kPaperRandomOi = 0.096284;
constexpr double kPaperRandomOid = 2.5414e22;
constexpr double kPaperEaeOid = 1.4818e27;
constexpr double kPaperEaeOi = 0.11798;
constexpr double kPaperTableIII[27] = {
    1.570881,  0.031672,  20.001537, 0.030290,  0.003324,  -1.568910, 0.004117,
    0.685666,  0.011386,  0.030969,  0.431692,  0.027905,  0.003694,  1.566960,
    -0.028746, 0.149672,  -0.000672, -1.581108, -0.002910, 0.433253,  0.006226,
    1.577711,  -0.001479, 0.000302,  -0.017604, 0.199881,  0.165315};
constexpr double kPaperTableIV[27] = {
    0.000084,  0.000256, 0.001537, 0.001126,  0.003324,  0.001886, 0.004117,
    0.000134,  0.011386, 0.000447, -0.000108, 0.003511,  0.003694, 0.003836,
    -0.008446, 0.000572, 0.000672, 0.010311,  -0.002910, 0.000153, 0.006226,
    0.006914,  0.001479, 0.000302, 0.017604,  0.000119,  0.000185};

std::string Path(const std::string& name) {
  return (std::filesystem::path(FLAGS_out_dir) / name).string();
}

double Quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * (v.size() - 1))];
}

std::string HistoryCsv(const SelectionSummary& s, int p) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "step,kind,added,removed,num_poses,log10_det,oi,"
         "log10_det_covariance\n";
  int n = 0;
  for (size_t k = 0; k < s.history.size(); ++k) {
    const SelectionStep& h = s.history[k];
    if (k == 0) {
      n = static_cast<int>(s.design.size());
      for (size_t j = 1; j < s.history.size(); ++j) {
        if (s.history[j].kind == SelectionStep::kAdd) --n;
      }
    } else if (h.kind == SelectionStep::kAdd) {
      ++n;
    }
    const double l10 = h.log_det / std::log(10.0);
    csv << k << "," << h.name() << "," << h.added << "," << h.removed << ","
        << n << "," << l10 << "," << OiFromLogDet(h.log_det, p) << "," << -l10
        << "\n";
  }
  return csv.str();
}

std::string PosesCsv(const std::vector<int64_t>& design,
                     const JointLattice& lattice) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "order,pose_index";
  for (int j = 1; j <= lattice.num_joints(); ++j) csv << ",level" << j;
  for (int j = 1; j <= lattice.num_joints(); ++j) csv << ",q" << j << "_rad";
  csv << "\n";
  for (size_t k = 0; k < design.size(); ++k) {
    csv << k << "," << design[k];
    for (int l : lattice.Levels(design[k])) csv << "," << l;
    const Eigen::VectorXd q = lattice.JointValues(design[k]);
    for (int j = 0; j < q.size(); ++j) csv << "," << q[j];
    csv << "\n";
  }
  return csv.str();
}

nlohmann::json IndicesJson(const ObservabilityIndices& o) {
  return {{"oi", o.oi}, {"log10_oid", o.log10_oid},
          {"o1", o.o1}, {"o2", o.o2},
          {"o3", o.o3}, {"o4", o.o4},
          {"o5", o.o5}, {"rank", o.rank}};
}

int Main() {
  const int64_t start = app::NowNs();
  std::error_code ec;
  std::filesystem::create_directories(FLAGS_out_dir, ec);
  if (ec)
    app::Fail("cannot create --out_dir '" + FLAGS_out_dir +
              "': " + ec.message());
  const RobotDescription robot = app::LoadRobotOrDie();
  const RobotModel& model = robot.model;
  const Eigen::VectorXd& truth = robot.true_parameters;
  if (model.FreeParameterNames() != Puma560PaperModel().FreeParameterNames() ||
      truth.size() != model.num_parameters()) {
    app::Fail(
        "--robot: this program reproduces the paper's PUMA 560 and needs its "
        "27 free parameters and true values (as in data/puma560.yaml); for "
        "another robot use activecal_select, activecal_simulate and "
        "activecal_identify");
  }
  const int p = model.num_free();
  const JointLattice lattice = app::MakeLatticeOrDie(model, 5);
  const Eigen::MatrixXd pool_joints = lattice.AllJointValues();
  double jacobian_seconds = 0;
  CandidatePoolOptions pool_options;
  pool_options.num_threads = FLAGS_threads;
  const CandidatePool pool = app::BuildPoolOrDie(
      model, pool_joints, pool_options, "the pool", &jacobian_seconds, nullptr);

  // V-C: random designs.
  RandomDesignOptions random_options;
  random_options.num_poses = FLAGS_num_poses;
  random_options.num_designs = FLAGS_random_designs;
  random_options.seed = Random::StreamSeed(FLAGS_seed, 1);
  random_options.num_threads = FLAGS_threads;
  SelectionSummary random_summary;
  std::vector<double> random_log_dets;
  if (!SelectRandomDesigns(pool, {}, random_options, &random_summary,
                           &random_log_dets)) {
    app::Fail(random_summary.message);
  }
  {
    std::ostringstream csv;
    csv.precision(10);
    csv << "design,log10_det,oi\n";
    for (size_t k = 0; k < random_log_dets.size(); ++k) {
      csv << k << "," << random_log_dets[k] / std::log(10.0) << ","
          << OiFromLogDet(random_log_dets[k], p) << "\n";
    }
    app::WriteTextOrDie(Path("random_designs.csv"), csv.str());
  }

  // V-D: exchange-add-exchange.
  ExchangeAddExchangeOptions eae_options;
  eae_options.num_poses = FLAGS_num_poses;
  eae_options.initial_poses = FLAGS_initial_poses;
  eae_options.seed = Random::StreamSeed(FLAGS_seed, 2);
  eae_options.num_threads = FLAGS_threads;
  SelectionSummary eae;
  if (!ExchangeAddExchange(pool, {}, eae_options, &eae)) {
    app::Fail(eae.message);
  }
  app::WriteTextOrDie(Path("eae_history.csv"), HistoryCsv(eae, p));
  app::WriteTextOrDie(Path("eae_poses.csv"), PosesCsv(eae.design, lattice));
  {
    // The initial design (Fig. 3) is the first initial_poses of the final
    // design's ancestors: recover it from the history.
    std::vector<int64_t> initial = eae.design;
    for (auto it = eae.history.rbegin(); it != eae.history.rend(); ++it) {
      if (it->added >= 0) {
        initial.erase(std::find(initial.begin(), initial.end(), it->added));
      }
      if (it->removed >= 0) initial.push_back(it->removed);
    }
    app::WriteTextOrDie(Path("eae_initial_poses.csv"),
                        PosesCsv(initial, lattice));
  }
  app::WriteTextOrDie(Path("random_best_poses.csv"),
                      PosesCsv(random_summary.design, lattice));

  SelectionSummary eig;
  if (FLAGS_compare_eigen_oi) {
    ExchangeAddExchangeOptions o = eae_options;
    o.criterion = SelectionCriterion::kEigenvalueOi;
    if (!ExchangeAddExchange(pool, {}, o, &eig)) app::Fail(eig.message);
    app::WriteTextOrDie(Path("eae_eigen_oi_history.csv"), HistoryCsv(eig, p));
  }

  // Beyond the paper: the certificate of each design, and Fedorov exchange.
  SelectionSummary fedorov;
  ApproximateDesignSummary approx;
  if (FLAGS_certificate) {
    ApproximateDesignOptions approx_options;
    approx_options.tolerance = 2e-3;
    approx_options.num_threads = FLAGS_threads;
    if (!SolveApproximateDesign(pool, {}, approx_options, &approx) &&
        approx.support.empty()) {
      app::Fail("approximate design: " + approx.message);
    }
    FedorovOptions fedorov_options;
    fedorov_options.num_poses = FLAGS_num_poses;
    fedorov_options.seed = Random::StreamSeed(FLAGS_seed, 4);
    fedorov_options.num_threads = FLAGS_threads;
    if (!FedorovExchange(pool, {}, fedorov_options, &approx, &fedorov)) {
      app::Fail(fedorov.message);
    }
    std::ostringstream csv;
    csv.precision(10);
    csv << "design,log10_det,log10_det_upper_bound,efficiency_lower_bound\n";
    for (SelectionSummary* s : {&random_summary, &eae, &fedorov}) {
      CertifyDesign(pool, {}, &approx, FLAGS_threads, s);
    }
    const std::pair<const char*, const SelectionSummary*> rows[] = {
        {"best random", &random_summary},
        {"exchange-add-exchange", &eae},
        {"Fedorov exchange", &fedorov}};
    for (const auto& [name, s] : rows) {
      csv << "\"" << name << "\"," << s->log10_det() << ","
          << s->log_det_upper_bound / std::log(10.0) << ","
          << s->efficiency_lower_bound << "\n";
    }
    app::WriteTextOrDie(Path("certificate.csv"), csv.str());
    app::WriteTextOrDie(Path("fedorov_poses.csv"),
                        PosesCsv(fedorov.design, lattice));
  }

  const ObservabilityIndices random_idx =
      ComputeObservabilityIndices(pool.Stack(random_summary.design));
  const ObservabilityIndices eae_idx =
      ComputeObservabilityIndices(pool.Stack(eae.design));

  // V-E: identification at the selected poses.
  Eigen::MatrixXd joints(eae.design.size(), model.num_joints());
  for (size_t i = 0; i < eae.design.size(); ++i) {
    joints.row(i) = lattice.JointValues(eae.design[i]).transpose();
  }
  std::vector<Measurement> measurements;
  std::string error;
  SimulationNoise noise;
  noise.position_m = FLAGS_noise_m;
  if (!SimulateMeasurements(model, truth, MeasurementPlan(joints), noise,
                            Random::StreamSeed(FLAGS_seed, 3), &measurements,
                            &error)) {
    app::Fail(error);
  }
  IdentificationSummary id;
  Identify(model, measurements, model.nominal, IdentificationOptions(), &id);
  if (id.termination_type != TerminationType::kConvergence) {
    app::Fail("identification failed: " + id.message);
  }
  const double total_seconds = app::Seconds(start);

  // Report.
  const double ratio_log10 = eae.log10_det() - random_summary.log10_det();
  std::printf("Sun & Hollerbach, Section V, reproduced (seed %llu)\n\n",
              static_cast<unsigned long long>(FLAGS_seed));
  std::printf("%-44s %14s %14s\n", "", "paper", "activecal");
  std::printf("%-44s %14s %14lld\n", "candidate pool (5 levels per joint)",
              "15625", static_cast<long long>(pool.size()));
  std::printf("%-44s %14.6f %14.6f\n", "best of 5000 random designs: OI",
              kPaperRandomOi, random_idx.oi);
  std::printf("%-44s %14.4e %14.4e\n", "best of 5000 random designs: OID",
              kPaperRandomOid, std::pow(10.0, random_idx.log10_oid));
  std::printf("%-44s %14.4e %14.4e\n", "exchange-add-exchange: OID",
              kPaperEaeOid, std::pow(10.0, eae_idx.log10_oid));
  std::printf("%-44s %14.5f %14.5f\n", "exchange-add-exchange: OI", kPaperEaeOi,
              eae_idx.oi);
  std::printf("%-44s %14.0f %14.0f\n", "OID ratio, active / random",
              kPaperEaeOid / kPaperRandomOid, std::pow(10.0, ratio_log10));
  std::vector<double> ois;
  for (double v : random_log_dets) ois.push_back(OiFromLogDet(v, p));
  std::printf(
      "\nRandom designs' OI: min %.4f, median %.4f, 99th pct %.4f, "
      "max %.4f\n",
      Quantile(ois, 0), Quantile(ois, 0.5), Quantile(ois, 0.99),
      Quantile(ois, 1));
  std::printf("Exchange-add-exchange: %zu steps (%s)\n", eae.history.size(),
              eae.message.c_str());
  if (FLAGS_compare_eigen_oi) {
    std::printf(
        "Same run with the eigenvalue OI: OI %.5f, %s poses, "
        "%.2f s against %.3f s for the determinant update (x%.0f)\n",
        OiFromLogDet(eig.log_det, p),
        eig.design == eae.design ? "the same" : "DIFFERENT", eig.seconds,
        eae.seconds, eig.seconds / eae.seconds);
  }
  if (FLAGS_certificate) {
    std::printf(
        "\nBeyond the paper: certified D-efficiency against the best "
        "possible %d-pose design (log10 det <= %.4f)\n",
        FLAGS_num_poses, eae.log_det_upper_bound / std::log(10.0));
    for (auto [name, s] : {std::pair<const char*, const SelectionSummary*>{
                               "best random", &random_summary},
                           {"exchange-add-exchange", &eae},
                           {"Fedorov exchange", &fedorov}}) {
      std::printf("%-24s log10 det %8.4f   efficiency >= %.4f\n", name,
                  s->log10_det(), s->efficiency_lower_bound);
    }
  }
  std::printf("\nObservability indices (unscaled columns)\n");
  std::printf("%-10s %12s %12s %12s %12s %12s\n", "design", "O1", "O2", "O3",
              "O4", "O5");
  for (auto [name, o] : {std::pair<const char*, const ObservabilityIndices*>{
                             "random", &random_idx},
                         {"eae", &eae_idx}}) {
    std::printf("%-10s %12.4e %12.4e %12.4e %12.4e %12.4e\n", name, o->o1,
                o->o2, o->o3, o->o4, o->o5);
  }

  std::printf(
      "\nIdentification at the selected poses, %.3g m noise "
      "(Tables III and IV)\n",
      FLAGS_noise_m);
  std::printf("%-9s %11s | %11s %11s | %10s %10s %10s\n", "parameter", "true",
              "paper est.", "our est.", "paper err", "our err", "our std");
  const std::vector<int> free = model.FreeParameterIndices();
  nlohmann::json params = nlohmann::json::array();
  std::ostringstream csv;
  csv.precision(10);
  csv << "name,unit,true,nominal,estimate,error,std,paper_estimate,"
         "paper_error\n";
  int within2 = 0;
  for (int k = 0; k < p; ++k) {
    const double t = truth[free[k]];
    const double err = id.estimates[k] - t;
    const double sd = id.standard_deviations[k];
    if (std::abs(err) <= 2 * sd) ++within2;
    std::printf("%-9s %11.6f | %11.6f %11.6f | %10.6f %10.6f %10.6f\n",
                id.names[k].c_str(), t, kPaperTableIII[k], id.estimates[k],
                kPaperTableIV[k], err, sd);
    csv << id.names[k] << "," << model.ParameterUnit(free[k]) << "," << t << ","
        << model.nominal[free[k]] << "," << id.estimates[k] << "," << err << ","
        << sd << "," << kPaperTableIII[k] << "," << kPaperTableIV[k] << "\n";
    params.push_back({{"name", id.names[k]},
                      {"true", t},
                      {"nominal", model.nominal[free[k]]},
                      {"estimate", id.estimates[k]},
                      {"std", sd},
                      {"paper_estimate", kPaperTableIII[k]},
                      {"paper_error", kPaperTableIV[k]}});
  }
  app::WriteTextOrDie(Path("identification.csv"), csv.str());
  std::printf(
      "%d of %d errors within 2 std; RMS residual %.4f m -> %.4f m; "
      "sigma %.4f m\n",
      within2, p, id.initial_rms_m, id.rms_m, id.sigma_m);
  std::printf(
      "\nJacobians %.3f s, random designs %.3f s, "
      "exchange-add-exchange %.3f s, total %.2f s\n",
      jacobian_seconds, random_summary.seconds, eae.seconds, total_seconds);
  std::printf("Files for the figures are in %s/\n", FLAGS_out_dir.c_str());

  nlohmann::json j;
  j["seed"] = FLAGS_seed;
  j["pool_size"] = pool.size();
  j["random"] = SelectionJson(random_summary, pool_joints, {});
  j["random"]["indices"] = IndicesJson(random_idx);
  j["eae"] = SelectionJson(eae, pool_joints, {});
  j["eae"]["indices"] = IndicesJson(eae_idx);
  if (FLAGS_compare_eigen_oi) {
    j["eae_eigen_oi"] = SelectionJson(eig, pool_joints, {});
    j["eae_eigen_oi"]["same_poses"] = eig.design == eae.design;
  }
  if (FLAGS_certificate) {
    j["fedorov"] = SelectionJson(fedorov, pool_joints, {});
    for (auto [key, sm] : {std::pair<const char*, const SelectionSummary*>{
                               "random", &random_summary},
                           {"eae", &eae},
                           {"fedorov", &fedorov}}) {
      j[key]["efficiency_lower_bound"] = sm->efficiency_lower_bound;
      j[key]["log10_det_upper_bound"] =
          sm->log_det_upper_bound / std::log(10.0);
    }
  }
  j["paper"] = {{"random_oi", kPaperRandomOi},
                {"random_oid", kPaperRandomOid},
                {"eae_oid", kPaperEaeOid},
                {"eae_oi", kPaperEaeOi}};
  j["identification"] = {
      {"parameters", params},
      {"rms_residual_m", id.rms_m},
      {"initial_rms_residual_m", id.initial_rms_m},
      {"sigma_m", id.sigma_m},
      {"iterations", id.iterations},
      {"converged", id.termination_type == TerminationType::kConvergence}};
  // Wall-clock times: the only fields that vary between runs.
  j["timing"] = {{"jacobian_seconds", jacobian_seconds},
                 {"random_seconds", random_summary.seconds},
                 {"eae_seconds", eae.seconds},
                 {"total_seconds", total_seconds}};
  app::WriteJsonOrDie(Path("paper_run.json"), j);
  app::CommitOutputsOrDie();
  // The run in one line: the last of stdout, and all that --quiet prints.
  char result[320];
  std::snprintf(result, sizeof(result),
                "%s: exchange-add-exchange OI %.5f (paper %.5f), OID ratio to "
                "the best random design %.0f (paper %.0f); %d of %d "
                "identified errors within 2 std; files in %s/",
                app::ProgramName().c_str(), eae_idx.oi, kPaperEaeOi,
                std::pow(10.0, ratio_log10), kPaperEaeOid / kPaperRandomOid,
                within2, p, FLAGS_out_dir.c_str());
  app::PrintResult(result);
  return 0;
}

}  // namespace
}  // namespace activecal

int main(int argc, char** argv) {
  activecal::app::Init(
      &argc, &argv,
      "Reproduces Section V of Sun & Hollerbach, 'Active Robot Calibration "
      "Algorithm', end to end on the PUMA 560 and prints the results beside "
      "the paper's figures. Writes CSV/JSON for Figs. 2-6 to --out_dir.\n"
      "  activecal_puma_paper --seed=1");
  return activecal::app::Finish(activecal::Main());
}
