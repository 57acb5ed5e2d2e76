// Robot description files (YAML) and the workflow's CSV files: the shipped
// PUMA file equals the built-in model, round trips are exact, and every
// malformed input is answered with file, line and field.

#include <gtest/gtest.h>

#include <string>

#include "activecal/core/csv_files.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/robot_file.h"
#include "activecal/core/simulation.h"
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
    const std::string text = RobotFileText(m, m.nominal, options);
    RobotDescription back;
    std::string error;
    ASSERT_TRUE(ParseRobotDescription(text, "mem", &back, &error))
        << error << "\n"
        << text;
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

TEST(PosesCsvTest, MalformedFilesNameLineAndColumn) {
  const RobotModel m = testing::MixedModel();
  const std::string h = "q1_rad,q2_rad,q3_m,q4_rad\n";
  const std::vector<BadCsv> cases = {
      {"empty", "", "p.csv: empty file: no header line"},
      {"header only", h, "p.csv:1: no poses after the header"},
      {"missing joint", "q1_rad,q2_rad,q3_m\n0,0,0.1\n",
       "p.csv:1: the header has neither 'q4_rad' nor 'q4_deg' for joint 4"},
      {"short row", h + "0,0,0.1,0\n0,0,0.1\n",
       "p.csv:3: expected 4 fields as in the header, got 3"},
      {"not a number", h + "0,zero,0.1,0\n",
       "p.csv:2: q2_rad: expected a number, got 'zero'"},
      {"NaN", h + "0,nan,0.1,0\n", "p.csv:2: q2_rad: must be finite"},
      {"empty field", h + "0,,0.1,0\n", "p.csv:2: q2_rad: empty"},
      {"out of range", h + "0,0,0.5,0\n",
       "p.csv:2: joint 3 (L3) value 0.5 m is outside its range [0, 0.4] m"},
      {"duplicate", h + "0,0,0.1,0\n0.1,0,0.1,0\n0,0,0.1,0\n",
       "p.csv:4: duplicate pose: the same joint values as line 2"},
      {"disagreeing units",
       "q1_rad,q1_deg,q2_rad,q3_m,q4_rad\n0.1,90,0,0.1,0\n",
       "p.csv:2: q1_rad = 0.1 and q1_deg disagree"},
      {"repeated column", "q1_rad,q1_rad\n",
       "p.csv:1: header names column "
       "'q1_rad' twice"},
      {"bad pose_index", "pose_index," + h + "1.5,0,0,0.1,0\n",
       "p.csv:2: pose_index: expected an integer >= 0"},
  };
  for (const BadCsv& c : cases) {
    PoseList poses;
    std::string error;
    EXPECT_FALSE(ParsePosesCsv(c.text, "p.csv", m, true, &poses, &error))
        << c.what;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.what << "\n  got: " << error << "\n  want: " << c.message;
  }
  PoseList poses;
  std::string error;
  EXPECT_FALSE(ReadPosesCsv("/nonexistent.csv", m, true, &poses, &error));
  EXPECT_EQ(error, "/nonexistent.csv: cannot open the file");
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
      {"no type column", "q1_rad,q2_rad,q3_m,q4_rad\n0,0,0.1,0\n",
       "m.csv:1: the header has no column 'type'"},
      {"no rows", h, "m.csv:1: no measurements after the header"},
      {"bad type", h + "laser,0,0,0.1,0,1,2,3,,,,,,,,\n",
       "m.csv:2: type: expected position, pose or distance, got 'laser'"},
      {"missing point", h + "position,0,0,0.1,0,1,,3,,,,,,,,\n",
       "m.csv:2: y_m: empty"},
      {"value a type does not have", h + "position,0,0,0.1,0,1,2,3,,,,,,,,4\n",
       "m.csv:2: distance_m: a position measurement has no such value"},
      {"pose without rotation columns",
       "type,q1_rad,q2_rad,q3_m,q4_rad,x_m,y_m,z_m\npose,0,0,0.1,0,1,2,3\n",
       "m.csv:1: the header has no column 'rx_rad'"},
      {"rotation angle above pi", h + "pose,0,0,0.1,0,1,2,3,4,0,0,,,,,\n",
       "m.csv:2: measured rotation vector has angle 4 rad > pi"},
      {"second pose out of range",
       h + "distance,0,0,0.1,0,,,,,,,0,0,0.9,0,0.5\n",
       "m.csv:2: second pose: joint 3 (L3) value 0.9 m is outside its range"},
      {"negative distance", h + "distance,0,0,0.1,0,,,,,,,0,0,0.1,1,-0.5\n",
       "m.csv:2: measured distance must be finite and >= 0, got -0.5"},
      {"infinite", h + "position,0,0,0.1,0,1,2,inf,,,,,,,,\n",
       "m.csv:2: z_m: must be finite"},
  };
  for (const BadCsv& c : cases) {
    std::vector<Measurement> out;
    std::string error;
    EXPECT_FALSE(ParseMeasurementsCsv(c.text, "m.csv", m, &out, &error))
        << c.what;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.what << "\n  got: " << error << "\n  want: " << c.message;
  }
}

}  // namespace
}  // namespace activecal
