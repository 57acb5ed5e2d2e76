// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// ISO 9283 figures of a measurements file of cycles
// (calibration/iso9283_cycles.h) on simulation: the PUMA 560 of the paper
// with its true (Table I) errors runs commanded poses with the nominal
// model's joints; the attained poses scatter by a known repeatability. The
// figures without the model equal the simulated error; with the true model
// the predicted AP is noise; with the nominal model "with" is "without".
// And the commanded-pose columns of the reader (io/csv_files.h).

#include "activecal/calibration/iso9283_cycles.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/io/csv_files.h"
#include "activecal/report/svg_figures.h"

namespace activecal {
namespace {

Eigen::Matrix3d RotationExp(const Eigen::Vector3d& d) {
  const double a = d.norm();
  return a == 0 ? Eigen::Matrix3d::Identity()
                : Eigen::AngleAxisd(a, d / a).toRotationMatrix();
}

Eigen::Vector3d Log(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

// The base transform of a full parameter vector.
void Base(const RobotModel& model, const Eigen::VectorXd& p, Eigen::Matrix3d* r,
          Eigen::Vector3d* t) {
  const std::vector<const double*> blocks = BlockPointers(model, p.data());
  LinkTransform(model.base, blocks[0], 0.0, r, t);
}

// The target frame in the base frame of `p`.
void BaseFrame(const RobotModel& model, const Eigen::VectorXd& p,
               const Eigen::VectorXd& q, Eigen::Matrix3d* r,
               Eigen::Vector3d* t) {
  Eigen::Matrix3d rd, rb;
  Eigen::Vector3d td, tb;
  TargetFrame(model, p, q, &rd, &td);
  Base(model, p, &rb, &tb);
  *r = rb.transpose() * rd;
  *t = rb.transpose() * (td - tb);
}

struct Simulation {
  std::vector<Measurement> measurements;
  std::vector<int> lines;
  std::vector<CommandedPose> commanded;
  std::vector<Eigen::Vector3d> error_m;    // true - nominal, base frame
  std::vector<Eigen::Vector3d> error_rad;  // log(R_true R_nominal^T)
};

constexpr double kSigmaM = 20e-6;    // repeatability per axis
constexpr double kSigmaRad = 20e-6;  // per rotation-vector component
constexpr int kCycles = 30;

Simulation Simulate(uint64_t seed) {
  const RobotModel model = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  Random random(seed);
  Simulation s;
  Eigen::Matrix3d rb;
  Eigen::Vector3d tb;
  Base(model, truth, &rb, &tb);
  int line = 2;
  for (int k = 0; k < 5; ++k) {
    Eigen::VectorXd q(model.num_joints());
    for (int j = 0; j < q.size(); ++j) {
      const Link& l = model.links[j];
      q[j] = 0.5 * (l.joint_min + l.joint_max) +
             0.3 * (random.Uniform() - 0.5) * (l.joint_max - l.joint_min);
    }
    // The commanded pose: what the nominal model (the controller's) puts
    // at q, so that the controller's inverse kinematics gives q.
    Eigen::Matrix3d rc, rt;
    Eigen::Vector3d xc, xt;
    BaseFrame(model, model.nominal, q, &rc, &xc);
    BaseFrame(model, truth, q, &rt, &xt);
    s.error_m.push_back(xt - xc);
    s.error_rad.push_back(Log(rt * rc.transpose()));
    for (int c = 0; c < kCycles; ++c) {
      const Eigen::Vector3d dx(random.Gaussian(), random.Gaussian(),
                               random.Gaussian());
      const Eigen::Vector3d dr(random.Gaussian(), random.Gaussian(),
                               random.Gaussian());
      const Eigen::Vector3d xa = xt + kSigmaM * dx;
      const Eigen::Matrix3d ra = RotationExp(kSigmaRad * dr) * rt;
      Measurement m;
      m.type = MeasurementType::kPose;
      m.joints = q;
      m.position = rb * xa + tb;  // in the device's frame
      m.rotation = Log(rb * ra);
      s.measurements.push_back(m);
      s.lines.push_back(line);
      CommandedPose cp;
      cp.line = line;
      cp.pose = "P" + std::to_string(k + 1);
      cp.position = xc;
      cp.has_rotation = true;
      cp.rotation = rc;
      s.commanded.push_back(cp);
      ++line;
    }
  }
  return s;
}

TEST(Iso9283CyclesTest, WithoutIsTheSimulatedErrorWithTheTrueModelIsNoise) {
  const RobotModel model = Puma560PaperModel();
  const Simulation s = Simulate(7);
  Iso9283CyclesSummary summary;
  ASSERT_TRUE(EvaluateIso9283Cycles(model, Puma560TrueParameters(),
                                    s.measurements, s.lines, s.commanded,
                                    &summary))
      << summary.message;
  ASSERT_EQ(summary.poses.size(), 5u);
  // The mean of n cycles is within 4 sigma / sqrt(n) per axis.
  const double tol_m = 4 * kSigmaM / std::sqrt(kCycles);
  const double tol_rad = 4 * kSigmaRad / std::sqrt(kCycles);
  for (int k = 0; k < 5; ++k) {
    const Iso9283PoseReport& p = summary.poses[k];
    EXPECT_EQ(p.pose, "P" + std::to_string(k + 1));
    EXPECT_EQ(p.without.num_cycles, kCycles);
    // The simulated error is millimetres: far above the noise.
    EXPECT_GT(s.error_m[k].norm(), 100 * tol_m);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(p.without.ap_xyz_m[a], s.error_m[k][a], tol_m);
      EXPECT_NEAR(p.without.ap_rad[a], s.error_rad[k][a], tol_rad);
      EXPECT_NEAR(p.with.ap_xyz_m[a], 0.0, tol_m);
      EXPECT_NEAR(p.with.ap_rad[a], 0.0, tol_rad);
    }
    // RP of 3D Gaussian scatter: l_bar ~ 1.6 sigma, RP_l ~ 3.6 sigma.
    EXPECT_GT(p.without.rp_l_m, 2.5 * kSigmaM);
    EXPECT_LT(p.without.rp_l_m, 5.0 * kSigmaM);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(p.without.rp_rad[a], 3 * kSigmaRad, 1.2 * kSigmaRad);
    }
    // The joints of the cycles of a pose are the same: the model moves
    // them all alike, the scatter is the same (the orientation's to second
    // order: log(RotationExp(n) RotationExp(e)) turns the scatter n by the
    // Jacobian of the log at the error e, by about |e| relative).
    EXPECT_NEAR(p.with.rp_l_m, p.without.rp_l_m, 1e-12);
    EXPECT_NEAR((p.with.rp_rad - p.without.rp_rad).norm(), 0.0,
                s.error_rad[k].norm() * 2 * p.without.rp_rad.norm());
  }
}

TEST(Iso9283CyclesTest, WithTheNominalModelWithIsWithout) {
  // The controller's own model predicts no compensation: x'_j = x_j.
  RobotModel model = Puma560PaperModel();
  const Simulation s = Simulate(8);
  Eigen::VectorXd nominal = model.nominal;
  // The registration is the true one (the base block of the truth).
  nominal.head(model.block_size(0)) =
      Puma560TrueParameters().head(model.block_size(0));
  Iso9283CyclesSummary summary;
  ASSERT_TRUE(EvaluateIso9283Cycles(model, nominal, s.measurements, s.lines,
                                    s.commanded, &summary))
      << summary.message;
  for (const Iso9283PoseReport& p : summary.poses) {
    EXPECT_NEAR((p.with.ap_xyz_m - p.without.ap_xyz_m).norm(), 0.0, 1e-12);
    EXPECT_NEAR((p.with.ap_rad - p.without.ap_rad).norm(), 0.0, 1e-12);
  }
  // The table names each pose, in mm.
  const std::string table = summary.TableText();
  EXPECT_NE(table.find("P5"), std::string::npos);
  EXPECT_NE(table.find("mrad"), std::string::npos);
  const nlohmann::json j = summary.Json();
  ASSERT_EQ(j["poses"].size(), 5u);
  EXPECT_DOUBLE_EQ(j["poses"][0]["without"]["ap_p_m"].get<double>(),
                   summary.poses[0].without.ap_p_m);
  EXPECT_DOUBLE_EQ(j["poses"][0]["without"]["ap_p_mm"].get<double>(),
                   summary.poses[0].without.ap_p_m * 1e3);
}

TEST(Iso9283CyclesTest, BadCycles) {
  const RobotModel model = Puma560PaperModel();
  const Eigen::VectorXd truth = Puma560TrueParameters();
  Simulation s = Simulate(9);
  Iso9283CyclesSummary summary;
  // One cycle of a pose.
  Simulation one = s;
  one.commanded[0].pose = "lonely";
  EXPECT_FALSE(EvaluateIso9283Cycles(model, truth, one.measurements, one.lines,
                                     one.commanded, &summary));
  EXPECT_NE(summary.message.find("2: pose: 'lonely' has 1 cycle"),
            std::string::npos)
      << summary.message;
  // A pose row without a commanded orientation.
  Simulation no_rotation = s;
  no_rotation.commanded[3].has_rotation = false;
  EXPECT_FALSE(EvaluateIso9283Cycles(model, truth, no_rotation.measurements,
                                     no_rotation.lines, no_rotation.commanded,
                                     &summary));
  EXPECT_NE(summary.message.find("5: pose: 'P1': a 6D pose row without"),
            std::string::npos)
      << summary.message;
  // Two commanded poses under one label.
  Simulation moved = s;
  moved.commanded[4].position.x() += 1e-3;
  EXPECT_FALSE(EvaluateIso9283Cycles(model, truth, moved.measurements,
                                     moved.lines, moved.commanded, &summary));
  EXPECT_NE(summary.message.find("6: pose: 'P1' (first line 2): a "
                                 "commanded pose other"),
            std::string::npos)
      << summary.message;
  // Two measurements of one line (the wide form).
  Simulation wide = s;
  wide.lines[1] = wide.lines[0];
  EXPECT_FALSE(EvaluateIso9283Cycles(model, truth, wide.measurements,
                                     wide.lines, wide.commanded, &summary));
  EXPECT_NE(summary.message.find("several markers on one row"),
            std::string::npos)
      << summary.message;
}

TEST(Iso9283CyclesTest, CommandedColumns) {
  const RobotModel model = Puma560PaperModel();
  const std::string joints = "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad";
  const std::string q = "0,0,0,0,0,0";
  std::vector<CommandedPose> poses;
  std::string error;
  // A quaternion in mm: the point in m, the rotation its matrix.
  const double h = std::sqrt(0.5);
  ASSERT_TRUE(ParseCommandedPosesCsv(
      "pose," + joints +
          ",commanded_x_mm,commanded_y_mm,commanded_z_mm,commanded_qw,"
          "commanded_qx,commanded_qy,commanded_qz\nP1," +
          q + ",1500,-2.5,300," + std::to_string(h) + ",0,0," +
          std::to_string(h) + "\n",
      "a.csv", model, MeasurementsCsvOptions(), &poses, &error))
      << error;
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_EQ(poses[0].pose, "P1");
  EXPECT_EQ(poses[0].line, 2);
  EXPECT_DOUBLE_EQ(poses[0].position.x(), 1.5);
  EXPECT_DOUBLE_EQ(poses[0].position.y(), -0.0025);
  EXPECT_TRUE(poses[0].has_rotation);
  EXPECT_NEAR(
      (poses[0].rotation -
       Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix())
          .norm(),
      0.0, 1e-6);
  const std::string matrix_header =
      "pose," + joints +
      ",commanded_x_m,commanded_y_m,commanded_z_m,commanded_r11,"
      "commanded_r12,commanded_r13,commanded_r21,commanded_r22,"
      "commanded_r23,commanded_r31,commanded_r32,commanded_r33\n";
  // A rotation matrix about z by 90 deg, row by row.
  ASSERT_TRUE(ParseCommandedPosesCsv(
      matrix_header + "P1," + q + ",1,2,3,0,-1,0,1,0,0,0,0,1\n", "b.csv", model,
      MeasurementsCsvOptions(), &poses, &error))
      << error;
  EXPECT_NEAR(poses[0].rotation(1, 0), 1.0, 1e-15);
  EXPECT_NEAR(poses[0].rotation(0, 1), -1.0, 1e-15);
  // A reflection and a scaled matrix are not rotations.
  EXPECT_FALSE(ParseCommandedPosesCsv(
      matrix_header + "P1," + q + ",1,2,3,1,0,0,0,1,0,0,0,-1\n", "c.csv", model,
      MeasurementsCsvOptions(), &poses, &error));
  EXPECT_NE(error.find("c.csv:2: commanded_r11..commanded_r33: not a rotation "
                       "matrix"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("det = -1"), std::string::npos) << error;
  EXPECT_FALSE(ParseCommandedPosesCsv(
      matrix_header + "P1," + q + ",1,2,3,1.00001,0,0,0,1,0,0,0,1\n", "d.csv",
      model, MeasurementsCsvOptions(), &poses, &error));
  EXPECT_NE(error.find("not a rotation matrix"), std::string::npos) << error;
  // Within the tolerance: the nearest rotation.
  ASSERT_TRUE(ParseCommandedPosesCsv(
      matrix_header + "P1," + q + ",1,2,3,1.0000004,0,0,0,1,0,0,0,1\n", "e.csv",
      model, MeasurementsCsvOptions(), &poses, &error))
      << error;
  EXPECT_NEAR((poses[0].rotation - Eigen::Matrix3d::Identity()).norm(), 0.0,
              1e-15);
  // No commanded point; no pose label; an empty label.
  EXPECT_FALSE(ParseCommandedPosesCsv("pose," + joints + "\nP1," + q + "\n",
                                      "f.csv", model, MeasurementsCsvOptions(),
                                      &poses, &error));
  EXPECT_NE(
      error.find("f.csv:1: header: the header has no column 'commanded_x_m'"),
      std::string::npos)
      << error;
  EXPECT_FALSE(ParseCommandedPosesCsv(
      joints + ",commanded_x_m,commanded_y_m,commanded_z_m\n" + q + ",1,2,3\n",
      "g.csv", model, MeasurementsCsvOptions(), &poses, &error));
  EXPECT_NE(error.find("g.csv:1: header: the header has no column 'pose'"),
            std::string::npos)
      << error;
  EXPECT_FALSE(ParseCommandedPosesCsv(
      "pose,commanded_x_m,commanded_y_m,commanded_z_m\n,1,2,3\n", "h.csv",
      model, MeasurementsCsvOptions(), &poses, &error));
  EXPECT_NE(error.find("h.csv:2: pose: empty"), std::string::npos) << error;
  // Part of the commanded point.
  EXPECT_FALSE(ParseCommandedPosesCsv(
      "pose,commanded_x_m,commanded_y_m\nP1,1,2\n", "i.csv", model,
      MeasurementsCsvOptions(), &poses, &error));
  EXPECT_NE(
      error.find("i.csv:1: header: the header has commanded_x_m,commanded_y_m "
                 "but not commanded_z_m"),
      std::string::npos)
      << error;
}

TEST(Iso9283CyclesTest, CommandedColumnsWrittenAreReadBack) {
  // activecal_simulate carries a poses file's cycle columns to the
  // measurements it writes: each row gets its pose's label and commanded
  // pose, and both readers read the file back.
  const RobotModel model = Puma560PaperModel();
  std::vector<Measurement> measurements(3);
  for (int i = 0; i < 3; ++i) {
    measurements[i].joints = Eigen::VectorXd::Constant(6, 0.1 * i);
    measurements[i].position = Eigen::Vector3d(i, -0.5, 0.25);
  }
  std::vector<CommandedPose> commanded(2);
  commanded[0].pose = "P1";
  commanded[0].position = Eigen::Vector3d(1.0 / 3, 0.2, -0.7);
  commanded[1].pose = "P \"2\", left";  // a comma and quotes: quoted
  commanded[1].position = Eigen::Vector3d(-1.25, 1e-9, 2.0);
  commanded[1].has_rotation = true;
  commanded[1].rotation =
      Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, -2, 0.5).normalized())
          .toRotationMatrix();
  const std::vector<int> row_of = {1, 0, 1};
  const std::string text = WithCommandedPoseColumns(
      MeasurementsCsvText(model, measurements), commanded, row_of);
  std::vector<CommandedPose> back;
  std::string error;
  ASSERT_TRUE(ParseCommandedPosesCsv(text, "m.csv", model,
                                     MeasurementsCsvOptions(), &back, &error))
      << error;
  ASSERT_EQ(back.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const CommandedPose& c = commanded[row_of[i]];
    EXPECT_EQ(back[i].pose, c.pose);
    EXPECT_EQ(back[i].position, c.position);  // %.17g: exact
    // Every row has an orientation once one pose has: P1's is identity.
    EXPECT_TRUE(back[i].has_rotation);
    EXPECT_LT((back[i].rotation - c.rotation).cwiseAbs().maxCoeff(), 1e-15);
  }
  std::vector<Measurement> read;
  ASSERT_TRUE(ParseMeasurementsCsv(text, "m.csv", model, &read, &error))
      << error;
  ASSERT_EQ(read.size(), 3u);
  EXPECT_EQ(read[2].position, measurements[2].position);
  // A poses file without the columns: none, and no error; with them (a
  // byte-order mark, a comment, a quoted header name): read.
  const std::string joints = "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad";
  ASSERT_TRUE(ParseCommandedPosesIfAny("# poses\n" + joints + "\n0,0,0,0,0,0\n",
                                       "p.csv", model, {}, &back, &error));
  EXPECT_TRUE(back.empty());
  ASSERT_TRUE(ParseCommandedPosesIfAny(
      "\xEF\xBB\xBF# cube\n\"pose\"," + joints +
          ",commanded_x_m,commanded_y_m,commanded_z_m\nP3,0,0,0,0,0,0,1,2,3\n",
      "c.csv", model, {}, &back, &error))
      << error;
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].pose, "P3");
  EXPECT_EQ(back[0].position, Eigen::Vector3d(1, 2, 3));
  // With a 'pose' column the file must be a cycles file.
  EXPECT_FALSE(ParseCommandedPosesIfAny("pose," + joints + "\nP1,0,0,0,0,0,0\n",
                                        "f.csv", model, {}, &back, &error));
  EXPECT_NE(error.find("f.csv:1: header: the header has no column "
                       "'commanded_x_m'"),
            std::string::npos)
      << error;
}

TEST(Iso9283CyclesTest, MeasurementsReaderKnowsTheColumns) {
  // The commanded columns are neither noted nor refused as unknown.
  const RobotModel model = Puma560PaperModel();
  MeasurementsCsvOptions strict;
  strict.columns_strict = true;
  std::vector<Measurement> m;
  MeasurementsCsvReport report;
  std::string error;
  ASSERT_TRUE(ParseMeasurementsCsv(
      "pose,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m,"
      "commanded_x_m,commanded_y_m,commanded_z_m\nP1,0,0,0,0,0,0,1,2,3,1,2,"
      "3\n",
      "a.csv", model, strict, &m, &report, &error))
      << error;
  EXPECT_TRUE(report.notes.empty());
  EXPECT_EQ(report.lines, std::vector<int>({2}));
}

// The cell of the report's and the ISO 9283 section's tables: millimetres
// with 3 decimals, the SI value in full, no "-0.000", "-" where the value is
// not finite, the key escaped.
TEST(HtmlNumberCell, ShowsThreeDecimalsAndKeepsTheSiValue) {
  EXPECT_EQ(HtmlNumberCell("iso.ap_p", 0.0012345, 1.2345),
            "<td class=\"num\" data-key=\"iso.ap_p\" "
            "data-value=\"0.0012344999999999999\">1.234</td>");
  EXPECT_NE(HtmlNumberCell("k", -4e-7, -4e-4).find(">0.000</td>"),
            std::string::npos);
  EXPECT_NE(HtmlNumberCell("k", -6e-7, -6e-4).find(">-0.001</td>"),
            std::string::npos);
  EXPECT_NE(HtmlNumberCell("k", NAN, NAN).find(">-</td>"), std::string::npos);
  EXPECT_NE(HtmlNumberCell("k", INFINITY, INFINITY).find(">-</td>"),
            std::string::npos);
  EXPECT_NE(HtmlNumberCell("a<b", 1, 1).find("data-key=\"a&lt;b\""),
            std::string::npos);
}

}  // namespace
}  // namespace activecal
