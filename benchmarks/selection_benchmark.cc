// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Cost of scoring one candidate pose: the paper's determinant update
// against the eigenvalue OI by SVD of the stacked design matrix, for the
// paper's PUMA (27 parameters) and a 30-pose design.
//
//   build/benchmarks/activecal_selection_benchmark

#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>
#include <Eigen/SVD>

#include "activecal/calibration/pool_builder.h"
#include "activecal/core/candidate_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/selection/criteria.h"
#include "activecal/selection/design.h"

namespace activecal {
namespace {

const CandidatePool& Pool(int levels) {
  static std::map<int, CandidatePool> pools;
  auto it = pools.find(levels);
  if (it != pools.end()) return it->second;
  RobotModel model = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  JointLattice::Create(model, levels, &lattice, &error);
  CandidatePool pool;
  CandidatePoolSummary summary;
  BuildCandidatePool(model, model.nominal, lattice.AllJointValues(),
                     CandidatePoolOptions(), &pool, &summary);
  return pools.emplace(levels, std::move(pool)).first->second;
}

std::vector<int64_t> Design30() {
  return Random(1).SampleWithoutReplacement(Pool(5).size(), 30);
}

// The Design of Design30()'s poses on `pool`.
Design Design30Of(const CandidatePool& pool) {
  Design design(pool);
  for (int64_t i : Design30()) design.Add(i);
  return design;
}

// One candidate by the update formula: log det(I + X V X^T).
void BM_CandidateByDeterminantUpdate(benchmark::State& state) {
  const CandidatePool& pool = Pool(5);
  Design design = Design30Of(pool);
  int64_t c = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(design.information().AddGain(pool.block(c)));
    c = (c + 7919) % pool.size();
  }
}
BENCHMARK(BM_CandidateByDeterminantUpdate);

// One candidate by the eigenvalue OI: SVD of the stacked 93 x 27 matrix,
// by Eigen's divide-and-conquer SVD or the classical Jacobi SVD.
template <typename Svd>
void BM_CandidateByEigenvalueOi(benchmark::State& state) {
  const CandidatePool& pool = Pool(5);
  Eigen::MatrixXd X(31 * 3, 27);
  X.topRows(90) = pool.Stack(Design30());
  int64_t c = 0;
  for (auto _ : state) {
    X.bottomRows(3) = pool.block(c);
    Svd svd(X);
    benchmark::DoNotOptimize(
        std::exp(svd.singularValues().array().log().mean()) / 27);
    c = (c + 7919) % pool.size();
  }
}
BENCHMARK_TEMPLATE(BM_CandidateByEigenvalueOi, Eigen::BDCSVD<Eigen::MatrixXd>);
BENCHMARK_TEMPLATE(BM_CandidateByEigenvalueOi,
                   Eigen::JacobiSVD<Eigen::MatrixXd>);

// Every candidate of the 15,625-pose pool by the batched update formula.
void BM_AllCandidatesByDeterminantUpdate(benchmark::State& state) {
  const CandidatePool& pool = Pool(5);
  Design design = Design30Of(pool);
  Eigen::VectorXd gains;
  for (auto _ : state) {
    ComputeAddGains(pool, design.information(), state.range(0), &gains);
    benchmark::DoNotOptimize(gains.data());
  }
  state.SetItemsProcessed(state.iterations() * pool.size());
}
BENCHMARK(BM_AllCandidatesByDeterminantUpdate)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond);

// Adding and removing a pose (rank-3 update of V and log det).
void BM_AddRemoveUpdate(benchmark::State& state) {
  const CandidatePool& pool = Pool(5);
  Design design = Design30Of(pool);
  int64_t c = 12345;
  for (auto _ : state) {
    design.Add(c);
    design.Remove(c);
  }
}
BENCHMARK(BM_AddRemoveUpdate);

// Jacobians of the whole 15,625-pose pool: args (threads, analytic). The
// analytic point Jacobian (core/point_jacobian.h) against the Ceres
// auto-diff cost function; items/s is poses per second.
void BM_PoolJacobians(benchmark::State& state) {
  const RobotModel model = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  JointLattice::Create(model, 5, &lattice, &error);
  const Eigen::MatrixXd joints = lattice.AllJointValues();
  PoolJacobianOptions options;
  options.num_threads = state.range(0);
  options.analytic = state.range(1) != 0;
  RowMatrixXd stacked;
  for (auto _ : state) {
    PoolJacobians(model, model.nominal, joints, options, &stacked, &error);
  }
  state.SetItemsProcessed(state.iterations() * joints.rows());
}
BENCHMARK(BM_PoolJacobians)
    ->ArgNames({"threads", "analytic"})
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

// One sweep of the variance function d_i = tr(X_i V X_i^T) over the
// 7^6 = 117,649-pose PUMA pool (what the approximate design, the reduced
// pool, the polish rounds and the certificate each cost): args (threads,
// storage: 0 double, 1 float, 2 float pool swept through its exact source,
// i.e. Jacobians recomputed in double as the certificate does). items/s is
// poses per second.
void BM_VarianceSweep(benchmark::State& state) {
  const CandidatePool& pool = Pool(7);
  CandidatePool single;
  if (state.range(1) != 0) {
    // Built as the programs build it: with the exact source.
    RobotModel model = Puma560PaperModel();
    JointLattice lattice;
    std::string error;
    JointLattice::Create(model, 7, &lattice, &error);
    CandidatePoolOptions options;
    options.single_precision = true;
    CandidatePoolSummary summary;
    BuildCandidatePool(model, model.nominal, lattice.AllJointValues(), options,
                       &single, &summary);
  }
  const CandidatePool& swept = state.range(1) != 0 ? single : pool;
  const PoolReading reading =
      state.range(1) == 2 ? PoolReading::kExact : PoolReading::kStored;
  const int p = pool.num_parameters();
  const Eigen::MatrixXd X =
      pool.Stack(Random(1).SampleWithoutReplacement(pool.size(), 60));
  const Eigen::MatrixXd M = X.transpose() * X;
  const Eigen::MatrixXd V = M.llt().solve(Eigen::MatrixXd::Identity(p, p));
  Eigen::VectorXd d;
  for (auto _ : state) {
    ComputeVariances(swept, V, state.range(0), &d, reading);
    benchmark::DoNotOptimize(d.data());
  }
  state.SetItemsProcessed(state.iterations() * pool.size());
}
BENCHMARK(BM_VarianceSweep)
    ->ArgNames({"threads", "storage"})
    ->ArgsProduct({{1, 2}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace activecal

BENCHMARK_MAIN();
