// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// ReproducePaperExample: Sun & Hollerbach, "Active Robot Calibration
// Algorithm", Section V, end to end on the PUMA 560, with the paper's
// figures beside ours (what activecal_puma_paper runs and prints):
//
//   1. Jacobians of the 5^6 = 15,625 lattice poses at the nominal values.
//   2. Best of random_designs random designs (Section V-C, Fig. 2).
//   3. Exchange-add-exchange from initial_poses random poses to num_poses
//      (V-D, Figs. 3, 4, 6), optionally again with the eigenvalue OI
//      (Fig. 5).
//   4. Beyond the paper (certificate): the approximate design, Fedorov
//      exchange and the certified D-efficiency of each design.
//   5. Identification from simulated noise_m measurements at the selected
//      poses (V-E, Tables III and IV).
//
//   PaperExampleOptions options;
//   options.out_dir = "paper_out";  // named in the report
//   PaperExampleSummary summary;
//   const bool ok = ReproducePaperExample(robot.model, robot.true_parameters,
//                                         options, &summary);
//   std::printf("%s", summary.report.c_str());  // also on a failure
//   if (!ok) LOG(ERROR) << summary.message;
//   // summary.files: CSV files for the figures, by name in out_dir;
//   // summary.json: paper_run.json.
//
// PaperLatticePool is the pool of steps 1 (activecal_monte_carlo's default
// design is selected from it too).

#ifndef ACTIVECAL_CALIBRATION_PAPER_EXAMPLE_H_
#define ACTIVECAL_CALIBRATION_PAPER_EXAMPLE_H_

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "activecal/calibration/select_workflow.h"
#include "activecal/core/candidate_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/types.h"

namespace activecal {

// The paper's pool: the 5-level lattice of `model` (MakeLatticePool for
// position measurements) and the candidate pool of its poses at the
// nominal values, for the free parameters.
struct PaperPool {
  JointLattice lattice;
  Eigen::MatrixXd joints;  // lattice.AllJointValues()
  CandidatePool pool;
  double jacobian_seconds = 0;
  // The lattice's notes (JointLattice::OneTurnNotes), in order, one
  // "note: <note>\n" line each.
  std::string notes;
};

// False with *error ("--levels=5: ..." or the pool's message) on failure;
// out->notes is set as soon as the lattice is made. `progress` (may be
// empty) gets the Jacobians' progress.
bool MakePaperPool(const RobotModel& model, int num_threads,
                   const ProgressCallback& progress, PaperPool* out,
                   std::string* error);

struct PaperExampleOptions {
  // Seed of the random designs, the initial design and the noise (each its
  // own Random stream: 1, 2, 3; Fedorov exchange 4).
  uint64_t seed = 1;
  int random_designs = 5000;  // paper: 5,000
  int num_poses = 30;         // poses per design (paper: 30)
  int initial_poses = 12;     // exchange-add-exchange's start (paper: 12)
  double noise_m = 0.01;      // per axis (paper: 1 cm)
  // Also run exchange-add-exchange with the eigenvalue OI (tens of s).
  bool compare_eigen_oi = false;
  // Solve the approximate design, run Fedorov exchange and certify each
  // design (certificate.csv, fedorov_poses.csv).
  bool certificate = true;
  int num_threads = 0;  // 0: all; the results do not depend on it
  // The folder the caller writes the files to: named in the report and
  // the result line only.
  std::string out_dir = "paper_out";
  // The program's name, in the result line.
  std::string program_name = "activecal_puma_paper";
  // Progress of the long steps (may be empty): "Jacobians of the pool
  // poses".
  StageProgress progress;
};

struct PaperExampleSummary {
  // CONVERGENCE when every step succeeded; FAILURE with message (one line)
  // otherwise.
  TerminationType termination_type = TerminationType::kFailure;
  std::string message;
  // What the program prints on stdout: the lattice's notes, then (on
  // success) the tables beside the paper's figures; on a failure, what
  // was printed before it.
  std::string report;
  // The CSV files for the figures, (name in out_dir, text), in the order
  // they are written: random_designs.csv, eae_history.csv, eae_poses.csv,
  // eae_initial_poses.csv, random_best_poses.csv[,
  // eae_eigen_oi_history.csv][, certificate.csv, fedorov_poses.csv],
  // identification.csv.
  std::vector<std::pair<std::string, std::string>> files;
  // paper_run.json (its "timing" the only fields that vary between runs).
  nlohmann::json json;
  // "<program>: exchange-add-exchange OI ... files in <out_dir>/": the
  // run in one line (what --quiet prints).
  std::string result_line;
  // The headline numbers.
  double eae_oi = 0;
  double random_oi = 0;
  double oid_ratio_log10 = 0;  // log10 of OID(eae) / OID(best random)
  int num_within_2_std = 0;    // identified errors within 2 std
  int num_parameters = 0;
  double total_seconds = 0;
};

// `model` must be the paper's PUMA 560 (the free parameters of
// Puma560PaperModel()) with `true_parameters` its true values (as in
// data/puma560.yaml). Returns true (CONVERGENCE) when every step succeeded.
bool ReproducePaperExample(const RobotModel& model,
                           const Eigen::VectorXd& true_parameters,
                           const PaperExampleOptions& options,
                           PaperExampleSummary* summary);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_PAPER_EXAMPLE_H_
