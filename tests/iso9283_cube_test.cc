// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The ISO 9283 cube test poses (calibration/iso9283_cube.h): the geometry
// (P1 the centre, P2-P5 on the diagonals of the plane C1-C2-C7-C8 at 10 %
// of the diagonal from the corners, in a turned cube too) checked by
// distances and a plane normal computed here, and the inverse kinematics
// reaching every point and the orientation to 1e-9.

#include "activecal/calibration/iso9283_cube.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "activecal/core/kinematics.h"
#include "activecal/core/puma560.h"
#include "activecal/io/csv_files.h"

namespace activecal {
namespace {

void CheckGeometry(const Iso9283CubeOptions& o) {
  std::vector<Eigen::Vector3d> p, c;
  Iso9283CubePoints(o, &p, &c);
  ASSERT_EQ(p.size(), 5u);
  ASSERT_EQ(c.size(), 4u);
  const double e = o.edge_m, diagonal = std::sqrt(3.0) * e;
  // The corners: C1-C2 and C7-C8 are opposite edges (length e, parallel),
  // C1-C7 and C2-C8 space diagonals, every corner sqrt(3) e / 2 from c.
  EXPECT_NEAR((c[1] - c[0]).norm(), e, 1e-12);
  EXPECT_NEAR((c[2] - c[3]).norm(), e, 1e-12);
  EXPECT_NEAR((c[1] - c[0] - (c[2] - c[3])).norm(), 0.0, 1e-12);
  EXPECT_NEAR((c[2] - c[0]).norm(), diagonal, 1e-12);
  EXPECT_NEAR((c[3] - c[1]).norm(), diagonal, 1e-12);
  EXPECT_NEAR((c[3] - c[0]).norm(), std::sqrt(2.0) * e, 1e-12);
  for (const Eigen::Vector3d& k : c) {
    EXPECT_NEAR((k - o.centre_m).norm(), diagonal / 2, 1e-12);
  }
  // P1 the centre; P2..P5 on the plane, 10 % of the diagonal from C1, C2,
  // C7, C8 and 90 % from the opposite corners (so on the diagonal).
  EXPECT_NEAR((p[0] - o.centre_m).norm(), 0.0, 1e-15);
  const Eigen::Vector3d normal = (c[1] - c[0]).cross(c[3] - c[0]).normalized();
  const int opposite[4] = {2, 3, 0, 1};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& q = p[k + 1];
    EXPECT_NEAR((q - c[0]).dot(normal), 0.0, 1e-12) << "P" << k + 2;
    EXPECT_NEAR((q - c[k]).norm(), 0.1 * diagonal, 1e-12) << "P" << k + 2;
    EXPECT_NEAR((q - c[opposite[k]]).norm(), 0.9 * diagonal, 1e-12);
    // Inside the cube, 0.4 of the diagonal from the centre.
    EXPECT_NEAR((q - o.centre_m).norm(), 0.4 * diagonal, 1e-12);
  }
}

TEST(Iso9283CubeTest, Geometry) {
  Iso9283CubeOptions o;
  o.centre_m = Eigen::Vector3d(0.5, -0.1, 0.3);
  o.edge_m = 0.4;
  CheckGeometry(o);
  // The base's axes: C1 the corner of the smallest x, y, z.
  std::vector<Eigen::Vector3d> p, c;
  Iso9283CubePoints(o, &p, &c);
  EXPECT_NEAR((c[0] - Eigen::Vector3d(0.3, -0.3, 0.1)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((p[1] - Eigen::Vector3d(0.34, -0.26, 0.14)).norm(), 0.0, 1e-15);
  // A turned cube.
  o.cube_rotation =
      Eigen::Quaterniond(
          Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()))
          .toRotationMatrix();
  CheckGeometry(o);
}

TEST(Iso9283CubeTest, SolvedPosesReachThePoints) {
  const RobotModel model = Puma560PaperModel();
  // A cube about the marker's point at a configuration away from the
  // wrist's singularity, with its orientation.
  Eigen::VectorXd q0(model.num_joints());
  const double offset[6] = {0.3, -0.4, 0.5, 0.3, 0.7, 0.2};
  for (int j = 0; j < model.num_joints(); ++j) {
    q0[j] =
        0.5 * (model.links[j].joint_min + model.links[j].joint_max) + offset[j];
  }
  const std::vector<const double*> blocks =
      BlockPointers(model, model.nominal.data());
  Eigen::Matrix3d rb, r;
  Eigen::Vector3d tb, t;
  LinkTransform(model.base, blocks[0], 0.0, &rb, &tb);
  TargetFrame(model, model.nominal, q0, &r, &t);
  Iso9283CubeOptions o;
  o.centre_m = rb.transpose() * (t - tb);
  o.has_tool_rotation = true;
  o.tool_rotation = rb.transpose() * r;
  o.edge_m = 0.2;
  Iso9283CubeSummary s;
  ASSERT_TRUE(DesignIso9283Cube(model, model.nominal, o, &s)) << s.message;
  ASSERT_EQ(s.joints.rows(), 5);
  for (int k = 0; k < 5; ++k) {
    TargetFrame(model, model.nominal, s.joints.row(k).transpose(), &r, &t);
    EXPECT_LT((rb.transpose() * (t - tb) - s.points_m[k]).norm(), 1e-9)
        << s.labels[k];
    const Eigen::AngleAxisd d(rb.transpose() * r * s.tool_rotation.transpose());
    EXPECT_LT(std::abs(d.angle()), 1e-9) << s.labels[k];
    EXPECT_TRUE(model.CheckJointValues(s.joints.row(k).transpose(), nullptr));
  }
  // The poses file: the pose labels and the commanded poses, read back by
  // the reader of ISO 9283 cycles.
  const std::string poses = Iso9283CubePosesCsvText(model, s);
  std::vector<CommandedPose> commanded;
  std::string error;
  ASSERT_TRUE(ParseCommandedPosesCsv(
      poses, "cube.csv", model, MeasurementsCsvOptions(), &commanded, &error))
      << error;
  ASSERT_EQ(commanded.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(commanded[k].pose, s.labels[k]);
    EXPECT_EQ(commanded[k].position, s.points_m[k]);
    EXPECT_LT((commanded[k].rotation - s.tool_rotation).norm(), 1e-15);
  }
  EXPECT_NE(s.TableText().find("P5"), std::string::npos);
  // A cube beyond the reach: the pose named.
  o.centre_m.x() += 10.0;
  EXPECT_FALSE(DesignIso9283Cube(model, model.nominal, o, &s));
  EXPECT_EQ(s.message.rfind("P1 at (", 0), 0u) << s.message;
  EXPECT_NE(s.message.find("unreachable"), std::string::npos) << s.message;
}

TEST(Iso9283CubeTest, FlagText) {
  Iso9283CubeOptions o;
  std::string error;
  ASSERT_TRUE(ParseIso9283Cube("0.5,0,0.4,0.3", "", &o, &error)) << error;
  EXPECT_DOUBLE_EQ(o.edge_m, 0.3);
  EXPECT_FALSE(o.has_tool_rotation);
  ASSERT_TRUE(ParseIso9283Cube("0.5,0,0.4,0.3,0,0,0,1", "0,1,0,0", &o, &error))
      << error;
  EXPECT_NEAR(o.cube_rotation(0, 0), -1.0, 1e-15);  // 180 deg about z
  EXPECT_TRUE(o.has_tool_rotation);
  EXPECT_NEAR(o.tool_rotation(2, 2), -1.0, 1e-15);  // 180 deg about x
  EXPECT_FALSE(ParseIso9283Cube("0.5,0,0.4", "", &o, &error));
  EXPECT_NE(error.find("got 3 values"), std::string::npos) << error;
  EXPECT_FALSE(ParseIso9283Cube("0.5,0,0.4,-1", "", &o, &error));
  EXPECT_NE(error.find("edge (value 4) must be > 0"), std::string::npos);
  EXPECT_FALSE(ParseIso9283Cube("0.5,x,0.4,1", "", &o, &error));
  EXPECT_NE(error.find("value 2 is 'x'"), std::string::npos) << error;
  EXPECT_FALSE(ParseIso9283Cube("0.5,0,0.4,1", "1,1,0,0", &o, &error));
  EXPECT_NE(error.find("norm 1.41421"), std::string::npos) << error;
}

}  // namespace
}  // namespace activecal
