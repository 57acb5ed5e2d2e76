// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/estimation/identification.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>

#include "activecal/core/lattice.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/parameter_reduction.h"
#include "activecal/estimation/registration.h"
#include "activecal/io/urdf_robot.h"
#include "test_util.h"

namespace activecal {
namespace {

std::vector<Measurement> IdentifiedPumaMeasurements(int num_poses, double noise,
                                                    uint64_t seed) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::MatrixXd joints = testing::PumaLatticeSample(num_poses, seed);
  std::string error;
  std::vector<Measurement> out;
  EXPECT_TRUE(SimulateMeasurements(m, Puma560TrueParameters(),
                                   MeasurementPlan(joints), {noise, 0.0},
                                   seed + 1000, &out, &error))
      << error;
  return out;
}

// m identified from data, starting at `start`.
IdentificationSummary Identified(
    const RobotModel& m, const std::vector<Measurement>& data,
    const Eigen::VectorXd& start,
    const IdentificationOptions& options = IdentificationOptions()) {
  IdentificationSummary summary;
  Identify(m, data, start, options, &summary);
  return summary;
}

// The fit did not converge, and its message says `text`.
void ExpectRefused(const IdentificationSummary& summary,
                   const std::string& text) {
  EXPECT_NE(summary.termination_type, TerminationType::kConvergence);
  EXPECT_NE(summary.message.find(text), std::string::npos) << summary.message;
}

TEST(IdentificationTest, NoiseFreeRecoversTrueValues) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  IdentificationSummary summary;
  Identify(m, IdentifiedPumaMeasurements(30, 0.0, 3), m.nominal,
           IdentificationOptions(), &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.termination_type, TerminationType::kConvergence);
  EXPECT_LT((summary.parameters - truth).cwiseAbs().maxCoeff(), 1e-8)
      << summary.BriefReport();
  EXPECT_LT(summary.rms_m, 1e-9);
}

TEST(IdentificationTest, NoisyEstimatesWithinFourStd) {
  const RobotModel m = Puma560PaperModel();
  const Eigen::VectorXd truth = ExtractFree(m, Puma560TrueParameters());
  for (uint64_t seed : {1, 2, 3, 4}) {
    IdentificationSummary summary;
    Identify(m, IdentifiedPumaMeasurements(30, 0.01, seed), m.nominal,
             IdentificationOptions(), &summary);
    ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
        << summary.message;
    ASSERT_EQ(summary.estimates.size(), 27);
    for (int k = 0; k < 27; ++k) {
      EXPECT_LT(std::abs(summary.estimates[k] - truth[k]),
                4 * summary.standard_deviations[k])
          << summary.names[k] << " seed " << seed;
    }
    // sigma estimates the 1 cm noise (90 - 27 = 63 degrees of freedom).
    EXPECT_GT(summary.sigma_m, 0.006);
    EXPECT_LT(summary.sigma_m, 0.014);
  }
}

TEST(IdentificationTest, TooFewPosesIsReported) {
  const RobotModel m = Puma560PaperModel();
  const IdentificationSummary summary =
      Identified(m, IdentifiedPumaMeasurements(8, 0.01, 1), m.nominal);
  ExpectRefused(summary, "too few equations: 24");
  EXPECT_EQ(summary.termination_type, TerminationType::kFailure);
  EXPECT_EQ(summary.estimates.size(), 0);
}

TEST(IdentificationTest, ZeroDegreesOfFreedomIsRefused) {
  // 9 position poses, 27 rows for 27 parameters: the estimates fit the data
  // exactly and nothing is left to estimate the noise; never std 0.
  const RobotModel m = Puma560PaperModel();
  const IdentificationSummary summary =
      Identified(m, IdentifiedPumaMeasurements(9, 0.01, 1), m.nominal);
  ExpectRefused(summary, "0 degrees of freedom");
  EXPECT_EQ(summary.standard_deviations.size(), 0);
}

TEST(IdentificationTest, ExactDataFlagsNoOutliers) {
  // Noise-free data: the median residual row is ~0, which must not make
  // every rounding-level residual an outlier.
  const RobotModel m = Puma560PaperModel();
  IdentificationSummary summary;
  IdentificationOptions options;
  options.robust_loss = RobustLoss::kHuber;
  options.robust_scale_m = 0.001;
  Identify(m, IdentifiedPumaMeasurements(30, 0.0, 3), m.nominal, options,
           &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_TRUE(summary.outliers.empty()) << summary.outliers.size();
}

TEST(IdentificationTest, StartingAtTheSolutionCountsZeroIterations) {
  const RobotModel m = Puma560PaperModel();
  IdentificationSummary summary;
  Identify(m, IdentifiedPumaMeasurements(30, 0.0, 3), Puma560TrueParameters(),
           IdentificationOptions(), &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_GE(summary.iterations, 0);
}

TEST(IdentificationTest, UnidentifiableParametersAreNamed) {
  // Tool z and L6.d both move the point along the same axis (L6 has
  // alpha = 0): together they are not identifiable.
  RobotModel m = Puma560PaperModel();
  m.markers[0].free[2] = true;
  const IdentificationSummary summary =
      Identified(m, IdentifiedPumaMeasurements(30, 0.01, 1), m.nominal);
  ExpectRefused(summary, "rank 27 < 28");
  EXPECT_NE(summary.message.find("L6.d"), std::string::npos);
  EXPECT_NE(summary.message.find("tool.z"), std::string::npos);
}

TEST(IdentificationTest, BadInputIsReportedNotCrashed) {
  const RobotModel m = Puma560PaperModel();
  std::vector<Measurement> data = IdentifiedPumaMeasurements(30, 0.01, 1);
  data[4].position[1] = std::nan("");
  const IdentificationSummary summary = Identified(m, data, m.nominal);
  EXPECT_EQ(summary.termination_type, TerminationType::kUserFailure);
  EXPECT_NE(summary.message.find("measurement 4"), std::string::npos)
      << summary.message;
  data = IdentifiedPumaMeasurements(30, 0.01, 1);
  data[7].joints.resize(5);
  ExpectRefused(Identified(m, data, m.nominal),
                "measurement 7: joints: expected 6 joint values");
  data = IdentifiedPumaMeasurements(30, 0.01, 1);
  data[2].joints[0] = std::nan("");
  ExpectRefused(Identified(m, data, m.nominal), "measurement 2");
  Eigen::VectorXd initial = m.nominal;
  initial[5] = std::numeric_limits<double>::infinity();
  ExpectRefused(Identified(m, IdentifiedPumaMeasurements(30, 0.01, 1), initial),
                "initial values");
  ExpectRefused(Identified(m, std::vector<Measurement>{}, m.nominal),
                "too few equations: 0");
}

TEST(IdentificationTest, JointGainsAreRecovered) {
  // The PUMA with its six joint gains free as well (33 parameters); the
  // true gains differ from 1.
  RobotModel m = Puma560PaperModel();
  for (Link& l : m.links) l.free[kGain] = true;
  Eigen::VectorXd truth = Puma560TrueParameters();
  const double gains[6] = {1.002, 0.995, 1.01, 0.99, 1.005, 0.98};
  for (int j = 0; j < 6; ++j) truth[6 * (j + 1) + kGain] = gains[j];
  Random random(9);
  const Eigen::MatrixXd joints = testing::RandomJointRows(m, 60, &random);
  std::vector<Measurement> data;
  std::string error;
  ASSERT_TRUE(SimulateMeasurements(m, truth, MeasurementPlan(joints), {}, 1,
                                   &data, &error));
  IdentificationSummary summary;
  Identify(m, data, m.nominal, IdentificationOptions(), &summary);
  ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
      << summary.message;
  EXPECT_EQ(summary.num_free, 33);
  EXPECT_LT((summary.parameters - truth).cwiseAbs().maxCoeff(), 1e-8)
      << summary.BriefReport();
}

TEST(IdentificationTest, MixedModelRedundanciesAreNamed) {
  // Every parameter of every link free, as a first-time user might write:
  // the analysis must name the overlapping ones rather than solve.
  const RobotModel m = testing::MixedModel();
  Random random(9);
  const Eigen::MatrixXd joints = testing::RandomJointRows(m, 60, &random);
  std::vector<Measurement> data;
  std::string error;
  ASSERT_TRUE(SimulateMeasurements(m, m.nominal, MeasurementPlan(joints), {}, 1,
                                   &data, &error));
  const IdentificationSummary summary = Identified(m, data, m.nominal);
  ExpectRefused(summary, "not identifiable");
  EXPECT_GT(summary.identifiability.unidentifiable.size(), 0u);
  EXPECT_EQ(summary.identifiability.num_free - summary.identifiability.rank,
            static_cast<int>(summary.identifiability.unidentifiable.size()));
}

}  // namespace
}  // namespace activecal

namespace activecal {
namespace {

// `xml` with every number of every xyz="..." and rpy="..." attribute
// rewritten by `f`.
std::string RewriteOrigins(const std::string& xml,
                           const std::function<double(double)>& f) {
  static const std::regex attribute(R"((xyz|rpy)="([^"]*)\")");
  std::string out;
  auto begin = xml.cbegin();
  for (std::sregex_iterator it(xml.begin(), xml.end(), attribute), end;
       it != end; ++it) {
    out.append(begin, (*it)[0].first);
    std::istringstream numbers((*it)[2].str());
    std::string text;
    double v;
    while (numbers >> v) {
      char buffer[40];
      std::snprintf(buffer, sizeof(buffer), "%.17g", f(v));
      text += (text.empty() ? "" : " ") + std::string(buffer);
    }
    out += (*it)[1].str() + "=\"" + text + "\"";
    begin = (*it)[0].second;
  }
  out.append(begin, xml.cend());
  return out;
}

// Multiples of pi/2 exact, rounding-level numbers zero.
double Exact(double v) {
  const double k = std::round(v / (M_PI / 2));
  if (std::abs(v - k * M_PI / 2) < 1e-7) return k * M_PI / 2;
  return std::abs(v) < 1e-8 ? 0.0 : v;
}

// As a file written with 9 decimals has it (pi/2 = 1.570796327), with 6
// (1.570796, common in hand-written URDFs) or with 4 (1.5708).
double Rounded(double v) { return std::round(Exact(v) * 1e9) / 1e9; }
double Rounded6(double v) { return std::round(Exact(v) * 1e6) / 1e6; }
double Rounded4(double v) { return std::round(Exact(v) * 1e4) / 1e4; }

std::vector<Measurement> Plan(const RobotModel& m, MeasurementType type, int n,
                              Random* random) {
  std::vector<Measurement> plan(n);
  for (Measurement& x : plan) {
    x.type = type;
    x.joints = testing::RandomJoints(m, random);
    if (type == MeasurementType::kDistance) {
      x.joints2 = testing::RandomJoints(m, random);
    }
  }
  return plan;
}

// A ballbar on data/ur10e.urdf, whose pi/2 is written 1.570796327: "the
// Jacobian at the solution is rank deficient", while the same file with
// pi/2 exact converged. A parameter that has no effect with exact angles
// has a column ~1e-10 of the largest with rounded ones: noise, which the
// identifiability rule took for a direction of its own. The class: every
// shipped robot, exact and rounded to 9 decimals, position, pose and
// distance data, full set: the same parameters kept and a converged fit
// with its covariance. Rounded to 6 decimals (3.3e-7 off) the UR10e's B.z
// and shoulder_lift_joint.y were both kept under the former tolerance
// (1e-7) and every URDF robot's fit failed "rank 27 < 28"
// (kRedundancyTolerance); with 4 decimals (3.7e-6 off) as many are kept.
TEST(IdentifiabilityTest, RoundedRobotFilesKeepTheSameParametersAndConverge) {
  struct Shipped {
    const char* file;
    const char* tip;
  };
  for (const Shipped& robot :
       {Shipped{"ur10e.urdf", "tool0"}, Shipped{"ur10.urdf", "tool0"},
        Shipped{"kuka_iiwa14.urdf", "flange"}, Shipped{"puma560.yaml", ""}}) {
    std::string xml, error;
    const std::string path = std::string(ACTIVECAL_DATA_DIR) + "/" + robot.file;
    const bool urdf =
        std::string(robot.file).find(".urdf") != std::string::npos;
    if (urdf) {
      std::ifstream in(path);
      xml.assign(std::istreambuf_iterator<char>(in), {});
      ASSERT_FALSE(xml.empty()) << path;
    }
    for (MeasurementType type :
         {MeasurementType::kPosition, MeasurementType::kPose,
          MeasurementType::kDistance}) {
      constexpr int kCopies = 4;
      double (*const rounding[kCopies])(double) = {Exact, Rounded, Rounded6,
                                                   Rounded4};
      const char* const copy_name[kCopies] = {"exact", "9 decimals",
                                              "6 decimals", "4 decimals"};
      std::vector<std::string> kept[kCopies];
      for (int copy = 0; copy < kCopies; ++copy) {
        const auto f = rounding[copy];
        RobotModel m;
        if (urdf) {
          RobotDescription d;
          UrdfChainOptions chain;
          chain.tip_link = robot.tip;
          ASSERT_TRUE(ParseUrdfRobot(RewriteOrigins(xml, f), robot.file, chain,
                                     &d, &error))
              << error;
          m = d.model;
          // A reflector or target off the flange.
          m.nominal.segment(m.block_offset(m.marker_block(0)), 3) << 0.05,
              -0.03, 0.12;
        } else {
          m = Puma560PaperModel();
          const double scale = copy == 2 ? 1e6 : copy == 3 ? 1e4 : 1e9;
          for (int i = 0; i < m.num_parameters(); ++i) {
            m.nominal[i] = std::round(m.nominal[i] * scale) / scale;
          }
        }
        const std::string what = std::string(robot.file) + " " +
                                 copy_name[copy] + " " +
                                 MeasurementTypeName(type);
        Random random(11);
        Eigen::VectorXd truth = m.nominal;
        if (m.base.convention == LinkConvention::kFrame) {
          truth.head(6) << 1.5, -0.4, 0.2, 0.01, -0.02, 0.7;
        }
        for (int i = m.block_offset(1); i < m.block_offset(m.marker_block(0));
             ++i) {
          if (m.Kind(i) != ParameterKind::kGain) {
            truth[i] += 2e-4 * random.Gaussian();
          }
        }
        std::vector<Measurement> data;
        ASSERT_TRUE(SimulateMeasurements(
            m, truth,
            Plan(m, type, type == MeasurementType::kDistance ? 80 : 40,
                 &random),
            {1e-5, 1e-5}, 12, &data, &error))
            << error;
        Eigen::VectorXd start = m.nominal;
        if (m.base.convention == LinkConvention::kFrame &&
            type != MeasurementType::kDistance) {
          RegistrationSummary registration;
          ASSERT_TRUE(RegisterBaseFrame(m, data, &start, &registration))
              << what;
        }
        std::vector<HeldParameter> dropped;
        ASSERT_TRUE(testing::ReduceModel(ParameterSet::kFull, data, 1.0, &m,
                                         &start, &dropped, &error))
            << what << ": " << error;
        IdentificationSummary fit;
        Identify(m, data, start, IdentificationOptions(), &fit);
        EXPECT_EQ(fit.termination_type, TerminationType::kConvergence)
            << what << ": " << fit.message;
        kept[copy] = m.FreeParameterNames();
      }
      for (int copy = 1; copy < kCopies; ++copy) {
        const std::string what = std::string(robot.file) + " " +
                                 copy_name[copy] + " " +
                                 MeasurementTypeName(type);
        if (copy < 3) {
          EXPECT_EQ(kept[0], kept[copy]) << what;
        } else {
          // 4 decimals: as many parameters, converged; a ballbar (no base
          // frame) may keep the other one of a pair that 3.7e-6 separates
          // (shoulder_lift_joint.y for .z).
          EXPECT_EQ(kept[0].size(), kept[copy].size()) << what;
        }
      }
    }
  }
}

}  // namespace
}  // namespace activecal
