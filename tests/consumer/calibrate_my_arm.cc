// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The whole calibration job through the library: load a robot file, choose
// poses by Fedorov exchange on a lattice, simulate what a tracker would
// measure there, identify, and save the calibrated model.
//
//   calibrate_my_arm <robot.yaml> <calibrated.yaml>

#include <activecal/calibration/pool_builder.h>
#include <activecal/core/candidate_pool.h>
#include <activecal/core/lattice.h>
#include <activecal/core/simulation.h>
#include <activecal/estimation/identification.h>
#include <activecal/io/robot_file.h>
#include <activecal/selection/approximate_design.h>
#include <activecal/selection/fedorov.h>

#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: calibrate_my_arm <robot.yaml> <calibrated.yaml>\n";
    return 2;
  }
  std::string error;
  activecal::RobotDescription robot;
  if (!activecal::LoadRobotFile(argv[1], &robot, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  activecal::RobotModel model = robot.model;

  // 1. A pool of candidate poses and its Jacobians at the nominal values,
  // checked to identify every free parameter.
  activecal::JointLattice lattice;
  if (!activecal::JointLattice::Create(model, 4, &lattice, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  const Eigen::MatrixXd joints = lattice.AllJointValues();
  activecal::CandidatePoolOptions pool_options;
  pool_options.check_identifiability = true;
  activecal::CandidatePool pool;
  activecal::CandidatePoolSummary pool_summary;
  if (!activecal::BuildCandidatePool(model, model.nominal, joints, pool_options,
                                     &pool, &pool_summary)) {
    std::cerr << pool_summary.message << "\n";
    return 1;
  }

  // 2. A D-optimal design of 40 poses, with its efficiency certificate.
  activecal::ApproximateDesignSummary approximate;
  activecal::SolveApproximateDesign(
      pool, {}, activecal::ApproximateDesignOptions(), &approximate);
  activecal::FedorovOptions options;
  options.num_poses = 40;
  options.restarts = 4;
  activecal::SelectionSummary design;
  if (!activecal::FedorovExchange(pool, {}, options, &approximate, &design)) {
    std::cerr << design.message << "\n";
    return 1;
  }
  activecal::CertifyDesign(pool, {}, &approximate, 0, &design);
  std::cout << design.BriefReport();

  // 3. What a tracker with 0.1 mm noise would measure there.
  std::vector<activecal::Measurement> plan(design.design.size());
  for (size_t i = 0; i < plan.size(); ++i) {
    plan[i].joints = joints.row(design.design[i]).transpose();
  }
  activecal::SimulationNoise noise;
  noise.position_m = 1e-4;
  std::vector<activecal::Measurement> measured;
  if (!activecal::SimulateMeasurements(model, robot.true_parameters, plan,
                                       noise, /*seed=*/1, &measured, &error)) {
    std::cerr << error << "\n";
    return 1;
  }

  // 4. Identify and save.
  activecal::IdentificationSummary summary;
  activecal::Identify(model, measured, model.nominal,
                      activecal::IdentificationOptions(), &summary);
  if (summary.termination_type != activecal::TerminationType::kConvergence) {
    std::cerr << summary.message << "\n";
    return 1;
  }
  std::cout << summary.BriefReport();
  std::ofstream(argv[2]) << activecal::RobotFileText(model, summary.parameters);
  return summary.rms_m < 1e-3 ? 0 : 1;
}
