// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/paper_example.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "activecal/calibration/pool_builder.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/random_designs.h"
#include "printf_text.h"
#include "workflow_fail.h"

namespace activecal {
namespace {

using internal::Printf;

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

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
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

// The initial design (Fig. 3): the first initial_poses of the final
// design's ancestors, recovered from the history.
std::vector<int64_t> InitialDesign(const SelectionSummary& s) {
  std::vector<int64_t> initial = s.design;
  for (auto it = s.history.rbegin(); it != s.history.rend(); ++it) {
    if (it->added >= 0) {
      initial.erase(std::find(initial.begin(), initial.end(), it->added));
    }
    if (it->removed >= 0) initial.push_back(it->removed);
  }
  return initial;
}

nlohmann::json IndicesJson(const ObservabilityIndices& o) {
  return {{"oi", o.oi}, {"log10_oid", o.log10_oid},
          {"o1", o.o1}, {"o2", o.o2},
          {"o3", o.o3}, {"o4", o.o4},
          {"o5", o.o5}, {"rank", o.rank}};
}

using internal::Fail;

}  // namespace

bool MakePaperPool(const RobotModel& model, int num_threads,
                   const ProgressCallback& progress, PaperPool* out,
                   std::string* error) {
  if (!MakeLatticePool(model, nullptr, 5, MeasurementType::kPosition, "--",
                       &out->lattice, &out->notes, error)) {
    return false;
  }
  out->joints = out->lattice.AllJointValues();
  CandidatePoolOptions options;
  options.num_threads = num_threads;
  options.progress = progress;
  CandidatePoolSummary summary;
  if (!BuildCandidatePool(model, model.nominal, out->joints, options,
                          &out->pool, &summary)) {
    *error = summary.message;
    return false;
  }
  out->jacobian_seconds = summary.jacobian_seconds;
  return true;
}

bool ReproducePaperExample(const RobotModel& model,
                           const Eigen::VectorXd& truth,
                           const PaperExampleOptions& options,
                           PaperExampleSummary* summary) {
  *summary = PaperExampleSummary();
  const int64_t start = NowNs();
  if (model.FreeParameterNames() != Puma560PaperModel().FreeParameterNames() ||
      truth.size() != model.num_parameters()) {
    return Fail(
        "--robot: this program reproduces the paper's PUMA 560 and needs its "
        "27 free parameters and true values (as in data/puma560.yaml); for "
        "another robot use activecal_select, activecal_simulate and "
        "activecal_identify",
        summary);
  }
  const int p = model.num_free();
  const int threads = options.num_threads;
  PaperPool paper;
  std::string error;
  bool pool_ok;
  {
    const ProgressCallback progress =
        options.progress ? options.progress("Jacobians of the pool poses")
                         : ProgressCallback();
    pool_ok = MakePaperPool(model, threads, progress, &paper, &error);
  }
  summary->report += paper.notes;
  if (!pool_ok) return Fail(error, summary);
  const JointLattice& lattice = paper.lattice;
  const CandidatePool& pool = paper.pool;
  const Eigen::MatrixXd& pool_joints = paper.joints;
  auto& files = summary->files;

  // V-C: random designs.
  RandomDesignOptions random_options;
  random_options.num_poses = options.num_poses;
  random_options.num_designs = options.random_designs;
  random_options.seed = Random::StreamSeed(options.seed, 1);
  random_options.num_threads = threads;
  SelectionSummary random_summary;
  std::vector<double> random_log_dets;
  if (!SelectRandomDesigns(pool, {}, random_options, &random_summary,
                           &random_log_dets)) {
    return Fail(random_summary.message, summary);
  }
  {
    std::ostringstream csv;
    csv.precision(10);
    csv << "design,log10_det,oi\n";
    for (size_t k = 0; k < random_log_dets.size(); ++k) {
      csv << k << "," << random_log_dets[k] / std::log(10.0) << ","
          << OiFromLogDet(random_log_dets[k], p) << "\n";
    }
    files.push_back({"random_designs.csv", csv.str()});
  }

  // V-D: exchange-add-exchange.
  ExchangeAddExchangeOptions eae_options;
  eae_options.num_poses = options.num_poses;
  eae_options.initial_poses = options.initial_poses;
  eae_options.seed = Random::StreamSeed(options.seed, 2);
  eae_options.num_threads = threads;
  SelectionSummary eae;
  if (!ExchangeAddExchange(pool, {}, eae_options, &eae)) {
    return Fail(eae.message, summary);
  }
  files.push_back({"eae_history.csv", HistoryCsv(eae, p)});
  files.push_back({"eae_poses.csv", PosesCsv(eae.design, lattice)});
  files.push_back(
      {"eae_initial_poses.csv", PosesCsv(InitialDesign(eae), lattice)});
  files.push_back(
      {"random_best_poses.csv", PosesCsv(random_summary.design, lattice)});

  SelectionSummary eig;
  if (options.compare_eigen_oi) {
    ExchangeAddExchangeOptions o = eae_options;
    o.criterion = SelectionCriterion::kEigenvalueOi;
    if (!ExchangeAddExchange(pool, {}, o, &eig)) {
      return Fail(eig.message, summary);
    }
    files.push_back({"eae_eigen_oi_history.csv", HistoryCsv(eig, p)});
  }

  // Beyond the paper: the certificate of each design, and Fedorov exchange.
  SelectionSummary fedorov;
  ApproximateDesignSummary approx;
  const std::pair<const char*, SelectionSummary*> designs[] = {
      {"best random", &random_summary},
      {"exchange-add-exchange", &eae},
      {"Fedorov exchange", &fedorov}};
  if (options.certificate) {
    ApproximateDesignOptions approx_options;
    approx_options.tolerance = 2e-3;
    approx_options.num_threads = threads;
    if (!SolveApproximateDesign(pool, {}, approx_options, &approx) &&
        approx.support.empty()) {
      return Fail("approximate design: " + approx.message, summary);
    }
    FedorovOptions fedorov_options;
    fedorov_options.num_poses = options.num_poses;
    fedorov_options.seed = Random::StreamSeed(options.seed, 4);
    fedorov_options.num_threads = threads;
    if (!FedorovExchange(pool, {}, fedorov_options, &approx, &fedorov)) {
      return Fail(fedorov.message, summary);
    }
    std::ostringstream csv;
    csv.precision(10);
    csv << "design,log10_det,log10_det_upper_bound,efficiency_lower_bound\n";
    for (const auto& [name, s] : designs) {
      CertifyDesign(pool, {}, &approx, threads, s);
    }
    for (const auto& [name, s] : designs) {
      csv << "\"" << name << "\"," << s->log10_det() << ","
          << s->log_det_upper_bound / std::log(10.0) << ","
          << s->efficiency_lower_bound << "\n";
    }
    files.push_back({"certificate.csv", csv.str()});
    files.push_back({"fedorov_poses.csv", PosesCsv(fedorov.design, lattice)});
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
  SimulationNoise noise;
  noise.position_m = options.noise_m;
  if (!SimulateMeasurements(model, truth, MeasurementPlan(joints), noise,
                            Random::StreamSeed(options.seed, 3), &measurements,
                            &error)) {
    return Fail(error, summary);
  }
  IdentificationSummary id;
  Identify(model, measurements, model.nominal, IdentificationOptions(), &id);
  if (id.termination_type != TerminationType::kConvergence) {
    return Fail("identification failed: " + id.message, summary);
  }
  const double total_seconds = (NowNs() - start) * 1e-9;

  // Report.
  std::string& r = summary->report;
  const double ratio_log10 = eae.log10_det() - random_summary.log10_det();
  r += Printf("Sun & Hollerbach, Section V, reproduced (seed %llu)\n\n",
              static_cast<unsigned long long>(options.seed));
  r += Printf("%-44s %14s %14s\n", "", "paper", "activecal");
  r += Printf("%-44s %14s %14lld\n", "candidate pool (5 levels per joint)",
              "15625", static_cast<long long>(pool.size()));
  r += Printf("%-44s %14.6f %14.6f\n", "best of 5000 random designs: OI",
              kPaperRandomOi, random_idx.oi);
  r += Printf("%-44s %14.4e %14.4e\n", "best of 5000 random designs: OID",
              kPaperRandomOid, std::pow(10.0, random_idx.log10_oid));
  r += Printf("%-44s %14.4e %14.4e\n", "exchange-add-exchange: OID",
              kPaperEaeOid, std::pow(10.0, eae_idx.log10_oid));
  r += Printf("%-44s %14.5f %14.5f\n", "exchange-add-exchange: OI", kPaperEaeOi,
              eae_idx.oi);
  r += Printf("%-44s %14.0f %14.0f\n", "OID ratio, active / random",
              kPaperEaeOid / kPaperRandomOid, std::pow(10.0, ratio_log10));
  std::vector<double> ois;
  for (double v : random_log_dets) ois.push_back(OiFromLogDet(v, p));
  r += Printf(
      "\nRandom designs' OI: min %.4f, median %.4f, 99th pct %.4f, "
      "max %.4f\n",
      Quantile(ois, 0), Quantile(ois, 0.5), Quantile(ois, 0.99),
      Quantile(ois, 1));
  r += Printf("Exchange-add-exchange: %zu steps (%s)\n", eae.history.size(),
              eae.message.c_str());
  if (options.compare_eigen_oi) {
    r += Printf(
        "Same run with the eigenvalue OI: OI %.5f, %s poses, "
        "%.2f s against %.3f s for the determinant update (x%.0f)\n",
        OiFromLogDet(eig.log_det, p),
        eig.design == eae.design ? "the same" : "DIFFERENT", eig.seconds,
        eae.seconds, eig.seconds / eae.seconds);
  }
  if (options.certificate) {
    r += Printf(
        "\nBeyond the paper: certified D-efficiency against the best "
        "possible %d-pose design (log10 det <= %.4f)\n",
        options.num_poses, eae.log_det_upper_bound / std::log(10.0));
    for (const auto& [name, s] : designs) {
      r += Printf("%-24s log10 det %8.4f   efficiency >= %.4f\n", name,
                  s->log10_det(), s->efficiency_lower_bound);
    }
  }
  r += "\nObservability indices (unscaled columns)\n";
  r += Printf("%-10s %12s %12s %12s %12s %12s\n", "design", "O1", "O2", "O3",
              "O4", "O5");
  for (auto [name, o] : {std::pair<const char*, const ObservabilityIndices*>{
                             "random", &random_idx},
                         {"eae", &eae_idx}}) {
    r += Printf("%-10s %12.4e %12.4e %12.4e %12.4e %12.4e\n", name, o->o1,
                o->o2, o->o3, o->o4, o->o5);
  }

  r += Printf(
      "\nIdentification at the selected poses, %.3g m noise "
      "(Tables III and IV)\n",
      options.noise_m);
  r += Printf("%-9s %11s | %11s %11s | %10s %10s %10s\n", "parameter", "true",
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
    r += Printf("%-9s %11.6f | %11.6f %11.6f | %10.6f %10.6f %10.6f\n",
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
  files.push_back({"identification.csv", csv.str()});
  r += Printf(
      "%d of %d errors within 2 std; RMS residual %.4f m -> %.4f m; "
      "sigma %.4f m\n",
      within2, p, id.initial_rms_m, id.rms_m, id.sigma_m);
  r += Printf(
      "\nJacobians %.3f s, random designs %.3f s, "
      "exchange-add-exchange %.3f s, total %.2f s\n",
      paper.jacobian_seconds, random_summary.seconds, eae.seconds,
      total_seconds);
  r += "Files for the figures are in " + options.out_dir + "/\n";

  nlohmann::json& j = summary->json;
  j["seed"] = options.seed;
  j["pool_size"] = pool.size();
  j["random"] = SelectionJson(random_summary, pool_joints, {});
  j["random"]["indices"] = IndicesJson(random_idx);
  j["eae"] = SelectionJson(eae, pool_joints, {});
  j["eae"]["indices"] = IndicesJson(eae_idx);
  if (options.compare_eigen_oi) {
    j["eae_eigen_oi"] = SelectionJson(eig, pool_joints, {});
    j["eae_eigen_oi"]["same_poses"] = eig.design == eae.design;
  }
  if (options.certificate) {
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
  j["timing"] = {{"jacobian_seconds", paper.jacobian_seconds},
                 {"random_seconds", random_summary.seconds},
                 {"eae_seconds", eae.seconds},
                 {"total_seconds", total_seconds}};

  // The run in one line (a line of at most 319 bytes, as the program's).
  char result[320];
  std::snprintf(result, sizeof(result),
                "%s: exchange-add-exchange OI %.5f (paper %.5f), OID ratio to "
                "the best random design %.0f (paper %.0f); %d of %d "
                "identified errors within 2 std; files in %s/",
                options.program_name.c_str(), eae_idx.oi, kPaperEaeOi,
                std::pow(10.0, ratio_log10), kPaperEaeOid / kPaperRandomOid,
                within2, p, options.out_dir.c_str());
  summary->result_line = result;
  summary->eae_oi = eae_idx.oi;
  summary->random_oi = random_idx.oi;
  summary->oid_ratio_log10 = ratio_log10;
  summary->num_within_2_std = within2;
  summary->num_parameters = p;
  summary->total_seconds = total_seconds;
  summary->termination_type = TerminationType::kConvergence;
  return true;
}

}  // namespace activecal
