// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Robot description files (YAML) and the workflow's CSV files: the shipped
// PUMA file equals the built-in model, round trips are exact, and every
// malformed input is answered with file, line and field.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_file.h"
#include "activecal/io/targets_csv.h"
#include "test_util.h"

namespace activecal {
namespace {

const std::string kPumaFile = std::string(ACTIVECAL_DATA_DIR) + "/puma560.yaml";

void ExpectSameStructure(const RobotModel& a, const RobotModel& b) {
  ASSERT_EQ(a.num_joints(), b.num_joints());
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.ParameterNames(), b.ParameterNames());
  EXPECT_EQ(a.FreeParameterIndices(), b.FreeParameterIndices());
  for (int blk = 0; blk <= a.num_joints(); ++blk) {
    EXPECT_EQ(a.link(blk).convention, b.link(blk).convention) << blk;
    EXPECT_EQ(a.link(blk).joint_type, b.link(blk).joint_type) << blk;
    if (blk > 0) {
      EXPECT_EQ(a.link(blk).joint_min, b.link(blk).joint_min) << blk;
      EXPECT_EQ(a.link(blk).joint_max, b.link(blk).joint_max) << blk;
    }
  }
}

TEST(RobotFileTest, ShippedPumaFileIsExactlyTheBuiltInModel) {
  RobotDescription robot;
  std::string error;
  ASSERT_TRUE(LoadRobotFile(kPumaFile, &robot, &error)) << error;
  const RobotModel builtin = Puma560PaperModel();
  ExpectSameStructure(robot.model, builtin);
  // Bit for bit, so every result computed from the file is the same.
  EXPECT_EQ(robot.model.nominal, builtin.nominal);
  EXPECT_EQ(robot.true_parameters, Puma560TrueParameters());
  EXPECT_EQ(robot.angle_unit, AngleUnit::kRadian);
}

TEST(RobotFileTest, RoundTripInRadiansIsExactAndInDegreesClose) {
  const RobotModel m = testing::MixedModel();
  Eigen::VectorXd truth = m.nominal;
  truth[2] += 0.001;
  for (AngleUnit unit : {AngleUnit::kRadian, AngleUnit::kDegree}) {
    RobotFileOptions options;
    options.angle_unit = unit;
    options.true_parameters = truth;
    options.comment = "two\nlines";
    RobotDescription back;
    std::string text;
    ASSERT_TRUE(testing::RobotFileRoundTrip(m, m.nominal, options, "mem", &back,
                                            &text));
    ExpectSameStructure(back.model, m);
    if (unit == AngleUnit::kRadian) {
      EXPECT_EQ(back.model.nominal, m.nominal);
      EXPECT_EQ(back.true_parameters, truth);
    } else {
      EXPECT_LT((back.model.nominal - m.nominal).cwiseAbs().maxCoeff(), 1e-14);
      EXPECT_LT((back.true_parameters - truth).cwiseAbs().maxCoeff(), 1e-14);
    }
  }
}

TEST(RobotFileTest, DegreesAndDefaults) {
  const std::string text = R"(name: two_link
angle_unit: deg
links:
  - convention: standard_dh
    joint: revolute
    limits: [-90, 90]
    gamma: 0
    alpha: 90
    a: 0.5
    d: 0.1
    free: [a, d]
  - convention: modified_dh
    joint: prismatic
    limits: [0, 0.3]
    gamma: 0
    alpha: 0
    a: 0.2
    d: 0
    gain: 1.01
    free: [gain]
)";
  RobotDescription r;
  std::string error;
  ASSERT_TRUE(ParseRobotDescription(text, "two.yaml", &r, &error)) << error;
  EXPECT_EQ(r.model.num_joints(), 2);
  EXPECT_DOUBLE_EQ(r.model.nominal[6 + kAlpha], M_PI / 2);
  EXPECT_DOUBLE_EQ(r.model.links[0].joint_max, M_PI / 2);
  EXPECT_DOUBLE_EQ(r.model.links[1].joint_max, 0.3);  // metres, not degrees
  EXPECT_DOUBLE_EQ(r.model.nominal[12 + kGain], 1.01);
  EXPECT_EQ(r.model.FreeParameterNames(),
            (std::vector<std::string>{"L1.a", "L1.d", "L2.gain"}));
  EXPECT_EQ(r.true_parameters.size(), 0);  // no true: entries
}

struct BadYaml {
  const char* what;
  std::string text;
  const char* message;  // expected inside the error
};

TEST(RobotFileTest, MalformedFilesNameFileLineAndField) {
  const std::string link =
      "  - convention: standard_dh\n    joint: revolute\n    limits: [-1, "
      "1]\n    gamma: 0\n    alpha: 0\n    a: 0.5\n    d: 0\n";
  const std::string head = "name: r\nangle_unit: rad\nlinks:\n";
  const std::vector<BadYaml> cases = {
      {"not YAML", "name: [1, 2\n", "f.yaml:2:1: not valid YAML"},
      {"top is a list", "- 1\n- 2\n", "f.yaml:1:1: expected a mapping"},
      {"missing name", "angle_unit: rad\nlinks: []\n", "name: missing"},
      {"bad unit", "name: r\nangle_unit: grad\nlinks:\n",
       "f.yaml:2:13: angle_unit: expected 'rad' or 'deg', got 'grad'"},
      {"no links", "name: r\nangle_unit: rad\nlinks: []\n",
       "links: expected a non-empty list"},
      {"unknown top field", (head + link + "colour: red\n"),
       "f.yaml:11:1: colour: unknown field"},
      {"typo in a link", (head + link + "    alfa: 1\n"),
       "f.yaml:11:5: links[0].alfa: unknown field"},
      {"bad number",
       (head + "  - convention: standard_dh\n    joint: revolute\n    "
               "limits: [-1, 1]\n    gamma: 0\n    alpha: abc\n    a: 0.5\n "
               "   d: 0\n"),
       "f.yaml:8:12: links[0].alpha: expected a number, got 'abc'"},
      {"NaN value",
       (head + "  - convention: standard_dh\n    joint: revolute\n    "
               "limits: [-1, 1]\n    gamma: .nan\n    alpha: 0\n    a: 0.5\n "
               "   d: 0\n"),
       "links[0].gamma: expected a number, got '.nan'"},
      {"infinite value",
       (head + "  - convention: standard_dh\n    joint: revolute\n    "
               "limits: [-1, 1]\n    gamma: 1e999\n    alpha: 0\n    a: "
               "0.5\n    d: 0\n"),
       "links[0].gamma: must be finite"},
      {"missing value",
       (head + "  - convention: standard_dh\n    joint: revolute\n    "
               "limits: [-1, 1]\n    gamma: 0\n    alpha: 0\n    d: 0\n"),
       "links[0].a: missing"},
      {"bad convention",
       (head + "  - convention: dh\n    joint: revolute\n    limits: [-1, "
               "1]\n    gamma: 0\n    alpha: 0\n    a: 0\n    d: 0\n"),
       "f.yaml:4:17: links[0].convention: expected standard_dh, modified_dh, "
       "hayati, urdf or frame, got 'dh'"},
      {"bad joint",
       (head + "  - convention: hayati\n    joint: spherical\n    limits: "
               "[-1, 1]\n    gamma: 0\n    alpha: 0\n    a: 0\n    d: 0\n    "
               "beta: 0\n"),
       "links[0].joint: expected revolute or prismatic, got 'spherical'"},
      {"empty limits",
       (head + "  - convention: standard_dh\n    joint: revolute\n    "
               "limits: [1, -1]\n    gamma: 0\n    alpha: 0\n    a: 0\n    "
               "d: 0\n"),
       "links[0].limits: min 1 is above max -1"},
      {"limits not a pair",
       (head + "  - convention: standard_dh\n    joint: revolute\n    "
               "limits: 3\n    gamma: 0\n    alpha: 0\n    a: 0\n    d: "
               "0\n"),
       "f.yaml:6:13: links[0].limits: expected [min, max]"},
      {"unknown free parameter", (head + link + "    free: [a, theta]\n"),
       "f.yaml:11:15: links[0].free: 'theta' is not a parameter of this "
       "block"},
      {"beta on a DH link", (head + link + "    beta: 0.1\n"),
       "beta is a Hayati parameter"},
      {"bad true value", (head + link + "    true: {a: x}\n"),
       "links[0].true.a: expected a number, got 'x'"},
      {"base gain",
       (head + link +
        "base:\n  convention: standard_dh\n  "
        "gamma: 0\n  alpha: 0\n  a: 0\n  d: 0\n  "
        "gain: 1\n"),
       "base.gain: unknown field"},
      {"tool typo", (head + link + "tool:\n  x: 0\n  w: 1\n"),
       "f.yaml:13:3: tool.w: unknown field"},
  };
  for (const BadYaml& c : cases) {
    RobotDescription r;
    std::string error;
    EXPECT_FALSE(ParseRobotDescription(c.text, "f.yaml", &r, &error)) << c.what;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.what << "\n  got: " << error << "\n  want: " << c.message;
  }
  RobotDescription r;
  std::string error;
  EXPECT_FALSE(LoadRobotFile("/nonexistent/robot.yaml", &r, &error));
  EXPECT_EQ(error, "/nonexistent/robot.yaml: cannot open the robot file");
}

TEST(PosesCsvTest, RoundTripAndDegreeOnlyFiles) {
  const RobotModel m = testing::MixedModel();  // joint 3 is prismatic
  Random random(1);
  PoseList poses;
  poses.joints.resize(5, m.num_joints());
  for (int i = 0; i < 5; ++i) {
    poses.joints.row(i) = testing::RandomJoints(m, &random).transpose();
    poses.pose_indices.push_back(100 + i);
  }
  const std::string text = PosesCsvText(m, poses);
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "pose_index,q1_rad,q2_rad,q3_m,q4_rad,q1_deg,q2_deg,q3_mm,q4_deg");
  PoseList back;
  std::string error;
  ASSERT_TRUE(ParsePosesCsv(text, "p.csv", m, true, &back, &error)) << error;
  EXPECT_EQ(back.joints, poses.joints);
  EXPECT_EQ(back.pose_indices, poses.pose_indices);
  // Only the pendant units, with a comment line and spaces.
  ASSERT_TRUE(ParsePosesCsv(
      "# from the pendant\nq1_deg, q2_deg, q3_mm, q4_deg\n90, -45, 100, 0\n",
      "p.csv", m, true, &back, &error))
      << error;
  EXPECT_DOUBLE_EQ(back.joints(0, 0), M_PI / 2);
  EXPECT_DOUBLE_EQ(back.joints(0, 2), 0.1);
  EXPECT_EQ(back.pose_indices, std::vector<int64_t>{0});
}

struct BadCsv {
  const char* what;
  std::string text;
  const char* message;
};

// Every case refused by parse(text, &error) with its message in the error.
template <typename Parse>
void ExpectRefused(const std::vector<BadCsv>& cases, Parse parse) {
  for (const BadCsv& c : cases) {
    std::string error;
    EXPECT_FALSE(parse(c.text, &error)) << c.what;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.what << "\n  got: " << error << "\n  want: " << c.message;
  }
}

TEST(PosesCsvTest, MalformedFilesNameLineAndColumn) {
  const RobotModel m = testing::MixedModel();
  const std::string h = "q1_rad,q2_rad,q3_m,q4_rad\n";
  const std::vector<BadCsv> cases = {
      {"empty", "", "p.csv: empty file: no header line"},
      {"header only", h, "p.csv:1: header: no poses after the header"},
      {"missing joint", "q1_rad,q2_rad,q3_m\n0,0,0.1\n",
       "p.csv:1: header: the header has neither 'q4_rad' nor 'q4_deg' for "
       "joint 4"},
      {"short row", h + "0,0,0.1,0\n0,0,0.1\n",
       "p.csv:3: row: expected 4 fields as in the header, got 3"},
      {"not a number", h + "0,zero,0.1,0\n",
       "p.csv:2: q2_rad: expected a number, got 'zero'"},
      {"NaN", h + "0,nan,0.1,0\n", "p.csv:2: q2_rad: must be finite"},
      {"empty field", h + "0,,0.1,0\n", "p.csv:2: q2_rad: empty"},
      {"out of range", h + "0,0,0.5,0\n",
       "p.csv:2: row: joint 3 (L3) value 0.5 m is outside its range [0, 0.4] "
       "m"},
      {"duplicate", h + "0,0,0.1,0\n0.1,0,0.1,0\n0,0,0.1,0\n",
       "p.csv:4: row: duplicate pose: the same joint values as line 2"},
      {"disagreeing units",
       "q1_rad,q1_deg,q2_rad,q3_m,q4_rad\n0.1,90,0,0.1,0\n",
       "p.csv:2: row: q1_rad = 0.1 and q1_deg disagree"},
      {"repeated column", "q1_rad,q1_rad\n",
       "p.csv:1: header: header names column "
       "'q1_rad' twice"},
      {"bad pose_index", "pose_index," + h + "1.5,0,0,0.1,0\n",
       "p.csv:2: pose_index: expected an integer >= 0"},
      // Issue 26: a pool's labels were taken twice silently.
      {"duplicate pose_index",
       "pose_index," + h + "7,0,0,0.1,0\n8,0.1,0,0.1,0\n7,0.2,0,0.1,0\n",
       "p.csv:4: pose_index: 7 is also the label of line 2 (the labels of a "
       "pool name its poses, each once)"},
  };
  ExpectRefused(cases, [&](const std::string& text, std::string* reason) {
    PoseList poses;
    return ParsePosesCsv(text, "p.csv", m, true, &poses, reason);
  });
  PoseList poses;
  std::string error;
  EXPECT_FALSE(ReadPosesCsv("/nonexistent.csv", m, true, &poses, &error));
  EXPECT_EQ(error, "/nonexistent.csv: cannot open the file");
  // A program (not a pool) may repeat a label.
  EXPECT_TRUE(ParsePosesCsv("pose_index," + h + "7,0,0,0.1,0\n7,0.1,0,0.1,0\n",
                            "p.csv", m, false, &poses, &error))
      << error;
}

// Issue 26, item 18: the Python module wrote labels every reader refuses
// (write_poses(pose_indices=[-1, ...])) and took a pool's labels twice.
// One library check, at both edges of the range and for repeats.
TEST(PosesCsvTest, PoseLabelsAreCheckedBeforeTheyAreWritten) {
  std::string error;
  EXPECT_TRUE(CheckPoseIndices({}, true, &error));
  EXPECT_TRUE(CheckPoseIndices({0, kMaxPoseIndex, 3}, true, &error)) << error;
  EXPECT_FALSE(CheckPoseIndices({0, -1}, false, &error));
  EXPECT_EQ(error,
            "pose_indices[1] = -1: a pose label must be an integer in [0, "
            "9e15] (the files' pose_index; every reader refuses others)");
  EXPECT_FALSE(CheckPoseIndices({kMaxPoseIndex + 1}, false, &error));
  EXPECT_NE(error.find("pose_indices[0] = 9000000000000001: a pose label"),
            std::string::npos)
      << error;
  EXPECT_TRUE(CheckPoseIndices({4, 5, 4}, false, &error));
  EXPECT_FALSE(CheckPoseIndices({4, 5, 4}, true, &error));
  EXPECT_EQ(error,
            "pose_indices[2] = 4, the same label as pose_indices[0]: the "
            "labels of a pool name its poses, each once");
  // What passes the check reads back; the largest label too.
  const RobotModel m = testing::MixedModel();
  PoseList poses;
  poses.joints = Eigen::MatrixXd::Zero(2, 4);
  poses.joints(0, 2) = poses.joints(1, 2) = 0.1;
  poses.joints(1, 0) = 0.2;
  poses.pose_indices = {kMaxPoseIndex, 0};
  ASSERT_TRUE(CheckPoseIndices(poses.pose_indices, true, &error));
  PoseList back;
  ASSERT_TRUE(
      ParsePosesCsv(PosesCsvText(m, poses), "p.csv", m, true, &back, &error))
      << error;
  EXPECT_EQ(back.pose_indices, poses.pose_indices);
}

TEST(MeasurementsCsvTest, MixedRoundTripIsExact) {
  const RobotModel m = testing::MixedModel();
  Random random(2);
  std::vector<Measurement> plan;
  for (MeasurementType t :
       {MeasurementType::kPosition, MeasurementType::kPose,
        MeasurementType::kDistance, MeasurementType::kPosition}) {
    Measurement x;
    x.type = t;
    x.joints = testing::RandomJoints(m, &random);
    if (t == MeasurementType::kDistance) {
      x.joints2 = testing::RandomJoints(m, &random);
    }
    plan.push_back(x);
  }
  SimulationNoise noise;
  noise.position_m = 0.001;
  noise.rotation_rad = 0.001;
  std::vector<Measurement> data, back;
  std::string error;
  ASSERT_TRUE(
      SimulateMeasurements(m, m.nominal, plan, noise, 3, &data, &error));
  const std::string text = MeasurementsCsvText(m, data);
  ASSERT_TRUE(ParseMeasurementsCsv(text, "m.csv", m, &back, &error)) << error;
  ASSERT_EQ(back.size(), data.size());
  for (size_t i = 0; i < data.size(); ++i) {
    EXPECT_EQ(back[i].type, data[i].type);
    EXPECT_EQ(back[i].joints, data[i].joints);
    EXPECT_EQ(back[i].position, data[i].position);
    EXPECT_EQ(back[i].rotation, data[i].rotation);
    EXPECT_EQ(back[i].distance, data[i].distance);
    if (data[i].type == MeasurementType::kDistance) {
      EXPECT_EQ(back[i].joints2, data[i].joints2);
    }
  }
}

TEST(MeasurementsCsvTest, MalformedFilesNameLineAndColumn) {
  const RobotModel m = testing::MixedModel();
  const std::string h =
      "type,q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,"
      "q1_rad_2,q2_rad_2,q3_m_2,q4_rad_2,distance_m\n";
  const std::vector<BadCsv> cases = {
      {"no type column, no point", "q1_rad,q2_rad,q3_m,q4_rad\n0,0,0.1,0\n",
       "m.csv:1: header: a position row needs a measured point: the header has "
       "none "
       "of x_m,y_m,z_m; x_mm,y_mm,z_mm"},
      {"distance columns without a type column",
       "q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,q1_rad_2,q2_rad_2,q3_m_2,"
       "q4_rad_2,distance_m\n0,0,0.1,0,1,2,3,,,,,\n",
       "m.csv:1: header: the header has no column 'type'"},
      {"no rows", h, "m.csv:1: header: no measurements after the header"},
      {"bad type", h + "laser,0,0,0.1,0,1,2,3,,,,,,,,\n",
       "m.csv:2: type: expected position, pose, distance, point or plane, "
       "got 'laser'"},
      {"missing point", h + "position,0,0,0.1,0,1,,3,,,,,,,,\n",
       "m.csv:2: y_m: empty"},
      {"value a type does not have", h + "position,0,0,0.1,0,1,2,3,,,,,,,,4\n",
       "m.csv:2: distance_m: a position measurement has no such value"},
      {"pose without rotation columns",
       "type,q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m\npose,0,0,0.1,0,1,2,3\n",
       "m.csv:1: header: a pose row needs an orientation: the header has none "
       "of "
       "rx_rad,ry_rad,rz_rad; qw,qx,qy,qz"},
      {"rotation angle above pi", h + "pose,0,0,0.1,0,1,2,3,4,0,0,,,,,\n",
       "m.csv:2: row: measured rotation vector has angle 4 rad > pi"},
      {"second pose out of range",
       h + "distance,0,0,0.1,0,,,,,,,0,0,0.9,0,0.5\n",
       "m.csv:2: row: second pose: q3_m_2: 0.9 m is 0.5 m beyond joint 3 "
       "(L3)'s "
       "range [0, 0.4] m, more than the tolerance of 0.01 m"},
      {"negative distance", h + "distance,0,0,0.1,0,,,,,,,0,0,0.1,1,-0.5\n",
       "m.csv:2: row: measured distance must be finite and >= 0, got -0.5"},
      {"infinite", h + "position,0,0,0.1,0,1,2,inf,,,,,,,,\n",
       "m.csv:2: z_m: must be finite"},
  };
  ExpectRefused(cases, [&](const std::string& text, std::string* reason) {
    std::vector<Measurement> out;
    return ParseMeasurementsCsv(text, "m.csv", m, &out, reason);
  });
}

// ---------------------------------------------------------------------------
// Measurement files as devices export them (issue 18).

// Position, pose and distance measurements of the mixed model with
// standard deviations: isotropic, per axis, a distance's, a pose's sigma_rad.
std::vector<Measurement> MixedMeasurements(const RobotModel& m, int n,
                                           uint64_t seed) {
  Random random(seed);
  std::vector<Measurement> plan;
  for (int i = 0; i < n; ++i) {
    Measurement x;
    x.type = i % 3 == 0   ? MeasurementType::kPose
             : i % 3 == 1 ? MeasurementType::kPosition
                          : MeasurementType::kDistance;
    x.joints = testing::RandomJoints(m, &random);
    if (x.type == MeasurementType::kDistance) {
      x.joints2 = testing::RandomJoints(m, &random);
    }
    plan.push_back(x);
  }
  SimulationNoise noise;
  noise.position_m = 0.001;
  noise.rotation_rad = 0.001;
  std::vector<Measurement> data;
  std::string error;
  EXPECT_TRUE(
      SimulateMeasurements(m, m.nominal, plan, noise, seed, &data, &error))
      << error;
  for (size_t i = 0; i < data.size(); ++i) {
    Measurement& x = data[i];
    if (i % 4 == 0) continue;  // not given
    if (x.type == MeasurementType::kDistance) {
      x.sigma_m = Eigen::Vector3d(2e-5, 0, 0);
    } else if (i % 4 == 1) {
      x.sigma_m = Eigen::Vector3d::Constant(1e-5 * (1 + i % 5));
    } else {
      x.sigma_m = Eigen::Vector3d(1e-5, 2e-5, 3.5e-5);
    }
    if (x.type == MeasurementType::kPose) x.sigma_rad = 1e-4;
  }
  return data;
}

std::vector<MeasurementsCsvFormat> AllFormats() {
  std::vector<MeasurementsCsvFormat> formats;
  for (OrientationFormat o :
       {OrientationFormat::kRotationVector, OrientationFormat::kQuaternion,
        OrientationFormat::kRpyRad, OrientationFormat::kRpyDeg}) {
    for (int bits = 0; bits < 8; ++bits) {
      MeasurementsCsvFormat f;
      f.orientation = o;
      f.millimetres = bits & 1;
      f.joint_degrees = bits & 2;
      f.joint_names = bits & 4;
      formats.push_back(f);
    }
  }
  return formats;
}

double RotationDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  auto R = [](const Eigen::Vector3d& v) {
    const double angle = v.norm();
    return angle == 0 ? Eigen::Matrix3d::Identity()
                      : Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
  };
  return Eigen::AngleAxisd(R(a).transpose() * R(b)).angle();
}

TEST(MeasurementFormatsTest, EveryFormatRoundTrips) {
  const RobotModel m = testing::MixedModel();
  const std::vector<Measurement> data = MixedMeasurements(m, 24, 7);
  // SI: bit for bit, sigmas included.
  {
    std::vector<Measurement> back;
    std::string error;
    const std::string text = MeasurementsCsvText(m, data);
    EXPECT_NE(text.find(",sigma_m,sigma_x_m,sigma_y_m,sigma_z_m,sigma_rad\n"),
              std::string::npos)
        << text.substr(0, text.find('\n'));
    ASSERT_TRUE(ParseMeasurementsCsv(text, "m.csv", m, &back, &error)) << error;
    ASSERT_EQ(back.size(), data.size());
    for (size_t i = 0; i < data.size(); ++i) {
      EXPECT_EQ(back[i].sigma_m, data[i].sigma_m) << i;
      EXPECT_EQ(back[i].sigma_rad, data[i].sigma_rad) << i;
      EXPECT_EQ(back[i].position, data[i].position) << i;
      EXPECT_EQ(back[i].rotation, data[i].rotation) << i;
    }
  }
  for (const MeasurementsCsvFormat& f : AllFormats()) {
    const std::string text = MeasurementsCsvText(m, data, f);
    const std::string header = text.substr(0, text.find('\n'));
    const std::string what = header;
    EXPECT_NE(header.find(f.millimetres ? ",x_mm,y_mm,z_mm" : ",x_m,y_m,z_m"),
              std::string::npos)
        << what;
    EXPECT_NE(
        header.find(f.joint_names ? (f.joint_degrees ? ",L1_deg" : ",L1_rad")
                                  : (f.joint_degrees ? ",q1_deg" : ",q1_rad")),
        std::string::npos)
        << what;
    const char* orientation[] = {",rx_rad,", ",qw,qx,qy,qz,", ",roll_rad,",
                                 ",roll_deg,"};
    EXPECT_NE(header.find(orientation[static_cast<int>(f.orientation)]),
              std::string::npos)
        << what;
    std::vector<Measurement> back;
    MeasurementsCsvReport report;
    std::string error;
    ASSERT_TRUE(
        ParseMeasurementsCsv(text, "m.csv", m, {}, &back, &report, &error))
        << what << ": " << error;
    EXPECT_TRUE(report.warnings.empty() && report.notes.empty()) << what;
    ASSERT_EQ(back.size(), data.size()) << what;
    for (size_t i = 0; i < data.size(); ++i) {
      const Measurement& a = data[i];
      const Measurement& b = back[i];
      ASSERT_EQ(b.type, a.type) << what;
      EXPECT_LT((b.joints - a.joints).cwiseAbs().maxCoeff(), 1e-14) << what;
      EXPECT_LT((b.position - a.position).cwiseAbs().maxCoeff(), 1e-14) << what;
      EXPECT_LT((b.sigma_m - a.sigma_m).cwiseAbs().maxCoeff(), 1e-18) << what;
      EXPECT_NEAR(b.sigma_rad, a.sigma_rad, 1e-18) << what;
      EXPECT_NEAR(b.distance, a.distance, 1e-14) << what;
      if (a.type == MeasurementType::kPose) {
        EXPECT_LT(RotationDistance(a.rotation, b.rotation), 1e-14) << what;
      }
      if (a.type == MeasurementType::kDistance) {
        EXPECT_LT((b.joints2 - a.joints2).cwiseAbs().maxCoeff(), 1e-14) << what;
      }
    }
  }
}

TEST(MeasurementFormatsTest, EveryFormatGivesTheSameEstimates) {
  // The PUMA's 27 parameters from 6D poses and points, each written in
  // every format and identified: the same estimates to 1e-12.
  const RobotModel m = Puma560PaperModel();
  Random random(11);
  std::vector<Measurement> plan;
  for (int i = 0; i < 40; ++i) {
    Measurement x;
    x.type = i % 2 ? MeasurementType::kPose : MeasurementType::kPosition;
    x.joints = testing::RandomJoints(m, &random);
    plan.push_back(x);
  }
  SimulationNoise noise;
  noise.position_m = 1e-4;
  noise.rotation_rad = 1e-4;
  std::vector<Measurement> data;
  std::string error;
  ASSERT_TRUE(SimulateMeasurements(m, Puma560TrueParameters(), plan, noise, 5,
                                   &data, &error))
      << error;
  IdentificationOptions options;
  options.rotation_weight_m_per_rad = 0.1;
  IdentificationSummary reference;
  Identify(m, data, m.nominal, options, &reference);
  ASSERT_EQ(reference.termination_type, TerminationType::kConvergence)
      << reference.message;
  // The fit recovers the truth to the noise: a real identification.
  EXPECT_LT(
      (reference.parameters - Puma560TrueParameters()).cwiseAbs().maxCoeff(),
      0.01);
  IdentificationSummary warm_reference;
  Identify(m, data, reference.parameters, options, &warm_reference);
  ASSERT_EQ(warm_reference.termination_type, TerminationType::kConvergence)
      << warm_reference.message;
  double worst[4] = {0, 0, 0, 0}, worst_warm = 0;
  for (const MeasurementsCsvFormat& f : AllFormats()) {
    const std::string text = MeasurementsCsvText(m, data, f);
    const std::string what = text.substr(0, text.find('\n'));
    std::vector<Measurement> back;
    ASSERT_TRUE(ParseMeasurementsCsv(text, "m.csv", m, &back, &error))
        << what << ": " << error;
    IdentificationSummary summary;
    Identify(m, back, m.nominal, options, &summary);
    ASSERT_EQ(summary.termination_type, TerminationType::kConvergence)
        << what << ": " << summary.message;
    // The files' data agree with the SI file's to the last bit or two
    // (positions 1e-16 relative, rotations <= 2.2e-16 rad). From the
    // nominal start, Ceres then stops within its own tolerances of the
    // same minimum: measured 2.8e-14 for every format but the quaternion
    // files, 3.7e-12 there (whose rotations differ in fewer rows than the
    // RPY files': the solver's stopping point, not the data). 1e-11 is
    // checked from the nominal start; started at the reference estimate,
    // where only the data can differ, every format agrees to 1e-12.
    const double difference =
        (summary.estimates - reference.estimates).cwiseAbs().maxCoeff();
    worst[static_cast<int>(f.orientation)] =
        std::max(worst[static_cast<int>(f.orientation)], difference);
    EXPECT_LT(difference, 1e-11) << what;
    IdentificationSummary warm;
    Identify(m, back, reference.parameters, options, &warm);
    ASSERT_EQ(warm.termination_type, TerminationType::kConvergence)
        << what << ": " << warm.message;
    const double warm_difference =
        (warm.estimates - warm_reference.estimates).cwiseAbs().maxCoeff();
    worst_warm = std::max(worst_warm, warm_difference);
    EXPECT_LT(warm_difference, 1e-12) << what;
  }
  std::printf(
      "largest estimate difference from the SI file: rotation "
      "vector %.3g, quaternion %.3g, RPY rad %.3g, RPY deg %.3g; started "
      "at the estimate %.3g\n",
      worst[0], worst[1], worst[2], worst[3], worst_warm);
}

TEST(MeasurementFormatsTest, QuaternionAndRpyFollowTheirConventions) {
  const RobotModel m = testing::MixedModel();
  const std::string joints = "0,0,0.1,0";
  const double roll = 0.3, pitch = -0.7, yaw = 2.9;
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::AngleAxisd expected(R);
  const Eigen::Quaterniond quat(R);
  std::vector<Measurement> out;
  std::string error;
  const std::string rpy =
      "q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,roll_deg,"
      "pitch_deg,yaw_deg\n" +
      joints + ",1,2,3," + std::to_string(roll * 180 / M_PI) + "," +
      std::to_string(pitch * 180 / M_PI) + "," +
      std::to_string(yaw * 180 / M_PI) + "\n";
  // No type column and orientation columns: pose rows.
  ASSERT_TRUE(ParseMeasurementsCsv(rpy, "m.csv", m, &out, &error)) << error;
  ASSERT_EQ(out[0].type, MeasurementType::kPose);
  EXPECT_LT(
      RotationDistance(out[0].rotation, expected.angle() * expected.axis()),
      1e-7);  // std::to_string keeps 6 decimals of a degree
  // A quaternion: -q is the same rotation; a norm within 1e-3 of 1 is
  // normalised, beyond it refused.
  const std::string head =
      "type,q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,qw,qx,"
      "qy,qz\n";
  for (double sign : {1.0, -1.0}) {
    for (double norm : {1.0, 1.0009, 0.9991}) {
      char row[256];
      std::snprintf(row, sizeof(row), "pose,%s,1,2,3,%.17g,%.17g,%.17g,%.17g\n",
                    joints.c_str(), sign * norm * quat.w(),
                    sign * norm * quat.x(), sign * norm * quat.y(),
                    sign * norm * quat.z());
      ASSERT_TRUE(ParseMeasurementsCsv(head + row, "m.csv", m, &out, &error))
          << error;
      EXPECT_LT(
          RotationDistance(out[0].rotation, expected.angle() * expected.axis()),
          1e-14)
          << sign << " " << norm;
      EXPECT_LE(out[0].rotation.norm(), M_PI);
    }
    for (double norm : {1.0011, 0.9989, 0.0}) {
      char row[256];
      std::snprintf(row, sizeof(row), "pose,%s,1,2,3,%.17g,%.17g,%.17g,%.17g\n",
                    joints.c_str(), sign * norm * quat.w(),
                    sign * norm * quat.x(), sign * norm * quat.y(),
                    sign * norm * quat.z());
      EXPECT_FALSE(ParseMeasurementsCsv(head + row, "m.csv", m, &out, &error));
      EXPECT_NE(
          error.find("m.csv:2: row: qw,qx,qy,qz: the quaternion's norm is "),
          std::string::npos)
          << error;
      EXPECT_NE(error.find("not 1 (to 0.001): not a unit quaternion"),
                std::string::npos)
          << error;
    }
  }
}

TEST(MeasurementFormatsTest, WideMocapFormatEqualsItsLongForm) {
  const RobotModel m = testing::UrdfStyleModel();
  Random random(3);
  // Four frames, two markers each; marker 2 not seen in frame 2 and marker
  // 1 not seen in frame 4.
  std::string wide =
      "frame,time_s,q1_rad,q2_rad,q3_m,q4_rad,x1_mm,y1_mm,"
      "z1_mm,x2_mm,y2_mm,z2_mm\n";
  std::vector<Measurement> plan;
  for (int frame = 1; frame <= 4; ++frame) {
    const Eigen::VectorXd q = testing::RandomJoints(m, &random);
    wide += std::to_string(frame) + ",0." + std::to_string(frame);
    for (int j = 0; j < 4; ++j) wide += "," + std::to_string(q[j]);
    for (int k = 0; k < 2; ++k) {
      Measurement x;
      x.joints = Eigen::VectorXd(4);
      for (int j = 0; j < 4; ++j) x.joints[j] = std::stod(std::to_string(q[j]));
      x.marker = k;
      const Eigen::Vector3d p =
          MeasuredPoint(m, m.nominal, x.joints, k) * 1000.0;
      if ((frame == 2 && k == 1) || (frame == 4 && k == 0)) {
        wide += ",,,";
        continue;
      }
      char cells[128];
      std::snprintf(cells, sizeof(cells), ",%.4f,%.4f,%.4f", p.x(), p.y(),
                    p.z());
      wide += cells;
      for (int a = 0; a < 3; ++a) {
        x.position[a] = std::round(p[a] * 1e4) / 1e4 * 1e-3;
      }
      plan.push_back(x);
    }
    wide += "\n";
  }
  std::vector<Measurement> from_wide, from_long;
  MeasurementsCsvReport report;
  std::string error;
  ASSERT_TRUE(ParseMeasurementsCsv(wide, "mocap.csv", m, {}, &from_wide,
                                   &report, &error))
      << error;
  ASSERT_EQ(from_wide.size(), 6u);
  EXPECT_EQ(report.lines, std::vector<int>({2, 2, 3, 4, 4, 5}));
  ASSERT_EQ(report.notes.size(), 2u);
  EXPECT_EQ(report.notes[0],
            "mocap.csv: ignored 2 columns activecal does not read: frame, "
            "time_s");
  EXPECT_EQ(report.notes[1],
            "mocap.csv: 2 marker positions left empty (not seen) skipped: "
            "marker 1 in 1 row, marker 2 in 1 row");
  // The long form: one row per marker position, the marker column.
  const std::string long_text = MeasurementsCsvText(m, plan);
  EXPECT_EQ(long_text.rfind("type,marker,", 0), 0u);
  ASSERT_TRUE(
      ParseMeasurementsCsv(long_text, "long.csv", m, &from_long, &error))
      << error;
  ASSERT_EQ(from_long.size(), from_wide.size());
  for (size_t i = 0; i < from_wide.size(); ++i) {
    EXPECT_EQ(from_wide[i].type, MeasurementType::kPosition);
    EXPECT_EQ(from_wide[i].marker, from_long[i].marker) << i;
    EXPECT_EQ(from_wide[i].joints, from_long[i].joints) << i;
    EXPECT_LT(
        (from_wide[i].position - from_long[i].position).cwiseAbs().maxCoeff(),
        1e-15)
        << i;
  }
}

// The mixed model's joint 3 is prismatic in [0, 0.4] m; the others revolute
// in [-2.5, 2.5] rad.
TEST(MeasurementFormatsTest, JointLimitToleranceIsCrossedBothWays) {
  const RobotModel m = testing::MixedModel();
  const std::string head = "q1_rad,q2_rad,q3_m,q4_deg,x_m,y_m,z_m\n";
  auto parse = [&](const std::string& rows, const MeasurementsCsvOptions& o,
                   MeasurementsCsvReport* report, std::string* error) {
    std::vector<Measurement> out;
    return ParseMeasurementsCsv(head + rows, "s.csv", m, o, &out, report,
                                error);
  };
  const double deg = 180 / M_PI;
  char rows[512];
  // Just inside: 9.99 mm above joint 3's upper limit in two rows, joint 4
  // 4.99 deg below its lower limit in one.
  std::snprintf(
      rows, sizeof(rows),
      "0,0,0.40999,0,1,2,3\n0,0,0.4005,%.17g,1,2,3\n0,0,0.2,0,1,2,3\n",
      -2.5 * deg - 4.99);
  MeasurementsCsvReport report;
  std::string error;
  ASSERT_TRUE(parse(rows, {}, &report, &error)) << error;
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0],
            "s.csv: 2 of 3 rows have joint readings beyond the joint limits, "
            "accepted within the tolerance (5 deg, 10 mm; strict limits "
            "refuse them): q3_m (joint 3 (L3)) up to 0.00999 m above its upper "
            "limit 0.4 m in 2 rows (first: line 2); q4_deg (joint 4 (L4)) up "
            "to 4.99 deg below its lower limit -143.239 deg in 1 row (first: "
            "line 3)");
  // Readings of one joint beyond both ends: each side on its own.
  ASSERT_TRUE(
      parse("0,0,0.403,0,1,2,3\n0,0,-0.001,0,1,2,3\n"
            "0,0,-0.002,0,1,2,3\n",
            {}, &report, &error))
      << error;
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find(
                ": q3_m (joint 3 (L3)) up to 0.003 m above its upper limit "
                "0.4 m in 1 row (first: line 2), up to 0.002 m below its "
                "lower limit 0 m in 2 rows (first: line 3)"),
            std::string::npos)
      << report.warnings[0];
  // Strict: the first reading beyond a limit is an error.
  MeasurementsCsvOptions strict;
  strict.strict_limits = true;
  EXPECT_FALSE(parse(rows, strict, &report, &error));
  EXPECT_EQ(error,
            "s.csv:2: q3_m: 0.40999 m is 0.00999 m beyond joint 3 (L3)'s "
            "range [0, 0.4] m (strict limits: no reading may lie outside the "
            "range)");
  // Just outside the tolerance.
  EXPECT_FALSE(parse("0,0,0.41001,0,1,2,3\n", {}, &report, &error));
  EXPECT_EQ(error,
            "s.csv:2: q3_m: 0.41001 m is 0.01001 m beyond joint 3 (L3)'s "
            "range [0, 0.4] m, more than the tolerance of 0.01 m for joint "
            "readings (wrong units, or a file of another robot?)");
  std::snprintf(rows, sizeof(rows), "0,0,0.2,%.17g,1,2,3\n", 2.5 * deg + 5.01);
  EXPECT_FALSE(parse(rows, {}, &report, &error));
  EXPECT_NE(error.find("s.csv:2: q4_deg: 148.249 deg is 5.01 deg beyond "
                       "joint 4 (L4)'s range [-143.239, 143.239] deg, more "
                       "than the tolerance of 5 deg"),
            std::string::npos)
      << error;
  // A tighter tolerance from the options; a bad one is refused.
  MeasurementsCsvOptions tight;
  tight.limit_tolerance_m = 0.005;
  EXPECT_FALSE(parse("0,0,0.4051,0,1,2,3\n", tight, &report, &error));
  EXPECT_NE(error.find("more than the tolerance of 0.005 m"), std::string::npos)
      << error;
  for (double bad : {-1.0, 0.02, std::nan("")}) {
    tight.limit_tolerance_m = bad;  // a wider tolerance is refused too
    EXPECT_FALSE(parse("0,0,0.2,0,1,2,3\n", tight, &report, &error));
    EXPECT_NE(error.find("joint limit tolerances must be in [0, 0.0872665] "
                         "rad and [0, 0.01] m"),
              std::string::npos)
        << error;
  }
  // Within the ranges: no warning.
  ASSERT_TRUE(parse("0,0,0.4,0,1,2,3\n", {}, &report, &error)) << error;
  EXPECT_TRUE(report.warnings.empty());
  // The second pose of a distance is held to the same rule.
  const std::string dh =
      "type,q1_rad,q2_rad,q3_m,q4_rad,q1_rad_2,q2_rad_2,q3_m_2,q4_rad_2,"
      "distance_m\n";
  std::vector<Measurement> out;
  ASSERT_TRUE(ParseMeasurementsCsv(dh + "distance,0,0,0.1,0,0,0,0.405,0,0.5\n",
                                   "d.csv", m, {}, &out, &report, &error))
      << error;
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("up to 0.005 m above"), std::string::npos)
      << report.warnings[0];
  // It names the column the reading is in: the second pose's.
  EXPECT_NE(report.warnings[0].find(": q3_m_2 (joint 3 (L3)) up to 0.005 m"),
            std::string::npos)
      << report.warnings[0];
  ASSERT_TRUE(
      ParseMeasurementsCsv(dh + "distance,0,0,0.402,0,0,0,0.405,0,0.5\n",
                           "d.csv", m, {}, &out, &report, &error))
      << error;
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find(
                ": q3_m, q3_m_2 (joint 3 (L3)) up to 0.005 m above its upper "
                "limit 0.4 m in 1 row (first: line 2)"),
            std::string::npos)
      << report.warnings[0];
  EXPECT_FALSE(ParseMeasurementsCsv(dh + "distance,0,0,0.1,0,0,0,0.42,0,0.5\n",
                                    "d.csv", m, {}, &out, &report, &error));
  EXPECT_NE(error.find("d.csv:2: row: second pose: q3_m_2: 0.42 m is 0.02 m "
                       "beyond"),
            std::string::npos)
      << error;
  // CheckMeasurement (what Identify, EvaluateModel and the Jacobians apply)
  // holds joint readings to the same tolerance: the accepted reading goes
  // through, one just beyond the tolerance does not, nor NaN.
  Measurement beyond;
  beyond.joints = Eigen::Vector4d(0, 0, 0.40999, -2.5 - 4.99 * M_PI / 180);
  EXPECT_TRUE(CheckMeasurement(m, beyond, &error)) << error;
  beyond.joints[2] = 0.41001;
  EXPECT_FALSE(CheckMeasurement(m, beyond, &error));
  EXPECT_NE(error.find("joints: joint 3 (L3) value 0.41001 m is outside its "
                       "range [0, 0.4] m by more than the 0.01 m a measured "
                       "joint may lie beyond it"),
            std::string::npos)
      << error;
  beyond.joints[2] = 0.2;
  beyond.joints[3] = -2.5 - 5.01 * M_PI / 180;
  EXPECT_FALSE(CheckMeasurement(m, beyond, &error));
  EXPECT_NE(error.find("by more than the 5 deg a measured joint may lie"),
            std::string::npos)
      << error;
  beyond.joints[2] = NAN;
  EXPECT_FALSE(CheckMeasurement(m, beyond, &error));
  EXPECT_NE(error.find("joints: joint 3 (L3) value is not finite"),
            std::string::npos)
      << error;
}

TEST(MeasurementFormatsTest, UncertaintyColumns) {
  const RobotModel m = testing::MixedModel();
  std::vector<Measurement> out;
  std::string error;
  // U95 in mm: sigma = U95 / 2, on every axis.
  ASSERT_TRUE(ParseMeasurementsCsv(
      "q1_rad,q2_rad,q3_m,q4_rad,x_mm,y_mm,z_mm,u95_mm\n"
      "0,0,0.1,0,1000,2000,3000,0.03\n0,0,0.1,0,1000,2000,3000,\n",
      "m.csv", m, &out, &error))
      << error;
  EXPECT_LT((out[0].sigma_m - Eigen::Vector3d::Constant(0.015e-3)).norm(),
            1e-20);
  EXPECT_EQ(out[0].position, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(out[1].sigma_m, Eigen::Vector3d::Zero());  // empty: not given
  // Per axis in mm; sigma_deg on a pose.
  ASSERT_TRUE(ParseMeasurementsCsv(
      "q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,sigma_x_mm,"
      "sigma_y_mm,sigma_z_mm,sigma_deg\n0,0,0.1,0,1,2,3,0,0,0.1,0.01,0.02,0.04,"
      "0.5\n",
      "m.csv", m, &out, &error))
      << error;
  EXPECT_LT((out[0].sigma_m - Eigen::Vector3d(1e-5, 2e-5, 4e-5)).norm(), 1e-20);
  EXPECT_DOUBLE_EQ(out[0].sigma_rad, 0.5 * M_PI / 180);
  const std::string h =
      "type,q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,"
      "q1_rad_2,q2_rad_2,q3_m_2,q4_rad_2,distance_m,sigma_m,sigma_x_m,"
      "sigma_y_m,sigma_z_m,sigma_rad\n";
  // A distance's sigma_m is its own.
  ASSERT_TRUE(ParseMeasurementsCsv(
      h + "distance,0,0,0.1,0,,,,,,,0,0,0.2,0,0.5,0.00002,,,,\n", "m.csv", m,
      &out, &error))
      << error;
  EXPECT_EQ(out[0].sigma_m, Eigen::Vector3d(2e-5, 0, 0));
  const std::vector<BadCsv> cases = {
      {"zero sigma", h + "position,0,0,0.1,0,1,2,3,,,,,,,,,0,,,,\n",
       "m.csv:2: sigma_m: a standard deviation must be > 0, got 0 (leave the "
       "cell empty when it is not known)"},
      {"negative sigma", h + "position,0,0,0.1,0,1,2,3,,,,,,,,,,1,-1,1,\n",
       "m.csv:2: sigma_y_m: a standard deviation must be > 0, got -1"},
      {"infinite sigma", h + "position,0,0,0.1,0,1,2,3,,,,,,,,,inf,,,,\n",
       "m.csv:2: sigma_m: must be finite"},
      {"NaN sigma_rad", h + "pose,0,0,0.1,0,1,2,3,0,0,0,,,,,,,,,,nan\n",
       "m.csv:2: sigma_rad: must be finite, got 'nan'"},
      {"zero sigma_rad", h + "pose,0,0,0.1,0,1,2,3,0,0,0,,,,,,,,,,0\n",
       "m.csv:2: sigma_rad: a standard deviation must be > 0, got 0"},
      {"sigma_rad on a position",
       h + "position,0,0,0.1,0,1,2,3,,,,,,,,,,,,,1\n",
       "m.csv:2: sigma_rad: a position measurement has no such value"},
      {"per-axis sigma on a distance",
       h + "distance,0,0,0.1,0,,,,,,,0,0,0.2,0,0.5,,1,1,1,\n",
       "m.csv:2: sigma_x_m: a distance measurement has no such value"},
      {"two sigmas in a row", h + "position,0,0,0.1,0,1,2,3,,,,,,,,,1,1,1,1,\n",
       "m.csv:2: row: sigma_m and sigma_x_m,sigma_y_m,sigma_z_m: the row gives "
       "its "
       "standard deviation twice"},
      {"part of the axes", h + "position,0,0,0.1,0,1,2,3,,,,,,,,,,1,,1,\n",
       "m.csv:2: sigma_y_m: empty, but the row gives the rest of "
       "sigma_x_m,sigma_y_m,sigma_z_m; fill all or none"},
      {"U95 beside sigma",
       "q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,u95_m,sigma_m\n0,0,0.1,0,1,2,3,1,"
       "\n",
       "m.csv:1: header: the standard deviation is given both as sigma_m and "
       "as u95_m"},
      {"sigma in m beside axes in mm",
       "q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,sigma_m,sigma_x_mm,sigma_y_mm,"
       "sigma_z_mm\n0,0,0.1,0,1,2,3,1,,,\n",
       "m.csv:1: header: the standard deviation is given both as sigma_m and "
       "as "
       "sigma_x_mm,sigma_y_mm,sigma_z_mm"},
  };
  ExpectRefused(cases, [&](const std::string& text, std::string* reason) {
    return ParseMeasurementsCsv(text, "m.csv", m, &out, reason);
  });
}

TEST(MeasurementFormatsTest, ColumnsADeviceAddsAreListedOrRefused) {
  const RobotModel m = testing::MixedModel();
  const std::string text =
      "target,q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,temperature_C,humidity\n"
      "P1,0,0,0.1,0,1,2,3,20.5,40\nP2,0,0,0.2,0,1,2,3,20.6,41\n";
  std::vector<Measurement> out;
  MeasurementsCsvReport report;
  std::string error;
  ASSERT_TRUE(ParseMeasurementsCsv(text, "t.csv", m, {}, &out, &report, &error))
      << error;
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].joints[2], 0.2);
  ASSERT_EQ(report.notes.size(), 1u);
  EXPECT_EQ(report.notes[0],
            "t.csv: ignored 3 columns activecal does not read: target, "
            "temperature_C, humidity");
  MeasurementsCsvOptions strict;
  strict.columns_strict = true;
  EXPECT_FALSE(
      ParseMeasurementsCsv(text, "t.csv", m, strict, &out, &report, &error));
  EXPECT_EQ(error,
            "t.csv:1: header: columns 'target', 'temperature_C', 'humidity' "
            "activecal does not read (strict columns: every column must be "
            "one activecal reads)");
  // A known column the row's type does not use stays an error.
  EXPECT_FALSE(ParseMeasurementsCsv(
      "q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m,distance_m\n0,0,0.1,0,1,2,3,4\n",
      "t.csv", m, &out, &error));
  EXPECT_NE(error.find("t.csv:2: distance_m: a position measurement has no "
                       "such value; leave it empty"),
            std::string::npos)
      << error;
}

TEST(MeasurementFormatsTest, JointsByUrdfNameAndBadHeaders) {
  const RobotModel m = testing::UrdfStyleModel();  // joint1..joint4
  std::vector<Measurement> out;
  std::string error;
  ASSERT_TRUE(ParseMeasurementsCsv(
      "joint1_rad,joint2_deg,joint3_mm,joint4_rad,x_m,y_m,z_m\n"
      "0.1,90,50,0.2,1,2,3\n",
      "n.csv", m, &out, &error))
      << error;
  EXPECT_EQ(out[0].joints[0], 0.1);
  EXPECT_DOUBLE_EQ(out[0].joints[1], M_PI / 2);
  EXPECT_DOUBLE_EQ(out[0].joints[2], 0.05);
  const std::string j = "q1_rad,q2_rad,q3_m,q4_rad,";
  const std::vector<BadCsv> cases = {
      {"joint names mixed", "q1_rad,joint2_rad,q3_m,q4_rad,x_m,y_m,z_m\n",
       "n.csv:1: header: joints are named both q<j> ('q1_rad') and by joint "
       "name "
       "('joint2_rad'): a file uses one of the two"},
      {"metres and millimetres", j + "x_m,y_m,z_m,x_mm,y_mm,z_mm\n",
       "n.csv:1: header: the measured point is given both as x_m,y_m,z_m and "
       "as "
       "x_mm,y_mm,z_mm: a file holds one representation of each quantity"},
      {"part of a form", j + "x_mm,y_mm\n",
       "n.csv:1: header: the header has x_mm,y_mm but not z_mm (the measured "
       "point)"},
      {"rotation vector and quaternion",
       j + "x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,qw,qx,qy,qz\n",
       "n.csv:1: header: the orientation is given both as rx_rad,ry_rad,rz_rad "
       "and as "
       "qw,qx,qy,qz"},
      {"rpy in rad and deg",
       j + "x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad,roll_deg,pitch_deg,"
           "yaw_deg\n",
       "n.csv:1: header: the orientation is given both as "
       "roll_rad,pitch_rad,yaw_rad "
       "and as roll_deg,pitch_deg,yaw_deg"},
      {"distance in m and mm",
       "type," + j + "x_m,y_m,z_m,distance_m,distance_mm\n",
       "n.csv:1: header: the distance is given both as distance_m and as "
       "distance_mm"},
      {"wide and long point", j + "x_m,y_m,z_m,x1_m,y1_m,z1_m\n",
       "n.csv:1: header: the measured point is given both as x_m,y_m,z_m and "
       "as "
       "numbered markers (x1_m, ...)"},
      {"wide in m and mm", j + "x1_m,y1_m,z1_m,x2_mm,y2_mm,z2_mm\n",
       "n.csv:1: header: marker positions are given both in m and in mm "
       "('x2_mm')"},
      {"wide marker the model lacks", j + "x1_m,y1_m,z1_m,x3_m,y3_m,z3_m\n",
       "n.csv:1: header: column 'x3_m' is for marker 3, but the model has 2 "
       "marker(s)"},
      {"wide marker axis twice", j + "x1_m,y1_m,z1_m,x01_m\n",
       "n.csv:1: header: columns 'x1_m' and 'x01_m' both give marker 1's x"},
      {"wide marker without z", j + "x1_m,y1_m,z1_m,x2_m,y2_m\n",
       "n.csv:1: header: marker 2 has no column 'z2_m'"},
      {"wide with a marker column", "marker," + j + "x1_m,y1_m,z1_m\n",
       "n.csv:1: header: a 'marker' column and numbered marker columns (x1_m, "
       "...)"},
      {"wide pose row",
       "type," + j +
           "x1_m,y1_m,z1_m,rx_rad,ry_rad,rz_rad\npose,0,0,0,0,1,2,3,"
           "0,0,0\n",
       "n.csv:2: type: a file of numbered marker columns (x1_m, ...) holds "
       "position rows only, got 'pose'"},
      {"wide marker half seen", j + "x1_m,y1_m,z1_m\n0,0,0,0,1,,3\n",
       "n.csv:2: y1_m: empty, but marker 1's other coordinates are given"},
      {"no marker seen anywhere", j + "x1_m,y1_m,z1_m\n0,0,0,0,,,\n",
       "n.csv:1: header: no measurements: no marker was seen in any row"},
      {"joint named for a missing joint", "q5_rad," + j + "x_m,y_m,z_m\n",
       "n.csv:1: header: column 'q5_rad' is for joint 5"},
  };
  ExpectRefused(cases, [&](const std::string& text, std::string* reason) {
    return ParseMeasurementsCsv(text, "n.csv", m, &out, reason);
  });
}

// Issue 26, item 17: the targets CSV dropped the columns it did not know,
// among them start joints named by joint name and qw,qx,qy,qz, which the
// measurements CSV reads. It reads what the measurements CSV reads now:
// every format MeasurementsCsvText writes (joint names, pendant units, mm,
// quaternion, roll-pitch-yaw) read as targets gives the points, the
// orientations and the joints the measurements reader gives; the columns
// of neither (type, sigma_*) are named in a note, or refused with
// columns_strict.
TEST(TargetsCsvTest, ReadsWhatTheMeasurementsCsvReads) {
  const RobotModel m = testing::UrdfStyleModel();  // joint1..joint4
  std::vector<Measurement> poses;
  for (const Measurement& x : MixedMeasurements(m, 12, 5)) {
    if (x.type == MeasurementType::kPose) poses.push_back(x);
  }
  ASSERT_GE(poses.size(), 3u);
  for (const MeasurementsCsvFormat& format : AllFormats()) {
    const std::string text = MeasurementsCsvText(m, poses, format);
    std::vector<Measurement> measured;
    std::string error;
    ASSERT_TRUE(ParseMeasurementsCsv(text, "f.csv", m, &measured, &error))
        << error;
    TargetList targets;
    std::vector<std::string> notes;
    ASSERT_TRUE(ParseTargetsCsv(text, "f.csv", m, TargetsCsvOptions(), &targets,
                                &notes, &error))
        << error;
    ASSERT_EQ(targets.points.rows(), static_cast<int>(measured.size()));
    ASSERT_EQ(targets.rotation_vectors.rows(), targets.points.rows());
    ASSERT_EQ(targets.start_joints.rows(), targets.points.rows());
    for (size_t i = 0; i < measured.size(); ++i) {
      EXPECT_TRUE(targets.points.row(i).transpose() == measured[i].position);
      EXPECT_TRUE(targets.rotation_vectors.row(i).transpose() ==
                  measured[i].rotation);
      EXPECT_TRUE(targets.start_joints.row(i).transpose() ==
                  measured[i].joints);
    }
    // type and the standard deviations are measurements' columns only.
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0].rfind("f.csv: ignored ", 0), 0u) << notes[0];
    EXPECT_NE(notes[0].find("activecal does not read: type"), std::string::npos)
        << notes[0];
    TargetsCsvOptions strict;
    strict.columns_strict = true;
    EXPECT_FALSE(
        ParseTargetsCsv(text, "f.csv", m, strict, &targets, &notes, &error));
    EXPECT_NE(error.find("f.csv:1: header: columns 'type'"), std::string::npos)
        << error;
    EXPECT_NE(error.find("activecal does not read (strict columns"),
              std::string::npos)
        << error;
  }
  // A file of only known columns: no note, and strict reads it.
  TargetList targets;
  std::vector<std::string> notes = {"stale"};
  std::string error;
  TargetsCsvOptions strict;
  strict.columns_strict = true;
  ASSERT_TRUE(ParseTargetsCsv(
      "pose_index,x_mm,y_mm,z_mm,qw,qx,qy,qz,joint1_deg,joint2_rad,joint3_mm,"
      "joint4_rad\n7,1000,2000,-3,1,0,0,0,90,0.1,50,0.2\n",
      "t.csv", m, strict, &targets, &notes, &error))
      << error;
  EXPECT_TRUE(notes.empty());
  EXPECT_EQ(targets.pose_indices, (std::vector<int64_t>{7}));
  EXPECT_EQ(targets.points(0, 0), 1.0);
  EXPECT_EQ(targets.points(0, 2), -0.003);
  EXPECT_TRUE(targets.rotation_vectors.row(0).isZero(0));
  EXPECT_DOUBLE_EQ(targets.start_joints(0, 0), M_PI / 2);
  EXPECT_EQ(targets.start_joints(0, 2), 0.05);
  // And the measurements reader's messages.
  const std::vector<BadCsv> cases = {
      {"joint names mixed",
       "x_m,y_m,z_m,q1_rad,joint2_rad,q3_m,q4_rad\n1,2,3,0,0,0,0\n",
       "t.csv:1: header: joints are named both q<j> ('q1_rad') and by joint "
       "name "
       "('joint2_rad'): a file uses one of the two"},
      {"quaternion not unit", "x_m,y_m,z_m,qw,qx,qy,qz\n1,2,3,1,1,0,0\n",
       "t.csv:2: row: qw,qx,qy,qz: the quaternion's norm is 1.41421, not 1"},
      {"two orientations",
       "x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,qw,qx,qy,qz\n1,2,3,0,0,0,1,0,0,0\n",
       "t.csv:1: header: the orientation is given both as rx_rad,ry_rad,rz_rad "
       "and "
       "as qw,qx,qy,qz"},
      {"a joint missing by name",
       "x_m,y_m,z_m,joint1_rad,joint2_rad,joint4_rad\n1,2,3,0,0,0\n",
       "t.csv:1: header: the header has joint columns for joint 1 but not for "
       "joint 3 "
       "('joint3_m' or 'joint3_mm'): give every joint or none"},
      {"implausible length", "x_mm,y_mm,z_mm\n1e12,0,0\n",
       "t.csv:2: x_mm: 1e+12 mm is more than 1000 km"},
  };
  ExpectRefused(cases, [&](const std::string& text, std::string* reason) {
    return ParseTargetsCsv(text, "t.csv", m, &targets, reason);
  });
}

// The poses CSV names joints as the measurements CSV does: q<j> or the
// joint's name (item 17).
TEST(PosesCsvTest, JointsByJointName) {
  const RobotModel m = testing::UrdfStyleModel();  // joint1..joint4
  PoseList poses;
  std::string error;
  ASSERT_TRUE(
      ParsePosesCsv("pose_index,joint1_rad,joint2_deg,joint3_mm,joint4_rad\n3,"
                    "0.1,90,50,0.2\n",
                    "p.csv", m, false, &poses, &error))
      << error;
  EXPECT_EQ(poses.pose_indices, (std::vector<int64_t>{3}));
  EXPECT_EQ(poses.joints(0, 0), 0.1);
  EXPECT_DOUBLE_EQ(poses.joints(0, 1), M_PI / 2);
  EXPECT_DOUBLE_EQ(poses.joints(0, 2), 0.05);
  EXPECT_FALSE(ParsePosesCsv("q1_rad,joint2_rad,q3_m,q4_rad\n0,0,0,0\n",
                             "p.csv", m, false, &poses, &error));
  EXPECT_NE(
      error.find("p.csv:1: header: joints are named both q<j> ('q1_rad') and "
                 "by joint name ('joint2_rad')"),
      std::string::npos)
      << error;
  EXPECT_FALSE(ParsePosesCsv("joint1_rad,joint2_rad,joint4_rad\n0,0,0\n",
                             "p.csv", m, false, &poses, &error));
  EXPECT_NE(
      error.find("p.csv:1: header: the header has neither 'q3_m' nor 'q3_mm' "
                 "for joint 3, nor 'joint3_m' or 'joint3_mm' (its "
                 "joint name)"),
      std::string::npos)
      << error;
}

// What spreadsheets and device software put around the values (review of
// issue 18): Windows line ends with an empty last cell (a marker not seen
// at the end of a mocap row), a space after the last comma, a UTF-8 byte
// order mark, quoted fields (a target name with a comma in it).
TEST(MeasurementFormatsTest, ExportQuirksReadAsThePlainFile) {
  const RobotModel m = testing::UrdfStyleModel();
  const std::string plain =
      "target,joint1_rad,joint2_rad,joint3_m,joint4_rad,x1_m,y1_m,z1_m,"
      "x2_m,y2_m,z2_m\n"
      "P1,0.1,0.2,0.05,0.3,1,2,3,1.1,2.1,3.1\n"
      "P2,0.2,0.1,0.04,0.1,1.2,2.2,3.2,,,\n";
  std::vector<Measurement> want, got;
  std::string error;
  ASSERT_TRUE(ParseMeasurementsCsv(plain, "p.csv", m, &want, &error)) << error;
  ASSERT_EQ(want.size(), 3u);
  auto crlf = [](std::string s) {
    std::string out;
    for (char c : s) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
    return out;
  };
  const std::vector<std::pair<const char*, std::string>> variants = {
      {"CRLF, last cells empty", crlf(plain)},
      {"space after the last comma", plain.substr(0, plain.size() - 1) + " \n"},
      {"UTF-8 byte order mark", "\xEF\xBB\xBF" + plain},
      {"rows of separators only (a spreadsheet's empty rows)",
       plain + ",,,,,,,,,,\r\n,,,,,,,,,,\n"},
      {"quoted fields",
       "\"target\",\"joint1_rad\",\"joint2_rad\",\"joint3_m\",\"joint4_rad\","
       "\"x1_m\",\"y1_m\",\"z1_m\",\"x2_m\",\"y2_m\",\"z2_m\"\n"
       "\"P1, \"\"north\"\"\",0.1,0.2,0.05,0.3,1,2,3,1.1,2.1,3.1\n"
       "\"P2\",\"0.2\",0.1,0.04,0.1,1.2,2.2,3.2,\"\",,\n"},
  };
  for (const auto& [what, text] : variants) {
    MeasurementsCsvReport report;
    ASSERT_TRUE(
        ParseMeasurementsCsv(text, "q.csv", m, {}, &got, &report, &error))
        << what << ": " << error;
    ASSERT_EQ(got.size(), want.size()) << what;
    for (size_t i = 0; i < got.size(); ++i) {
      EXPECT_EQ(got[i].joints, want[i].joints) << what;
      EXPECT_EQ(got[i].position, want[i].position) << what;
      EXPECT_EQ(got[i].marker, want[i].marker) << what;
    }
    ASSERT_EQ(report.notes.size(), 2u) << what;
    EXPECT_EQ(report.notes[0],
              "q.csv: ignored 1 column activecal does not read: target")
        << what;
  }
  const std::string j = "joint1_rad,joint2_rad,joint3_m,joint4_rad,";
  const std::vector<BadCsv> cases = {
      {"semicolons", "joint1_rad;joint2_rad;joint3_m;joint4_rad;x_m;y_m;z_m\n",
       "s.csv:1: header: the fields are separated by ';', not ','"},
      {"tabs", "joint1_rad\tjoint2_rad\tjoint3_m\tjoint4_rad\tx_m\n",
       "s.csv:1: header: the fields are separated by tabs, not ','"},
      {"a quote not closed", j + "x_m,y_m,z_m\n0.1,0.2,\"0.05,0.3,1,2,3\n",
       "s.csv:2: row: field 3: the quote opened there is not closed on the "
       "line"},
      {"text after a closing quote",
       j + "x_m,y_m,z_m\n0.1,\"0.2\"5,0.05,0.3,1,2,3\n",
       "s.csv:2: row: field 2: text after the closing quote"},
      {"UTF-16 (a NUL byte after each ASCII one)",
       std::string("\xFF\xFEj\0o\0i\0n\0t\0\x31\0", 14),
       "s.csv:1: header: the file holds NUL bytes: not UTF-8 or ASCII text "
       "(UTF-16? "
       "save it as UTF-8 CSV)"},
      {"a joint under neither name",
       "joint1_rad,joint2_rad,joint3_m,x_m,y_m,z_m\n",
       "s.csv:1: header: the header has neither 'q4_rad' nor 'q4_deg' for "
       "joint 4, "
       "nor 'joint4_rad' or 'joint4_deg' (its joint name)"},
  };
  ExpectRefused(cases, [&](const std::string& text, std::string* reason) {
    return ParseMeasurementsCsv(text, "s.csv", m, &got, reason);
  });
}

// Empty columns a spreadsheet or mocap export adds (a ',' ending every
// line) are no measurement problem; a value under no name is. Lengths
// beyond any device's reach are a corrupt cell or a wrong unit, not data
// (evaluating 1e200 mm gave an RMSE of inf).
TEST(MeasurementFormatsTest, NamelessEmptyColumnsAndImplausibleLengths) {
  const RobotModel m = testing::UrdfStyleModel();
  const std::string j = "joint1_rad,joint2_rad,joint3_m,joint4_rad,";
  std::vector<Measurement> out;
  MeasurementsCsvReport report;
  std::string error;
  ASSERT_TRUE(ParseMeasurementsCsv(
      j + "x1_mm,y1_mm,z1_mm,,\n0.1,0.2,0.05,0.3,1000,2000,3000,,\n", "e.csv",
      m, {}, &out, &report, &error))
      << error;
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].position, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(report.notes.empty()) << report.notes[0];
  MeasurementsCsvOptions strict;
  strict.columns_strict = true;
  EXPECT_TRUE(
      ParseMeasurementsCsv(j + "x_m,y_m,z_m,\n0.1,0.2,0.05,0.3,1,2,3,\n",
                           "e.csv", m, strict, &out, &report, &error))
      << error;
  const std::vector<BadCsv> cases = {
      {"a value under no name",
       j + "x_m,y_m,z_m,\n0.1,0.2,0.05,0.3,1,2,3,\n0.1,0.2,0.05,0.3,1,2,3,7\n",
       "e.csv:3: row: column 8 has no name in the header, but a value here "
       "('7')"},
      {"a point beyond any device's reach",
       j + "x_mm,y_mm,z_mm\n0.1,0.2,0.05,0.3,1e200,2,3\n",
       "e.csv:2: x_mm: 1e+200 mm is more than 1000 km: a corrupt cell or a "
       "wrong unit"},
      {"a wide marker beyond reach",
       j + "x1_m,y1_m,z1_m\n0.1,0.2,0.05,0.3,1,-2e6,3\n",
       "e.csv:2: y1_m: -2e+06 m is more than 1000 km"},
      {"a distance beyond reach",
       "type," + j +
           "joint1_rad_2,joint2_rad_2,joint3_m_2,joint4_rad_2,"
           "distance_mm\ndistance,0.1,0.2,0.05,0.3,0,0,0,0,1e10\n",
       "e.csv:2: distance_mm: 1e+10 mm is more than 1000 km"},
      {"a standard deviation beyond reach",
       j + "x_m,y_m,z_m,u95_m\n0.1,0.2,0.05,0.3,1,2,3,1e300\n",
       "e.csv:2: u95_m: 1e+300 m is more than 1000 km"},
  };
  ExpectRefused(cases, [&](const std::string& text, std::string* reason) {
    return ParseMeasurementsCsv(text, "e.csv", m, &out, reason);
  });
}

}  // namespace
}  // namespace activecal
