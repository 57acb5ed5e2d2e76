// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Helpers shared by the tests.

#ifndef ACTIVECAL_TESTS_TEST_UTIL_H_
#define ACTIVECAL_TESTS_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <fstream>
#include <sstream>
#include <string>

#include "activecal/calibration/pool_builder.h"
#include "activecal/core/candidate_pool.h"
#include "activecal/core/free_set.h"
#include "activecal/core/kinematics.h"
#include "activecal/core/lattice.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/robot_model.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/urdf_robot.h"
#include "activecal/residuals/jacobians.h"
#include "activecal/selection/design.h"

namespace activecal {
namespace testing {

// ReduceParameterSet, its free set applied to *model: the model a fit of
// the reduced set runs on (the tests' shorthand).
inline bool ReduceModel(ParameterSet set,
                        const std::vector<Measurement>& measurements,
                        double rotation_weight, RobotModel* model,
                        Eigen::VectorXd* point,
                        std::vector<HeldParameter>* held, std::string* error) {
  FreeSet free;
  if (!ReduceParameterSet(*model, set, measurements, rotation_weight, point,
                          &free, held, error)) {
    return false;
  }
  *model = WithFreeSet(*model, free);
  return true;
}

// The PUMA lattice pool with `levels` values per joint, Jacobians at the
// nominal values.
inline CandidatePool PumaPool(int levels, JointLattice* lattice_out = nullptr) {
  RobotModel model = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(model, levels, &lattice, &error)) << error;
  CandidatePool pool;
  CandidatePoolSummary summary;
  EXPECT_TRUE(BuildCandidatePool(model, model.nominal, lattice.AllJointValues(),
                                 CandidatePoolOptions(), &pool, &summary))
      << summary.message;
  if (lattice_out) *lattice_out = lattice;
  return pool;
}

// A planar three-link arm: six free parameters (offsets and lengths), a
// pool of 5^3 = 125 poses (Jacobians at the nominal values); small enough
// for exhaustive search over all 3-pose designs.
inline CandidatePool PlanarPool() {
  RobotModel m;
  m.name = "planar3";
  m.base.joint_type = JointType::kFixed;
  for (int i = 0; i < 3; ++i) {
    Link l;
    l.name = "L" + std::to_string(i + 1);
    l.joint_min = -2.8;
    l.joint_max = 2.8;
    l.free = {true, false, true, false, false, false};
    m.links.push_back(l);
  }
  m.nominal = Eigen::VectorXd::Zero(m.num_parameters());
  const double lengths[3] = {0.6, 0.45, 0.2};
  for (int b = 0; b < 4; ++b) m.nominal[6 * b + kGain] = 1.0;
  for (int i = 0; i < 3; ++i) {
    m.nominal[6 * (i + 1) + kA] = lengths[i];
    m.nominal[6 * (i + 1) + kGamma] = 0.1 * (i + 1);
  }
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(m, 5, &lattice, &error)) << error;
  RowMatrixXd stacked;
  EXPECT_TRUE(PoolJacobians(m, m.nominal, lattice.AllJointValues(),
                            PoolJacobianOptions(), &stacked, &error))
      << error;
  CandidatePool pool;
  EXPECT_TRUE(CandidatePool::Create(std::move(stacked), 3, &pool, &error));
  return pool;
}

// The PUMA lattice's joint values with `levels` values per joint.
inline Eigen::MatrixXd PumaLatticeJoints(int levels) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(m, levels, &lattice, &error)) << error;
  return lattice.AllJointValues();
}

// num_poses random poses (drawn with `seed`) of the PUMA lattice with 5
// values per joint, one a row.
inline Eigen::MatrixXd PumaLatticeSample(int num_poses, uint64_t seed) {
  const RobotModel m = Puma560PaperModel();
  JointLattice lattice;
  std::string error;
  EXPECT_TRUE(JointLattice::Create(m, 5, &lattice, &error));
  Random random(seed);
  const std::vector<int64_t> poses =
      random.SampleWithoutReplacement(lattice.size(), num_poses);
  Eigen::MatrixXd joints(num_poses, 6);
  for (int i = 0; i < num_poses; ++i) {
    joints.row(i) = lattice.JointValues(poses[i]).transpose();
  }
  return joints;
}

// Adds a pose of the design's pool drawn with `random` (uniformly, drawn
// again until it is not in the design).
inline void AddRandomNewPose(Design* design, Random* random) {
  int64_t i;
  do {
    i = static_cast<int64_t>(random->UniformInt(design->pool().size()));
  } while (design->Contains(i));
  design->Add(i);
}

// Removes a pose of the design drawn with `random`; a refused removal (the
// rest singular) is drawn again.
inline void RemoveRandomPose(Design* design, Random* random) {
  while (!design->Remove(design->poses()[random->UniformInt(design->size())])) {
  }
}

// A six-joint URDF chain's model with only these free: the base frame, the
// marker's position, the offsets of joints 2-5 (joint 1's is the base's rz,
// joint 6's the marker's).
inline RobotModel UrdfOffsetsModel(const RobotModel& m) {
  RobotModel fitted = m;
  for (int i = 0; i < m.num_parameters(); ++i) fitted.SetFree(i, false);
  for (int j = 0; j < 6; ++j) fitted.SetFree(j, true);
  for (int b = 2; b <= 5; ++b) {
    fitted.SetFree(m.block_offset(b) + kUrdfOffset, true);
  }
  for (int j = 0; j < 3; ++j) {
    fitted.SetFree(m.block_offset(m.marker_block(0)) + j, true);
  }
  return fitted;
}

// Random joint values inside the model's ranges.
inline Eigen::VectorXd RandomJoints(const RobotModel& model, Random* random) {
  Eigen::VectorXd q(model.num_joints());
  for (int j = 0; j < model.num_joints(); ++j) {
    const Link& l = model.links[j];
    q[j] = l.joint_min + (l.joint_max - l.joint_min) * random->Uniform();
  }
  return q;
}

// num_rows rows of RandomJoints, one configuration a row.
inline Eigen::MatrixXd RandomJointRows(const RobotModel& model, int num_rows,
                                       Random* random) {
  Eigen::MatrixXd joints(num_rows, model.num_joints());
  for (int i = 0; i < num_rows; ++i) {
    joints.row(i) = RandomJoints(model, random).transpose();
  }
  return joints;
}

// The true PUMA (Puma560TrueParameters) measured at num_poses random
// configurations (RandomJointRows of the paper model from joint_seed), rows
// of that type with that noise, the noise drawn from noise_seed.
inline std::vector<Measurement> SimulatedPuma(int num_poses,
                                              uint64_t joint_seed,
                                              MeasurementType type,
                                              const SimulationNoise& noise,
                                              uint64_t noise_seed) {
  const RobotModel model = Puma560PaperModel();
  Random random(joint_seed);
  const Eigen::MatrixXd joints = RandomJointRows(model, num_poses, &random);
  std::vector<Measurement> out;
  std::string error;
  EXPECT_TRUE(SimulateMeasurements(model, Puma560TrueParameters(),
                                   MeasurementPlan(joints, type), noise,
                                   noise_seed, &out, &error))
      << error;
  return out;
}

// log det M of a symmetric positive definite M, by its Cholesky factor.
inline double CholeskyLogDet(const Eigen::MatrixXd& M) {
  return 2.0 * Eigen::LLT<Eigen::MatrixXd>(M)
                   .matrixLLT()
                   .diagonal()
                   .array()
                   .log()
                   .sum();
}

// A test suite on the 3^6 = 729 PUMA poses of PumaPool(3) in puma_, built
// once for the suite.
class PumaPoolSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { puma_ = new CandidatePool(PumaPool(3)); }
  static void TearDownTestSuite() {
    delete puma_;
    puma_ = nullptr;
  }
  static inline CandidatePool* puma_ = nullptr;
};

// A model with no links yet, named `name`, whose base is the fixed link "B"
// of that convention with those parameters free.
inline RobotModel ModelWithBase(const std::string& name,
                                LinkConvention convention,
                                const std::array<bool, kMaxBlockSize>& free) {
  RobotModel m;
  m.name = name;
  m.base.name = "B";
  m.base.convention = convention;
  m.base.joint_type = JointType::kFixed;
  m.base.free = free;
  return m;
}

// m at `values` written by RobotFileText with `options` into *text and read
// back by ParseRobotDescription (as the file `source`) into *back.
inline ::testing::AssertionResult RobotFileRoundTrip(
    const RobotModel& m, const Eigen::VectorXd& values,
    const RobotFileOptions& options, const std::string& source,
    RobotDescription* back, std::string* text) {
  *text = RobotFileText(m, values, options);
  std::string error;
  if (ParseRobotDescription(*text, source, back, &error)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << error << "\n" << *text;
}

// parse(text, &value) reads `text` as `expected` and refuses `bad`: an
// enum's StringToX.
template <typename Enum, typename Parse>
void ExpectEnumParsing(Parse parse, const std::string& text, Enum expected,
                       const std::string& bad) {
  Enum value{};
  EXPECT_TRUE(parse(text, &value)) << text;
  EXPECT_EQ(value, expected) << text;
  EXPECT_FALSE(parse(bad, &value)) << bad;
}

// For each design, with no approximate design and with `approx`: a
// SelectionSummary holding the design, given to check(a, &summary) (a:
// nullptr, then &approx), until a fatal failure.
template <typename Approx, typename Check>
void CheckEachDesign(const std::vector<std::vector<int64_t>>& designs,
                     const Approx& approx, Check check) {
  for (const std::vector<int64_t>& d : designs) {
    for (const Approx* a : {static_cast<const Approx*>(nullptr), &approx}) {
      SelectionSummary summary;
      summary.design = d;
      check(a, &summary);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

// The whole text of the file at `path`, "" where it cannot be read.
inline std::string FileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

#ifdef ACTIVECAL_TEST_DATA_DIR
// The text of tests/data/<name>.
inline std::string TestDataText(const std::string& name) {
  return FileText(std::string(ACTIVECAL_TEST_DATA_DIR) + "/" + name);
}
#endif

#ifdef ACTIVECAL_DATA_DIR
// The path of data/<name>.
inline std::string DataFile(const std::string& name) {
  return std::string(ACTIVECAL_DATA_DIR) + "/" + name;
}

// data/<file>, the URDF chain from its base link to tool0 (the URs').
inline bool LoadShippedUr(const std::string& file, RobotDescription* robot,
                          std::string* error) {
  UrdfChainOptions chain;
  chain.tip_link = "tool0";
  return LoadUrdfRobot(std::string(ACTIVECAL_DATA_DIR) + "/" + file, chain,
                       robot, error);
}
#endif

// A model exercising every convention, a prismatic joint, free gains and a
// free tool point.
inline RobotModel MixedModel() {
  RobotModel m = ModelWithBase("mixed", LinkConvention::kHayati,
                               {true, true, true, true, true, false});
  const LinkConvention conventions[4] = {
      LinkConvention::kStandardDH, LinkConvention::kHayati,
      LinkConvention::kModifiedDH, LinkConvention::kStandardDH};
  for (int i = 0; i < 4; ++i) {
    Link l;
    l.name = "L" + std::to_string(i + 1);
    l.convention = conventions[i];
    l.joint_type = i == 2 ? JointType::kPrismatic : JointType::kRevolute;
    l.joint_min = i == 2 ? 0.0 : -2.5;
    l.joint_max = i == 2 ? 0.4 : 2.5;
    l.free = {true, true, true, true, conventions[i] == LinkConvention::kHayati,
              true};
    m.links.push_back(l);
  }
  m.markers[0].free = {true, true, true};
  m.nominal.resize(m.num_parameters());
  m.nominal << 0.1, 0.02, 1.5, 0.3, -0.01, 1.0,  // B
      0.0, -1.57, 0.05, 0.6, 0.0, 1.0,           // L1 DH
      0.01, 0.02, 0.43, 0.0, 0.01, 1.0,          // L2 Hayati
      0.3, 1.2, 0.1, 0.05, 0.0, 1.0,             // L3 modified DH, prismatic
      -0.2, 0.7, 0.2, 0.1, 0.0, 0.98,            // L4 DH
      0.05, -0.02, 0.12, 0.0, 0.0, 0.0;          // tool point, angles
  return m;
}

// A model of the newer conventions: a 6-DOF frame base, URDF joints
// (revolute about z, about a tilted axis, prismatic), a fixed tip transform
// and two markers, every parameter free except the base's that the first
// joint's corrections duplicate.
inline RobotModel UrdfStyleModel() {
  RobotModel m = ModelWithBase("urdf_style", LinkConvention::kFrame,
                               {true, true, true, true, true, true});
  const Eigen::Vector3d axes[4] = {
      Eigen::Vector3d::UnitZ(), Eigen::Vector3d(1, 2, 3).normalized(),
      Eigen::Vector3d::UnitY(), Eigen::Vector3d(0, -1, 1).normalized()};
  for (int i = 0; i < 4; ++i) {
    Link l;
    l.name = "joint" + std::to_string(i + 1);
    l.convention = LinkConvention::kUrdf;
    l.joint_type = i == 2 ? JointType::kPrismatic : JointType::kRevolute;
    l.joint_min = i == 2 ? -0.1 : -2.5;
    l.joint_max = i == 2 ? 0.3 : 2.5;
    l.origin_xyz = Eigen::Vector3d(0.1 * i, 0.05, 0.3 - 0.02 * i);
    l.origin_rotation = RpyRotation(0.3 * i - 0.2, 0.1, -0.4 + 0.2 * i);
    l.axis = axes[i];
    l.free = {true, true, true, true, true, true, true, true};
    m.links.push_back(l);
  }
  m.tip.translation = Eigen::Vector3d(0.0, 0.02, 0.11);
  m.tip.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized())
                       .toRotationMatrix();
  m.markers.resize(2);
  m.markers[0].free = {true, true, true, true, true, true};
  m.markers[1].name = "marker2";
  m.markers[1].free = {true, true, true, false, false, false};
  m.nominal = Eigen::VectorXd::Zero(m.num_parameters());
  for (int b = 0; b < m.num_blocks(); ++b) {
    DefaultBlockValues(m, b, m.nominal.data() + m.block_offset(b));
  }
  m.nominal.head(6) << 1.2, -0.4, 0.3, 0.2, -0.1, 1.4;  // base frame
  m.nominal.segment(m.block_offset(m.marker_block(0)), 6) << 0.05, 0.0, 0.1,
      0.1, -0.2, 0.3;
  m.nominal.segment(m.block_offset(m.marker_block(1)), 3) << -0.04, 0.03, 0.12;
  return m;
}

}  // namespace testing
}  // namespace activecal

#endif  // ACTIVECAL_TESTS_TEST_UTIL_H_
