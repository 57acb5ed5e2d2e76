// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// SelectDesign (the design step of activecal_select and the Python module)
// and BuildSelectionPool (its pool side).

#include "activecal/calibration/select_design.h"

#include <gtest/gtest.h>

#include <string>

#include "activecal/calibration/selection_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/selection/detmax.h"
#include "activecal/selection/exchange_add_exchange.h"
#include "activecal/selection/fedorov.h"
#include "activecal/selection/task_criterion.h"
#include "activecal/selection/task_exchange.h"
#include "test_util.h"

namespace activecal {
namespace {

std::string Invalid(const SelectDesignOptions& options) {
  std::string error;
  EXPECT_FALSE(options.IsValid(&error));
  return error;
}

TEST(SelectDesignTest, BadOptionsGiveOneLineMessages) {
  SelectDesignOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o = SelectDesignOptions();
  o.restarts = -1;
  EXPECT_EQ(Invalid(o), "restarts must be >= 0, got -1");
  o = SelectDesignOptions();
  o.criterion = DesignCriterion::kTaskRms;  // eae has no task version
  EXPECT_EQ(Invalid(o),
            "criterion=task_rms: algorithm must be fedorov, greedy or "
            "approx, got 'eae'");
  o = SelectDesignOptions();
  o.noise_m = 0;
  EXPECT_EQ(Invalid(o), "noise_m must be > 0 (m), got 0");
  o = SelectDesignOptions();
  o.target_rms_m = -1.0;
  EXPECT_EQ(Invalid(o), "target_rms_m must be > 0 (m), got -1");
  o = SelectDesignOptions();
  o.approx_tolerance = 0;  // the certificate solves the approximate design
  EXPECT_EQ(Invalid(o), "approx_tolerance: tolerance must be > 0, got 0");
  o.certificate = false;  // eae without a certificate does not
  EXPECT_TRUE(o.IsValid(&error)) << error;
}

TEST(SelectDesignTest, AlgorithmAndCriterionNamesRoundTrip) {
  for (DesignAlgorithm a :
       {DesignAlgorithm::kEae, DesignAlgorithm::kRandom,
        DesignAlgorithm::kFedorov, DesignAlgorithm::kDetmax,
        DesignAlgorithm::kGreedy, DesignAlgorithm::kApprox}) {
    DesignAlgorithm back = DesignAlgorithm::kEae;
    ASSERT_TRUE(StringToDesignAlgorithm(DesignAlgorithmToString(a), &back));
    EXPECT_EQ(back, a);
  }
  EXPECT_STREQ(DesignAlgorithmToString(DesignAlgorithm::kDetmax), "detmax");
  DesignAlgorithm a = DesignAlgorithm::kGreedy;
  EXPECT_FALSE(StringToDesignAlgorithm("Fedorov", &a));
  EXPECT_EQ(a, DesignAlgorithm::kGreedy);  // unchanged
  std::string error;
  EXPECT_FALSE(ParseDesignAlgorithm("simplex", &a, &error));
  EXPECT_EQ(error,
            "algorithm must be one of eae, random, fedorov, detmax, greedy, "
            "approx; got 'simplex'");
  for (DesignCriterion c : {DesignCriterion::kDet, DesignCriterion::kSvd,
                            DesignCriterion::kTaskRms}) {
    DesignCriterion back = DesignCriterion::kDet;
    ASSERT_TRUE(StringToDesignCriterion(DesignCriterionToString(c), &back));
    EXPECT_EQ(back, c);
  }
  DesignCriterion c = DesignCriterion::kSvd;
  ASSERT_TRUE(StringToDesignCriterion("d", &c));  // the alias of det
  EXPECT_EQ(c, DesignCriterion::kDet);
  EXPECT_STREQ(DesignCriterionToString(c), "det");
  EXPECT_FALSE(ParseDesignCriterion("e", &c, &error));
  EXPECT_EQ(error, "criterion must be det (d), svd or task_rms, got 'e'");
  EXPECT_TRUE(ReadsFloatPool(DesignAlgorithm::kFedorov, DesignCriterion::kDet));
  EXPECT_TRUE(ReadsFloatPool(DesignAlgorithm::kApprox, DesignCriterion::kSvd));
  EXPECT_FALSE(
      ReadsFloatPool(DesignAlgorithm::kFedorov, DesignCriterion::kTaskRms));
  EXPECT_FALSE(ReadsFloatPool(DesignAlgorithm::kEae, DesignCriterion::kDet));
}

TEST(SelectDesignTest, RestartsPolicyCrossesTheLargePoolThreshold) {
  SelectDesignOptions o;
  o.algorithm = DesignAlgorithm::kFedorov;
  EXPECT_EQ(ResolvedRestarts(o, kFedorovLargePool), FedorovOptions().restarts);
  EXPECT_EQ(ResolvedRestarts(o, kFedorovLargePool + 1),
            kFedorovLargePoolRestarts);
  EXPECT_EQ(kFedorovLargePool, 200000);
  EXPECT_EQ(kFedorovLargePoolRestarts, 8);
  o.restarts = 3;  // set: both sides
  EXPECT_EQ(ResolvedRestarts(o, kFedorovLargePool), 3);
  EXPECT_EQ(ResolvedRestarts(o, kFedorovLargePool + 1), 3);
  o.restarts = 0;
  o.algorithm = DesignAlgorithm::kApprox;
  EXPECT_EQ(ResolvedRestarts(o, kFedorovLargePool + 1), 1);
  o.algorithm = DesignAlgorithm::kEae;
  EXPECT_EQ(ResolvedRestarts(o, kFedorovLargePool + 1),
            ExchangeAddExchangeOptions().restarts);
  o.algorithm = DesignAlgorithm::kDetmax;
  EXPECT_EQ(ResolvedRestarts(o, kFedorovLargePool + 1),
            DetmaxOptions().restarts);
  o.algorithm = DesignAlgorithm::kGreedy;
  EXPECT_EQ(ResolvedRestarts(o, 10), 0);
  o.algorithm = DesignAlgorithm::kFedorov;
  o.criterion = DesignCriterion::kTaskRms;
  EXPECT_EQ(ResolvedRestarts(o, kFedorovLargePool + 1),
            TaskExchangeOptions().restarts);
}

class SelectDesignPoolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    pool_ = testing::PumaPool(3);
    W_ = TaskMatrix(pool_);
    no_prior_ = RowMatrixXd(0, pool_.num_parameters());
  }
  CandidatePool pool_;
  Eigen::MatrixXd W_;
  RowMatrixXd no_prior_;
};

TEST_F(SelectDesignPoolTest, FedorovEqualsTheAlgorithmCalledDirectly) {
  SelectDesignOptions o;
  o.algorithm = DesignAlgorithm::kFedorov;
  o.num_poses = 12;
  o.seed = 7;
  SelectDesignSummary s;
  ASSERT_TRUE(SelectDesign(pool_, W_, no_prior_, o, &s)) << s.message;
  EXPECT_FALSE(s.task);
  EXPECT_TRUE(s.with_approx);
  EXPECT_FALSE(s.with_task_approx);
  EXPECT_EQ(s.restarts, FedorovOptions().restarts);  // pool <= 200,000
  EXPECT_EQ(s.selection.restarts, s.restarts);

  ApproximateDesignSummary approx;
  ApproximateDesignOptions ao;
  ao.tolerance = 2e-3;
  ao.seed = 7;  // the approximate design follows the seed too
  ASSERT_TRUE(SolveApproximateDesign(pool_, {}, ao, &approx) ||
              !approx.support.empty());
  FedorovOptions fo;
  fo.num_poses = 12;
  fo.seed = 7;
  SelectionSummary direct;
  ASSERT_TRUE(FedorovExchange(pool_, {}, fo, &approx, &direct));
  EXPECT_EQ(s.selection.design, direct.design);
  EXPECT_EQ(s.selection.log_det, direct.log_det);
  EXPECT_EQ(s.approx.weights, approx.weights);
  CertifyDesign(pool_, {}, &approx, 0, &direct);
  EXPECT_EQ(s.selection.efficiency_lower_bound, direct.efficiency_lower_bound);
  EXPECT_DOUBLE_EQ(s.predicted_task_rms_m,
                   PredictedTaskRms(TaskCriterionFromScratch(
                                        pool_, W_, no_prior_, direct.design),
                                    o.noise_m));
  EXPECT_EQ(s.BriefReport(),
            s.selection.BriefReport() + s.approx.BriefReport());
}

TEST_F(SelectDesignPoolTest, EaeEqualsTheAlgorithmCalledDirectly) {
  SelectDesignOptions o;  // eae, det
  o.num_poses = 10;
  o.certificate = false;
  SelectDesignSummary s;
  ASSERT_TRUE(SelectDesign(pool_, W_, no_prior_, o, &s)) << s.message;
  EXPECT_FALSE(s.with_approx);
  ExchangeAddExchangeOptions eo;
  eo.num_poses = 10;
  eo.initial_poses = 10;  // min(12, num_poses)
  eo.seed = 1;
  SelectionSummary direct;
  ASSERT_TRUE(ExchangeAddExchange(pool_, {}, eo, &direct));
  EXPECT_EQ(s.selection.design, direct.design);
  EXPECT_EQ(s.selection.log_det, direct.log_det);
}

TEST_F(SelectDesignPoolTest, TaskCriterionDispatchesToTaskExchange) {
  SelectDesignOptions o;
  o.algorithm = DesignAlgorithm::kFedorov;
  o.criterion = DesignCriterion::kTaskRms;
  o.num_poses = 12;
  o.certificate = false;  // fedorov still solves the approximate design
  SelectDesignSummary s;
  ASSERT_TRUE(SelectDesign(pool_, W_, no_prior_, o, &s)) << s.message;
  EXPECT_TRUE(s.task);
  EXPECT_FALSE(s.with_approx);
  EXPECT_TRUE(s.with_task_approx);
  EXPECT_EQ(s.restarts, TaskExchangeOptions().restarts);

  TaskApproximateOptions ao;
  ao.tolerance = 1e-2;
  TaskApproximateSummary approx;
  ASSERT_TRUE(SolveTaskApproximateDesign(pool_, W_, {}, ao, &approx));
  TaskExchangeOptions to;
  to.num_poses = 12;
  to.seed = 1;
  SelectionSummary direct;
  ASSERT_TRUE(TaskExchange(pool_, W_, no_prior_, {}, to, &approx, &direct));
  EXPECT_EQ(s.selection.design, direct.design);
  EXPECT_DOUBLE_EQ(s.selection.task_criterion, direct.task_criterion);

  o.algorithm = DesignAlgorithm::kApprox;
  ASSERT_TRUE(SelectDesign(pool_, W_, no_prior_, o, &s)) << s.message;
  EXPECT_EQ(s.selection.algorithm, "task approx (rounded)");
  EXPECT_EQ(s.restarts, 1);
  o.criterion = DesignCriterion::kDet;
  ASSERT_TRUE(SelectDesign(pool_, W_, no_prior_, o, &s)) << s.message;
  EXPECT_EQ(s.selection.algorithm, "approx (rounded)");
  EXPECT_TRUE(s.with_approx);
}

TEST_F(SelectDesignPoolTest, TargetAndFailures) {
  SelectDesignOptions o;
  o.algorithm = DesignAlgorithm::kGreedy;
  o.num_poses = 0;
  SelectDesignSummary s;
  EXPECT_FALSE(SelectDesign(pool_, W_, no_prior_, o, &s));
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(s.message, "num_poses must be in [1, 729] (the pool size), got 0");
  o.restarts = -1;
  EXPECT_FALSE(SelectDesign(pool_, W_, no_prior_, o, &s));
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);

  // A prior needs the task criterion.
  o = SelectDesignOptions();
  o.num_poses = 10;
  const RowMatrixXd prior =
      RowMatrixXd::Identity(pool_.num_parameters(), pool_.num_parameters());
  EXPECT_FALSE(SelectDesign(pool_, W_, prior, o, &s));
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);

  // A target met: the size search, no num_poses needed.
  o = SelectDesignOptions();
  o.algorithm = DesignAlgorithm::kGreedy;
  o.criterion = DesignCriterion::kTaskRms;
  o.num_poses = 0;
  o.target_rms_m = 1.0;  // any design with enough poses
  ASSERT_TRUE(SelectDesign(pool_, W_, no_prior_, o, &s)) << s.message;
  EXPECT_TRUE(s.with_target);
  EXPECT_TRUE(s.target.reached());
  EXPECT_EQ(s.selection.design.size(), static_cast<size_t>(s.target.num_poses));
  EXPECT_LE(s.predicted_task_rms_m, 1.0);
  o.target_rms_m = 1e-12;  // unreachable
  EXPECT_FALSE(SelectDesign(pool_, W_, no_prior_, o, &s));
  EXPECT_EQ(s.message.rfind("target_rms_m: ", 0), 0u) << s.message;
}

TEST(SelectionPoolTest, StorageChoiceAndReduction) {
  RobotModel model = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  ASSERT_TRUE(JointLattice::Create(model, 3, &lattice, &error)) << error;
  const Eigen::MatrixXd joints = lattice.AllJointValues();

  SelectionPoolOptions o;
  o.storage = PoolStorage::kFloat;
  EXPECT_FALSE(o.IsValid(&error));  // float needs a design that reads it
  o.reads_float = true;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.storage = PoolStorage::kAuto;
  o.max_double_pool_mib = -1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_EQ(error, "max_double_pool_mib must be >= 0, got -1");

  o.max_double_pool_mib = 0;  // every pool is over it
  CandidatePool pool;
  SelectionPoolSummary s;
  RobotModel m = model;
  ASSERT_TRUE(BuildSelectionPool(&m, joints, o, &pool, &s)) << s.message;
  EXPECT_TRUE(s.single_precision);
  EXPECT_TRUE(pool.single_precision());
  EXPECT_EQ(pool.size(), joints.rows());
  EXPECT_EQ(pool.num_parameters(), m.num_free());

  o.reads_float = false;  // auto keeps double for the other designs
  m = model;
  ASSERT_TRUE(BuildSelectionPool(&m, joints, o, &pool, &s)) << s.message;
  EXPECT_FALSE(s.single_precision);
  EXPECT_FALSE(pool.single_precision());

  CandidatePool task_pool;
  bool task_is_pool = false;
  ASSERT_TRUE(BuildTaskPool(m, joints, Eigen::MatrixXd(), o, &task_pool,
                            &task_is_pool, &error));
  EXPECT_TRUE(task_is_pool);
  ASSERT_TRUE(BuildTaskPool(m, joints, joints.topRows(5), o, &task_pool,
                            &task_is_pool, &error));
  EXPECT_FALSE(task_is_pool);
  EXPECT_EQ(task_pool.size(), 5);
}

// Issue 26, item 15: activecal_select --pool_size=100000000000 was a
// std::bad_alloc (exit 134). The size is checked first against a lower
// bound (one single-precision column), then exactly once the parameters and
// storage are known; both cross their threshold here.
TEST(SelectionPoolTest, APoolLargerThanMemoryIsRefused) {
  const RobotModel model = Puma560PaperModel();
  EXPECT_EQ(SelectionPoolBytes(10, 6, MeasurementType::kPose, 27, true),
            10.0 * (6 * 8 + 6 * 27 * 4));
  EXPECT_EQ(SelectionPoolBytes(10, 6, MeasurementType::kPosition, 27, false),
            10.0 * (6 * 8 + 3 * 27 * 8));
  EXPECT_GT(PhysicalMemoryBytes(), 0);
  std::string error;
  EXPECT_FALSE(CheckSelectionPoolSize(100000000000, model,
                                      MeasurementType::kPosition, &error));
  EXPECT_EQ(error.rfind("a pool of 100000000000 poses needs at least 5.59e+03 "
                        "GiB (joint values and one single-precision Jacobian "
                        "column per measurement row), more than this "
                        "machine's ",
                        0),
            0u)
      << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
  const double limit =
      SelectionPoolBytes(1000, 6, MeasurementType::kPosition, 1, true);
  error.clear();
  EXPECT_TRUE(CheckSelectionPoolSize(1000, model, MeasurementType::kPosition,
                                     &error, limit));
  EXPECT_TRUE(error.empty());
  EXPECT_FALSE(CheckSelectionPoolSize(1001, model, MeasurementType::kPosition,
                                      &error, limit));
  EXPECT_NE(error.find("more than the limit of "), std::string::npos) << error;
  EXPECT_TRUE(
      CheckSelectionPoolSize(0, model, MeasurementType::kPosition, &error));

  // The exact size, once the 27 parameters and double storage are chosen:
  // the pool built at the limit holds that many bytes; one byte less fails
  // before the Jacobians are computed.
  JointLattice lattice;
  ASSERT_TRUE(JointLattice::Create(model, 3, &lattice, &error)) << error;
  const Eigen::MatrixXd joints = lattice.AllJointValues();
  const double exact = SelectionPoolBytes(
      joints.rows(), 6, MeasurementType::kPosition, 27, false);
  SelectionPoolOptions o;
  o.memory_limit_bytes = exact;
  CandidatePool pool;
  SelectionPoolSummary s;
  RobotModel m = model;
  ASSERT_TRUE(BuildSelectionPool(&m, joints, o, &pool, &s)) << s.message;
  ASSERT_EQ(m.num_free(), 27);
  EXPECT_EQ(static_cast<double>(pool.storage_bytes()) + 8.0 * joints.size(),
            exact);
  o.memory_limit_bytes = exact - 1;
  m = model;
  CandidatePool refused;
  EXPECT_FALSE(BuildSelectionPool(&m, joints, o, &refused, &s));
  EXPECT_EQ(s.termination_type, TerminationType::kUserFailure);
  EXPECT_EQ(refused.size(), 0);
  EXPECT_EQ(s.message.rfind("a pool of 729 poses needs ", 0), 0u) << s.message;
  EXPECT_NE(s.message.find("(joint values and double-precision Jacobians of "
                           "27 parameters), more than the limit of "),
            std::string::npos)
      << s.message;
}

}  // namespace
}  // namespace activecal
