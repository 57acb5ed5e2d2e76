// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Column maps (io/column_map.h): a device's export read through a map gives
// the measurements of the same data converted by hand.

#include "activecal/io/column_map.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>

#include "activecal/core/euler_angles.h"
#include "activecal/core/measurement.h"
#include "activecal/core/puma560.h"
#include "activecal/core/random.h"
#include "activecal/core/simulation.h"
#include "activecal/estimation/identification.h"
#include "activecal/io/csv_files.h"
#include "test_util.h"

namespace activecal {
namespace {

constexpr double kDeg = M_PI / 180.0;

std::string Text17(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  return buffer;
}

// "1.25" -> "1,25": how a German-locale PC writes numbers.
std::string Comma(std::string s) {
  for (char& c : s) {
    if (c == '.') c = ',';
  }
  return s;
}

ColumnMap MapOf(const std::string& yaml) {
  ColumnMap map;
  std::string error;
  EXPECT_TRUE(ParseColumnMap(yaml, "map.yaml", &map, &error)) << error;
  return map;
}

bool ReadThrough(const ColumnMap* map, const std::string& csv,
                 std::vector<Measurement>* out, std::string* error,
                 MeasurementsCsvReport* report = nullptr) {
  MeasurementsCsvOptions options;
  if (map) options.column_map = *map;
  return ParseMeasurementsCsv(csv, "data.csv", Puma560PaperModel(), options,
                              out, report, error);
}

// The hand conversion: elementary rotations about the axes named by the
// convention's letters, composed in the order the letters are applied.
Eigen::Matrix3d HandRotation(const std::string& axes, bool intrinsic,
                             Eigen::Vector3d angles) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(axes[k] - 'X');
    const Eigen::Matrix3d Rk =
        Eigen::AngleAxisd(angles[k], axis).toRotationMatrix();
    R = intrinsic ? Eigen::Matrix3d(R * Rk) : Eigen::Matrix3d(Rk * R);
  }
  return R;
}

const char* const kAllAxesNames[12] = {"XYZ", "XZY", "YXZ", "YZX",
                                       "ZXY", "ZYX", "XYX", "XZX",
                                       "YXY", "YZY", "ZXZ", "ZYZ"};

TEST(ColumnMapTest, EveryConventionMatchesTheHandConversion) {
  // Generic angles, the singular middle angle (+-90 deg Tait-Bryan, 0 and
  // 180 deg proper Euler) and near it, first and last at +-180 deg.
  const std::vector<Eigen::Vector3d> deg_angles = {
      {30, -50, 120},     {-170, 80, 45},  {10, 90, 20},
      {10, -90, 20},      {40, 0, -30},    {40, 180, -30},
      {25, 89.999999, 5}, {180, 30, -180}, {-60, 1e-7, 35}};
  for (const char* axes : kAllAxesNames) {
    for (bool intrinsic : {true, false}) {
      for (bool degrees : {true, false}) {
        const ColumnMap map = MapOf(
            std::string("orientation: {convention: ") + axes +
            ", intrinsic: " + (intrinsic ? "true" : "false") +
            ", unit: " + (degrees ? "deg" : "rad") + ", columns: [A, B, C]}\n");
        std::string csv =
            "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,"
            "z_m,A,B,C\n";
        std::vector<Eigen::Matrix3d> expected;
        for (const Eigen::Vector3d& d : deg_angles) {
          const Eigen::Vector3d rad = d * kDeg;
          const Eigen::Vector3d written = degrees ? d : rad;
          csv += "0.1,0.2,0.3,0.4,0.5,0.6,1,2,3," + Text17(written[0]) + "," +
                 Text17(written[1]) + "," + Text17(written[2]) + "\n";
          expected.push_back(HandRotation(
              axes, intrinsic, degrees ? Eigen::Vector3d(d * kDeg) : rad));
        }
        std::vector<Measurement> read;
        std::string error;
        ASSERT_TRUE(ReadThrough(&map, csv, &read, &error)) << error;
        ASSERT_EQ(read.size(), expected.size());
        for (size_t i = 0; i < read.size(); ++i) {
          EXPECT_EQ(read[i].type, MeasurementType::kPose);
          const double angle = read[i].rotation.norm();
          const Eigen::Matrix3d R =
              angle == 0.0 ? Eigen::Matrix3d::Identity()
                           : Eigen::AngleAxisd(angle, read[i].rotation / angle)
                                 .toRotationMatrix();
          EXPECT_LT((R - expected[i]).cwiseAbs().maxCoeff(), 2e-15)
              << axes << (intrinsic ? " intrinsic " : " extrinsic ")
              << (degrees ? "deg " : "rad ") << deg_angles[i].transpose();
        }
      }
    }
  }
}

TEST(ColumnMapTest, RollPitchYawByMistakeIsAnotherRotation) {
  // Intrinsic XYZ is not activecal's roll/pitch/yaw (extrinsic XYZ): the
  // map must not read it as one.
  const Eigen::Vector3d d(30, 40, 50);
  const ColumnMap map = MapOf(
      "orientation: {convention: XYZ, intrinsic: true, unit: deg, columns: "
      "[A, B, C]}\n");
  std::vector<Measurement> read;
  std::string error;
  ASSERT_TRUE(ReadThrough(
      &map,
      "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m,A,B,C\n"
      "0,0,0,0,0,0,1,2,3,30,40,50\n",
      &read, &error))
      << error;
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(read[0].rotation.norm(), read[0].rotation.normalized())
          .toRotationMatrix();
  EXPECT_LT((R - HandRotation("XYZ", true, d * kDeg)).norm(), 1e-14);
  EXPECT_GT((R - HandRotation("XYZ", false, d * kDeg)).norm(), 0.1);
}

// A simulated session written as a German-locale tracker export and as
// activecal's own file, converted by hand.
struct TwoFiles {
  std::string german, converted;
};

TwoFiles Session(bool with_orientation) {
  const RobotModel model = Puma560PaperModel();
  const std::vector<Measurement> measured = testing::SimulatedPuma(
      30, 7,
      with_orientation ? MeasurementType::kPose : MeasurementType::kPosition,
      {1e-4, 1e-4}, 3);
  TwoFiles f;
  f.german =
      "# Leica export\nPunkt;j1;j2;j3;j4;j5;j6;measurement_x;"
      "measurement_y;measurement_z";
  f.converted =
      "# Leica export\nPunkt,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,"
      "q6_deg,x_mm,y_mm,z_mm";
  if (with_orientation) {
    f.german += ";measurement_rx;measurement_ry;measurement_rz";
    f.converted += ",rx_rad,ry_rad,rz_rad";
  }
  f.german += "\n";
  f.converted += "\n";
  EulerConvention xyz_deg;
  xyz_deg.degrees = true;
  for (size_t i = 0; i < measured.size(); ++i) {
    const Measurement& m = measured[i];
    std::vector<std::string> values;
    for (int j = 0; j < 6; ++j) values.push_back(Text17(m.joints[j] / kDeg));
    for (int k = 0; k < 3; ++k) values.push_back(Text17(m.position[k] * 1e3));
    std::string g = "\"P" + std::to_string(i) + ", Halle 2\"",
                c = "\"P" + std::to_string(i) + ", Halle 2\"";
    for (const std::string& v : values) {
      g += ";" + Comma(v);
      c += "," + v;
    }
    if (with_orientation) {
      const Eigen::Matrix3d R =
          Eigen::AngleAxisd(m.rotation.norm(), m.rotation.normalized())
              .toRotationMatrix();
      const Eigen::Vector3d a = RotationMatrixToEulerAngles(R, xyz_deg);
      // By hand: the rotation vector of the angles' elementary rotations.
      const Eigen::AngleAxisd aa(HandRotation("XYZ", true, a * kDeg));
      const Eigen::Vector3d v = aa.angle() * aa.axis();
      for (int k = 0; k < 3; ++k) {
        g += ";" + Comma(Text17(a[k]));
        c += "," + Text17(v[k]);
      }
    }
    f.german += g + "\n";
    f.converted += c + "\n";
  }
  return f;
}

const char kLeicaMap[] =
    "delimiter: \";\"\n"
    "decimal: \",\"\n"
    "columns:\n"
    "  q1_deg: j1\n  q2_deg: j2\n  q3_deg: j3\n  q4_deg: j4\n  q5_deg: j5\n"
    "  q6_deg: j6\n"
    "  x_mm: measurement_x\n  y_mm: measurement_y\n  z_mm: measurement_z\n";

TEST(ColumnMapTest, GermanExportGivesBitIdenticalMeasurementsAndFit) {
  const TwoFiles f = Session(false);
  const ColumnMap map = MapOf(kLeicaMap);
  std::vector<Measurement> mapped, converted;
  std::string error;
  MeasurementsCsvReport report;
  ASSERT_TRUE(ReadThrough(&map, f.german, &mapped, &error, &report)) << error;
  ASSERT_TRUE(ReadThrough(nullptr, f.converted, &converted, &error)) << error;
  ASSERT_EQ(mapped.size(), 30u);
  ASSERT_EQ(converted.size(), mapped.size());
  for (size_t i = 0; i < mapped.size(); ++i) {
    EXPECT_EQ(mapped[i].joints, converted[i].joints) << i;
    EXPECT_EQ(mapped[i].position, converted[i].position) << i;
  }
  const RobotModel model = Puma560PaperModel();
  IdentificationSummary a, b;
  Identify(model, mapped, model.nominal, IdentificationOptions(), &a);
  Identify(model, converted, model.nominal, IdentificationOptions(), &b);
  ASSERT_EQ(a.termination_type, TerminationType::kConvergence) << a.message;
  EXPECT_EQ(a.parameters, b.parameters);
  EXPECT_EQ(a.rms_m, b.rms_m);
}

TEST(ColumnMapTest, GermanExportWithEulerAnglesMatchesTheHandConversion) {
  const TwoFiles f = Session(true);
  const ColumnMap map = MapOf(
      std::string(kLeicaMap) +
      "orientation: {convention: XYZ, intrinsic: true, unit: deg, columns: "
      "[measurement_rx, measurement_ry, measurement_rz]}\n");
  std::vector<Measurement> mapped, converted;
  std::string error;
  ASSERT_TRUE(ReadThrough(&map, f.german, &mapped, &error)) << error;
  ASSERT_TRUE(ReadThrough(nullptr, f.converted, &converted, &error)) << error;
  ASSERT_EQ(converted.size(), mapped.size());
  for (size_t i = 0; i < mapped.size(); ++i) {
    EXPECT_EQ(mapped[i].type, MeasurementType::kPose);
    EXPECT_EQ(mapped[i].joints, converted[i].joints) << i;
    EXPECT_EQ(mapped[i].position, converted[i].position) << i;
    // Two conversions of the same angles: equal to rounding.
    EXPECT_LT((mapped[i].rotation - converted[i].rotation).norm(), 4e-15) << i;
  }
  const RobotModel model = Puma560PaperModel();
  IdentificationSummary a, b;
  Identify(model, mapped, model.nominal, IdentificationOptions(), &a);
  Identify(model, converted, model.nominal, IdentificationOptions(), &b);
  ASSERT_EQ(a.termination_type, TerminationType::kConvergence) << a.message;
  EXPECT_LT((a.parameters - b.parameters).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(ColumnMapTest, DelimiterDetectedWithANote) {
  const TwoFiles f = Session(false);
  ColumnMap map = MapOf(std::string(kLeicaMap).substr(15));  // no delimiter
  ASSERT_EQ(map.delimiter, '\0');
  std::vector<Measurement> read;
  std::string error;
  MeasurementsCsvReport report;
  ASSERT_TRUE(ReadThrough(&map, f.german, &read, &error, &report)) << error;
  ASSERT_FALSE(report.notes.empty());
  EXPECT_EQ(report.notes[0],
            "data.csv: column map map.yaml: delimiter ';' detected (the header "
            "has 0 ',', 9 ';', 0 tabs)");
  // A tab-separated export, unmapped activecal names mixed with mapped ones.
  map = MapOf("columns: {x_mm: X}\n");
  ASSERT_TRUE(ReadThrough(&map,
                          "q1_rad\tq2_rad\tq3_rad\tq4_rad\tq5_rad\tq6_rad\tX\t"
                          "y_mm\tz_mm\n0\t0\t0\t0\t0\t0\t1.5\t2\t3\n",
                          &read, &error, &report))
      << error;
  EXPECT_EQ(read[0].position, Eigen::Vector3d(0.0015, 0.002, 0.003));
  EXPECT_NE(report.notes[0].find("delimiter tab detected"), std::string::npos);
}

std::string MapError(const std::string& yaml) {
  ColumnMap map;
  std::string error;
  EXPECT_FALSE(ParseColumnMap(yaml, "map.yaml", &map, &error));
  return error;
}

std::string ApplyError(const std::string& yaml, const std::string& csv) {
  const ColumnMap map = MapOf(yaml);
  std::vector<Measurement> read;
  std::string error;
  EXPECT_FALSE(ReadThrough(&map, csv, &read, &error));
  return error;
}

TEST(ColumnMapTest, BadMapsAreNamedInOneLine) {
  EXPECT_EQ(MapError("delimiter: \",\"\ndecimal: \",\"\n"),
            "map.yaml:2:10: decimal: ',' with ',' as the delimiter cannot be "
            "read (1,5 would be two fields): the file's delimiter is another "
            "(\";\" or \"\\t\")");
  EXPECT_EQ(MapError("orientation: {convention: XYZ, intrinsic: true, unit: "
                     "deg, columns: [a, b]}\n"),
            "map.yaml:1:69: orientation.columns: expected 3 columns (the "
            "angles a, b, c in the convention's order), got 2");
  EXPECT_EQ(MapError("orientation: {convention: XYW, intrinsic: true, unit: "
                     "deg, columns: [a, b, c]}\n"),
            "map.yaml:1:27: orientation.convention: unknown convention 'XYW' "
            "(expected one of XYZ, XZY, YXZ, YZX, ZXY, ZYX, XYX, XZX, YXY, "
            "YZY, ZXZ, ZYZ)");
  EXPECT_EQ(MapError("orientation: {convention: XYZ, intrinsic: true, unit: "
                     "grad, columns: [a, b, c]}\n"),
            "map.yaml:1:55: orientation.unit: expected deg or rad, got 'grad'");
  EXPECT_NE(
      MapError("colums: {}\n").find("map.yaml:1:1: colums: unknown field"),
      std::string::npos);
}

// The map accepts every column the reader reads (one list, the reader's:
// IsMeasurementsCsvColumn), the ISO 9283 ones among them: the commanded
// pose of a cycles file mapped from a controller's names reads as the
// same file written with activecal's names.
TEST(ColumnMapTest, IsoColumnsAreMappedAsTheReaderReadsThem) {
  const RobotModel model = Puma560PaperModel();
  for (const std::string& c : MeasurementsCsvFixedColumns()) {
    EXPECT_TRUE(IsMeasurementsCsvColumn(c, model)) << c;
  }
  for (const char* c : {"pose", "commanded_x_m", "commanded_z_mm",
                        "commanded_qw", "commanded_r11", "commanded_r33"}) {
    EXPECT_TRUE(IsMeasurementsCsvColumn(c, model)) << c;
  }
  for (const char* c : {"x_cm", "commanded_w", "q7_rad", "poses"}) {
    EXPECT_FALSE(IsMeasurementsCsvColumn(c, model)) << c;
  }
  const std::string joints = "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad";
  const std::string rows =
      "0.1,0.2,0.3,0.4,0.5,0.6,0.5,0.1,0.2,P1,0.5,0.1,0.2,1,0,0,0\n"
      "0.1,0.2,0.3,0.4,0.5,0.6,0.5,0.1,0.2,P1,0.5,0.1,0.2,1,0,0,0\n";
  const std::string own =
      joints +
      ",x_m,y_m,z_m,pose,commanded_x_m,commanded_y_m,commanded_z_m,"
      "commanded_qw,commanded_qx,commanded_qy,commanded_qz\n" +
      rows;
  const std::string device =
      joints + ",x_m,y_m,z_m,Target,CX,CY,CZ,QW,QX,QY,QZ\n" + rows;
  MeasurementsCsvOptions options;
  options.column_map = MapOf(
      "columns:\n  pose: Target\n  commanded_x_m: CX\n"
      "  commanded_y_m: CY\n  commanded_z_m: CZ\n"
      "  commanded_qw: QW\n  commanded_qx: QX\n  commanded_qy: QY\n"
      "  commanded_qz: QZ\n");
  std::vector<CommandedPose> mapped, direct;
  std::string error;
  ASSERT_TRUE(ParseCommandedPosesCsv(device, "device.csv", model, options,
                                     &mapped, &error))
      << error;
  ASSERT_TRUE(
      ParseCommandedPosesCsv(own, "own.csv", model, {}, &direct, &error))
      << error;
  ASSERT_EQ(mapped.size(), 2u);
  ASSERT_EQ(direct.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(mapped[i].pose, "P1");
    EXPECT_EQ(mapped[i].position, direct[i].position);
    EXPECT_TRUE(mapped[i].has_rotation);
    EXPECT_EQ(mapped[i].rotation, direct[i].rotation);
  }
  // The measurements reader reads the mapped file as the same measurements.
  std::vector<Measurement> a, b;
  ASSERT_TRUE(ParseMeasurementsCsv(device, "device.csv", model, options, &a,
                                   nullptr, &error))
      << error;
  ASSERT_TRUE(
      ParseMeasurementsCsv(own, "own.csv", model, {}, &b, nullptr, &error))
      << error;
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].position, b[i].position);
}

TEST(ColumnMapTest, BadColumnsAreNamedInOneLine) {
  const std::string header =
      "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,X,y_m,z_m\n"
      "0,0,0,0,0,0,1,2,3\n";
  EXPECT_EQ(ApplyError("columns:\n  x_cm: X\n", header),
            "map.yaml:2: columns: x_cm: not an activecal column "
            "(docs/formats.md lists them; joints are q<j>_rad/_deg/_m/_mm or "
            "<joint name>_rad/...)");
  EXPECT_EQ(ApplyError("columns:\n  x_m: measurement_x\n", header),
            "data.csv:1: measurement_x: not in the header (column map "
            "map.yaml:2: columns: x_m)");
  EXPECT_EQ(ApplyError("orientation: {convention: ZYZ, intrinsic: false, "
                       "unit: rad, columns: [X, y_m, a]}\n",
                       header),
            "data.csv:1: a: not in the header (column map map.yaml:1: "
            "orientation.columns)");
  EXPECT_EQ(
      ApplyError("decimal: \",\"\n", "# comment\nq1_rad,q2_rad\n0,0\n"),
      "data.csv:2: header: the column map map.yaml has decimal ',' and the "
      "header's delimiter is ',' (detected): a decimal comma needs "
      "another delimiter");
  EXPECT_EQ(ApplyError("orientation: {convention: ZYZ, intrinsic: false, "
                       "unit: rad, columns: [A, B, C]}\n",
                       "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m,"
                       "A,B,C\n0,0,0,0,0,0,1,2,3,0.1,,0.3\n"),
            "data.csv:2: row: A, B, C as extrinsic ZYZ, rad (map.yaml): some "
            "angles empty, some given (all three or none)");
  EXPECT_EQ(ApplyError("orientation: {convention: ZYZ, intrinsic: false, "
                       "unit: rad, columns: [A, B, C]}\n",
                       "q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m,"
                       "A,B,C\n0,0,0,0,0,0,1,2,3,0.1,x,0.3\n"),
            "data.csv:2: B: expected a number, got 'x'");
  // The reader's own messages keep the file's line numbers.
  EXPECT_EQ(
      ApplyError("delimiter: \";\"\ndecimal: \",\"\ncolumns: {x_mm: X}\n",
                 "# a\n\nq1_rad;q2_rad;q3_rad;q4_rad;q5_rad;q6_rad;X;"
                 "y_mm;z_mm\n0;0;0;0;0;0;1,5;2;3\n0;0;0;0;0;0;1,5;abc;3\n"),
      "data.csv:5: y_mm: expected a number, got 'abc'");
}

}  // namespace
}  // namespace activecal
