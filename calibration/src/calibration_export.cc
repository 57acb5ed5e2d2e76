// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/calibration_export.h"

#include <glog/logging.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>

#include "activecal/core/kinematics.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/robot_loader.h"
#include "activecal/io/ur_kinematics.h"
#include "activecal/io/urdf_export.h"

namespace activecal {

bool MakeCalibratedUrdf(const RobotModel& model,
                        const Eigen::VectorXd& parameters,
                        const std::vector<Measurement>& check,
                        const CalibratedUrdfOptions& options,
                        CalibratedUrdf* urdf, std::string* error) {
  CHECK(urdf != nullptr);
  CHECK(error != nullptr);
  *urdf = CalibratedUrdf();
  UrdfChainOptions chain = options.chain;
  if (!options.source_path.empty()) {
    std::string xml;
    if (!ReadUrdfText(options.source_path, &xml, error) ||
        !CalibratedUrdfText(xml, options.source_path, chain, model, parameters,
                            &urdf->text, &urdf->warnings, error)) {
      return false;
    }
  } else {
    urdf->text = UrdfFromModel(model, parameters, &urdf->warnings);
    chain.base_link = "base_link";
    chain.tip_link = "tip";
  }
  // Reload what is written: it must predict every measured point.
  if (!CheckUrdfAgainstModel(urdf->text, options.output_path, chain, model,
                             parameters, check, &urdf->worst_m, error)) {
    *error = "the written URDF does not reload: " + *error;
    return false;
  }
  if (!(urdf->worst_m <= options.tolerance_m)) {
    *error = "the written URDF predicts the measurements up to " +
             std::to_string(urdf->worst_m) +
             " m away from the calibrated model (more than 1e-9 m)" +
             (urdf->warnings.empty() ? "" : ": " + urdf->warnings[0]);
    return false;
  }
  return true;
}

}  // namespace activecal

namespace activecal {
namespace {

// The chain of `model` at `parameters` from its root link to its tip,
// without the base block (the registration): T(q) = L1(q1) ... Ln(qn) Tip.
void ChainPose(const RobotModel& model, const Eigen::VectorXd& parameters,
               const Eigen::VectorXd& q, Eigen::Matrix3d* R,
               Eigen::Vector3d* t) {
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  R->setIdentity();
  t->setZero();
  for (int i = 0; i < model.num_joints(); ++i) {
    Eigen::Matrix3d Ri;
    Eigen::Vector3d ti;
    LinkTransform(model.links[i], blocks[i + 1], q[i], &Ri, &ti);
    *t += (*R) * ti;
    *R = (*R) * Ri;
  }
  *t += (*R) * model.tip.translation;
  *R = (*R) * model.tip.rotation;
}

// Why `model` is not UR-shaped ("" when it is).
std::string NotUrShaped(const RobotModel& model) {
  if (model.num_joints() != 6) {
    return "a UR has 6 joints, the model has " +
           std::to_string(model.num_joints());
  }
  std::string prefix;
  for (int j = 0; j < 6; ++j) {
    const Link& l = model.links[j];
    const std::string want = kUrJointNames[j];
    const std::string who =
        "joint " + std::to_string(j + 1) + " ('" + l.name + "')";
    if (l.convention != LinkConvention::kUrdf) {
      return who + " is not a URDF joint (a UR is loaded from its URDF)";
    }
    if (l.joint_type != JointType::kRevolute) return who + " is not revolute";
    if (l.name.size() < want.size() ||
        l.name.compare(l.name.size() - want.size(), want.size(), want) != 0) {
      return who + " is not named " + want + " as in ur_description";
    }
    const std::string p = l.name.substr(0, l.name.size() - want.size());
    if (j == 0) prefix = p;
    if (p != prefix) {
      return who + " has another prefix than '" + prefix + "'";
    }
    if (l.axis != Eigen::Vector3d::UnitZ()) {
      return who + " does not turn about its frame's z (axis 0 0 1)";
    }
  }
  return "";
}

}  // namespace

bool MakeUrCalibration(const RobotModel& model,
                       const Eigen::VectorXd& parameters,
                       const std::vector<Measurement>& check,
                       const std::string& comment, UrCalibration* out,
                       std::string* error) {
  CHECK(out != nullptr);
  CHECK(error != nullptr);
  *out = UrCalibration();
  const std::string why = NotUrShaped(model);
  if (!why.empty()) {
    *error = "the robot is not a UR: " + why;
    return false;
  }
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  UrKinematics kinematics;
  // base_link_inertia in base_link: Rz(pi).
  Eigen::Matrix3d R_parent = RpyRotation<double>(0, 0, M_PI).transpose();
  for (int j = 0; j < 6; ++j) {
    const Link& l = model.links[j];
    const double* p = blocks[j + 1];
    if (p[kUrdfGain] != 1.0) {
      *error = "the robot is not a UR: joint " + std::to_string(j + 1) + " ('" +
               l.name + "') has a calibrated gain " +
               std::to_string(p[kUrdfGain]) +
               ", which the UR kinematics file cannot hold (hold gains "
               "fixed at 1)";
      return false;
    }
    // The origin with the offset folded in: the link at reading 0.
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    LinkTransform(l, p, 0.0, &R, &t);
    if (j == 0) {
      t = R_parent * t;
      R = R_parent * R;
    }
    kinematics.joints[j].xyz = t;
    kinematics.joints[j].rpy = RotationToShortRpy(R);
  }
  // A hash of the numbers, so that two calibrations get two names.
  uint64_t hash = 1469598103934665603ull;  // FNV-1a
  const std::string numbers = UrKinematicsText(kinematics, "");
  for (unsigned char c : numbers) {
    hash = (hash ^ c) * 1099511628211ull;
  }
  kinematics.hash = "activecal_" + std::to_string(hash);
  out->text = UrKinematicsText(kinematics, comment);

  // Read back and rebuilt as ur_macro.xacro does.
  UrKinematics written;
  if (!ParseUrKinematics(out->text, "the written UR kinematics", &written,
                         error)) {
    return false;
  }
  std::vector<Eigen::VectorXd> poses;
  for (const Measurement& m : check) {
    poses.push_back(m.joints);
    if (m.type == MeasurementType::kDistance) poses.push_back(m.joints2);
  }
  for (double a : {0.0, 0.7, -1.9, 2.8}) {
    Eigen::VectorXd q(6);
    q << a, -a / 2, a / 3, 1 - a, a * a / 4, -a;
    poses.push_back(q);
  }
  for (const Eigen::VectorXd& q : poses) {
    Eigen::Matrix3d R_model, R_ur;
    Eigen::Vector3d t_model, t_ur;
    ChainPose(model, parameters, q, &R_model, &t_model);
    UrTool0Pose(written, q, &R_ur, &t_ur);
    out->worst_m = std::max(out->worst_m, (t_model - t_ur).norm());
    out->worst_rad = std::max(
        out->worst_rad, Eigen::AngleAxisd(R_model.transpose() * R_ur).angle());
  }
  if (!(out->worst_m <= kUrCalibrationTolerance) ||
      !(out->worst_rad <= kUrCalibrationTolerance)) {
    char text[400];
    std::snprintf(text, sizeof(text),
                  "the written UR kinematics do not reproduce the calibrated "
                  "model: tool0 up to %.3g m and %.3g rad away (more than "
                  "1e-9 m / rad): is the chain base_link -> tool0 (the URDF "
                  "loaded with its default root and tip)?",
                  out->worst_m, out->worst_rad);
    *error = text;
    return false;
  }
  return true;
}

}  // namespace activecal
