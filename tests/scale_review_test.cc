// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Review of the scale work (issue #17): cases the other scale tests miss.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "activecal/calibration/pool_builder.h"
#include "activecal/core/candidate_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/selection/approximate_design.h"
#include "activecal/selection/fedorov.h"
#include "test_util.h"

namespace activecal {
namespace {

using testing::PumaLatticeJoints;

TEST(ScaleReviewTest, SinglePrecisionWithCheckNamesTheBadPoseInTheWholePool) {
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

TEST(ScaleReviewTest, RoundingOnlyOnAFloatPoolDoesNotHoldItInDouble) {
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
