// Review of the scale work (issue #17): cases the other scale tests miss.

#include <gtest/gtest.h>

#include <string>

#include "activecal/core/candidate_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/residuals/pool_builder.h"

namespace activecal {
namespace {

Eigen::MatrixXd PumaLatticeJoints(int levels) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(m, levels, &lattice, &error)) << error;
  return lattice.AllJointValues();
}

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
      EXPECT_FALSE(BuildCandidatePool(&model, model.nominal, j, options, &pool,
                                      &summary));
      EXPECT_EQ(
          summary.message.rfind("pool pose " + std::to_string(bad) + ":", 0),
          0u)
          << summary.message;
    }
  }
}

}  // namespace
}  // namespace activecal
