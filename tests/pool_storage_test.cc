// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Single-precision pools: the storage, the chunked builder and its exact
// source, and the sweeps that read them.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "activecal/calibration/pool_builder.h"
#include "activecal/core/candidate_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/design.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/task_criterion.h"
#include "test_util.h"

namespace activecal {
namespace {

using testing::PumaLatticeJoints;

TEST(CandidatePoolStorageTest, FloatPoolReadsWidenedAndRefusesDoubleViews) {
  RowMatrixXd rows = RowMatrixXd::Random(12, 5);
  CandidatePool d, f;
  std::string error;
  ASSERT_TRUE(CandidatePool::Create(rows, 3, &d, &error)) << error;
  ASSERT_TRUE(
      CandidatePool::Create(RowMatrixXf(rows.cast<float>()), 3, &f, &error))
      << error;
  EXPECT_FALSE(d.single_precision());
  EXPECT_TRUE(f.single_precision());
  EXPECT_EQ(d.storage_bytes(), 12 * 5 * 8);
  EXPECT_EQ(f.storage_bytes(), 12 * 5 * 4);
  EXPECT_EQ(f.size(), 4);
  EXPECT_EQ(f.num_parameters(), 5);
  RowMatrixXd buffer;
  const auto view = f.Rows(1, 2, &buffer);
  ASSERT_EQ(view.rows(), 6);
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 5; ++c) {
      EXPECT_EQ(view(r, c),
                static_cast<double>(static_cast<float>(rows(3 + r, c))));
    }
  }
  // A double pool's Rows is a view: no copy into the buffer.
  RowMatrixXd unused;
  EXPECT_EQ(d.Rows(1, 2, &unused).data(), d.stacked().data() + 15);
  EXPECT_EQ(unused.size(), 0);
  EXPECT_EQ(f.CopyBlock(2), view.bottomRows(3));
  EXPECT_DEATH(f.block(0), "single-precision");
  EXPECT_DEATH(f.stacked(), "single-precision");
  // Without an exact source ExactRows reads the stored blocks.
  EXPECT_FALSE(f.has_exact_source());
  EXPECT_EQ(f.ExactBlock(2), f.CopyBlock(2));
}

TEST(CandidatePoolStorageTest, FloatPoolRefusesEntriesBeyondFloatRange) {
  RowMatrixXd rows = RowMatrixXd::Ones(6, 2);
  rows(4, 1) = 1e300;  // finite in double, infinite in float
  CandidatePool pool;
  std::string error;
  EXPECT_FALSE(
      CandidatePool::Create(RowMatrixXf(rows.cast<float>()), 3, &pool, &error));
  EXPECT_NE(error.find("pose 1 has a non-finite Jacobian entry (row 1, "
                       "column 1)"),
            std::string::npos)
      << error;
}

TEST(BuildCandidatePoolTest, SinglePrecisionPoolIsTheDoublePoolRounded) {
  // 7^6 = 117,649 poses: two chunks of 65,536 poses and a partial third,
  // and more rows than max_analysis_rows (the sampled identifiability
  // check). The float blocks are the double ones rounded, the exact source
  // gives the double ones back, and the same parameters are fixed.
  const Eigen::MatrixXd joints = PumaLatticeJoints(7);
  RobotModel md = Puma560PaperModel();
  md.SetFree(kD, true);  // B.d and L1.d alike: auto-fix drops one
  RobotModel mf = md;
  CandidatePoolOptions options;
  options.check_identifiability = true;
  options.auto_fix = true;
  options.num_threads = 2;
  options.max_analysis_rows = 30000;
  CandidatePool d, f;
  CandidatePoolSummary sd, sf;
  ASSERT_TRUE(BuildCandidatePool(md, md.nominal, joints, options, &d, &sd))
      << sd.message;
  options.single_precision = true;
  // Progress may come from the Jacobian threads: keep the largest count.
  std::atomic<int64_t> last_done{0}, bad_total{0};
  options.progress = [&](int64_t done, int64_t total) {
    if (total != joints.rows()) ++bad_total;
    int64_t seen = last_done.load();
    while (done > seen && !last_done.compare_exchange_weak(seen, done)) {
    }
  };
  ASSERT_TRUE(BuildCandidatePool(mf, mf.nominal, joints, options, &f, &sf))
      << sf.message;
  EXPECT_GT(last_done.load(), 65536);  // progress counts across chunks
  EXPECT_LE(last_done.load(), joints.rows());
  EXPECT_EQ(bad_total.load(), 0);
  EXPECT_EQ(HeldNames(sf.held), HeldNames(sd.held));
  ASSERT_EQ(sf.held.size(), 1u);
  EXPECT_EQ(sf.free, sd.free);
  ASSERT_TRUE(f.single_precision());
  ASSERT_TRUE(f.has_exact_source());
  ASSERT_EQ(f.size(), d.size());
  ASSERT_EQ(f.num_parameters(), 27);
  const RowMatrixXd& D = d.stacked();
  for (int64_t i :
       {int64_t{0}, int64_t{65535}, int64_t{65536}, int64_t{117648}}) {
    const RowMatrixXd stored = f.CopyBlock(i);
    const RowMatrixXd exact = f.ExactBlock(i);
    const RowMatrixXd truth = D.middleRows(3 * i, 3);
    EXPECT_EQ(stored, truth.cast<float>().cast<double>()) << "pose " << i;
    EXPECT_LE((exact - truth).cwiseAbs().maxCoeff(), 1e-15) << "pose " << i;
  }
  // Every block, rounded once: the largest relative change is float's
  // unit roundoff.
  RowMatrixXd all;
  f.CopyRows(0, f.size(), &all);
  const double scale = D.cwiseAbs().maxCoeff();
  EXPECT_LE((all - D).cwiseAbs().maxCoeff(), scale * 6e-8);
  EXPECT_GT((all - D).cwiseAbs().maxCoeff(), 0.0);  // it is rounded

  // Sweeps: the variances over the stored blocks move by ~1e-7 relative;
  // over the exact source they are the double pool's.
  const RowMatrixXd Xs =
      d.Stack({5, 900, 40000, 77777, 100000, 117000, 3, 64000, 90001, 11111})
          .eval();
  const Eigen::MatrixXd M =
      Xs.transpose() * Xs + 1e-3 * Eigen::MatrixXd::Identity(27, 27);
  const Eigen::MatrixXd V = M.llt().solve(Eigen::MatrixXd::Identity(27, 27));
  Eigen::VectorXd vd, vs, ve;
  ComputeVariances(d, V, 2, &vd);
  ComputeVariances(f, V, 2, &vs);
  ComputeVariances(f, V, 2, &ve, PoolReading::kExact);
  EXPECT_LE(((ve - vd).array() / vd.array()).abs().maxCoeff(), 1e-13);
  const double stored_error = ((vs - vd).array() / vd.array()).abs().maxCoeff();
  EXPECT_LE(stored_error, 1e-5);
  EXPECT_GT(stored_error, 0.0);
  // The task matrix, summed in chunks from the widened blocks.
  const Eigen::MatrixXd Wd = TaskMatrix(d), Wf = TaskMatrix(f);
  EXPECT_LE((Wf - Wd).norm(), 1e-6 * Wd.norm());
}

TEST(BuildCandidatePoolTest, SinglePrecisionNamesTheBadPoseInTheWholePool) {
  // A pose past the first chunk beyond its joint range: the message names
  // its index in the pool, not in its chunk.
  Eigen::MatrixXd joints = PumaLatticeJoints(7);
  joints(70000, 2) = 100.0;
  RobotModel m = Puma560PaperModel();
  CandidatePoolOptions options;
  options.single_precision = true;
  CandidatePool pool;
  CandidatePoolSummary summary;
  EXPECT_FALSE(
      BuildCandidatePool(m, m.nominal, joints, options, &pool, &summary));
  EXPECT_EQ(summary.message.rfind("pool pose 70000:", 0), 0u)
      << summary.message;
}

TEST(BuildCandidatePoolTest, SinglePrecisionRefusesAnUnidentifiablePool) {
  // All poses at one level of joint 6: its parameters cannot be separated.
  Eigen::MatrixXd joints = PumaLatticeJoints(3);
  joints.col(5).setZero();
  RobotModel m = Puma560PaperModel();
  CandidatePoolOptions options;
  options.single_precision = true;
  options.check_identifiability = true;
  CandidatePool pool;
  CandidatePoolSummary summary;
  EXPECT_FALSE(
      BuildCandidatePool(m, m.nominal, joints, options, &pool, &summary));
  EXPECT_NE(summary.message.find("not identifiable"), std::string::npos)
      << summary.message;
}

TEST(CandidatePoolStorageTest,
     SinglePrecisionWithCheckNamesTheBadPoseInTheWholePool) {
  // 7^6 = 117,649 poses, more rows than max_analysis_rows: the
  // identifiability check runs on a sample of the poses first. A bad pose
  // in that sample must be named by its index in the pool (as the double
  // path names it), not by its index in the sample.
  Eigen::MatrixXd joints = PumaLatticeJoints(7);
  RobotModel m = Puma560PaperModel();
  CandidatePoolOptions options;
  options.check_identifiability = true;
  for (const bool single : {false, true}) {
    SCOPED_TRACE(single ? "float" : "double");
    for (const int64_t bad : {int64_t{70000}, int64_t{117648}}) {
      Eigen::MatrixXd j = joints;
      j(bad, 2) = 100.0;  // beyond joint 3's range
      options.single_precision = single;
      RobotModel model = m;
      CandidatePool pool;
      CandidatePoolSummary summary;
      EXPECT_FALSE(BuildCandidatePool(model, model.nominal, j, options, &pool,
                                      &summary));
      EXPECT_EQ(
          summary.message.rfind("pool pose " + std::to_string(bad) + ":", 0),
          0u)
          << summary.message;
    }
  }
}

// The process's peak resident set (VmHWM), in bytes; reset by writing 5 to
// /proc/self/clear_refs. -1 where unavailable.
int64_t PeakRssBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) {
      std::istringstream in(line.substr(6));
      int64_t kb = -1;
      in >> kb;
      return kb * 1024;
    }
  }
  return -1;
}
bool ResetPeakRss() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.close();
  return static_cast<bool>(clear);
}

TEST(CandidatePoolStorageTest, RoundingOnlyOnAFloatPoolDoesNotHoldItInDouble) {
  // approx is FedorovExchange with max_swaps = 0: the rounding only. On a
  // single-precision pool with polish_pool_size <= 0 the polish (which can
  // make no swap) built a double sub-pool of the whole eligible pool: the
  // pool held twice, in float and in double.
  const Eigen::MatrixXd joints = PumaLatticeJoints(8);  // 262,144 poses
  RobotModel m = Puma560PaperModel();
  CandidatePoolOptions pool_options;
  pool_options.single_precision = true;
  pool_options.num_threads = 2;
  CandidatePool pool;
  CandidatePoolSummary pool_summary;
  ASSERT_TRUE(BuildCandidatePool(m, m.nominal, joints, pool_options, &pool,
                                 &pool_summary))
      << pool_summary.message;
  const int64_t double_bytes = pool.storage_bytes() * 2;  // 170 MB
  ApproximateDesignOptions a;
  a.tolerance = 1e-2;
  a.num_threads = 2;
  ApproximateDesignSummary approx;
  ASSERT_TRUE(SolveApproximateDesign(pool, {}, a, &approx)) << approx.message;
  FedorovOptions o;
  o.num_poses = 30;
  o.restarts = 1;
  o.max_swaps = 0;
  o.polish_pool_size = 0;
  o.num_threads = 2;
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer's quarantine keeps freed memory resident: the peak
  // RSS measures the sanitizer, not the pool.
  GTEST_SKIP() << "peak RSS is not meaningful under AddressSanitizer";
#endif
  if (!ResetPeakRss()) GTEST_SKIP() << "cannot reset the peak RSS";
  const int64_t before = PeakRssBytes();
  ASSERT_GT(before, 0);
  SelectionSummary summary;
  ASSERT_TRUE(FedorovExchange(pool, {}, o, &approx, &summary))
      << summary.message;
  const int64_t grown = PeakRssBytes() - before;
  EXPECT_LT(grown, double_bytes / 2)
      << "peak RSS grew by " << grown << " bytes; the pool in double is "
      << double_bytes << " bytes";
  EXPECT_EQ(summary.design.size(), 30u);
  EXPECT_TRUE(std::isfinite(summary.log_det));
}

}  // namespace
}  // namespace activecal
