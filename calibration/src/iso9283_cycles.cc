// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/iso9283_cycles.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <map>

#include "activecal/core/kinematics.h"

namespace activecal {
namespace {

bool Fail(const std::string& message, Iso9283CyclesSummary* summary) {
  summary->ok = false;
  summary->message = message;
  return false;
}

// "<line>": the caller puts the file before it ("cycles.csv:12: pose: ...",
// the format of every reader).
std::string LineOf(int line) { return std::to_string(line); }

nlohmann::json Vec(const Eigen::Vector3d& v, double scale = 1.0) {
  return {v.x() * scale, v.y() * scale, v.z() * scale};
}

nlohmann::json ResultJson(const Iso9283PoseResult& r, bool orientation) {
  const double deg = 180.0 / M_PI;
  nlohmann::json j = {
      {"ap_p_m", r.ap_p_m},        {"ap_xyz_m", Vec(r.ap_xyz_m)},
      {"rp_l_m", r.rp_l_m},        {"l_bar_m", r.l_bar_m},
      {"s_l_m", r.s_l_m},          {"barycentre_m", Vec(r.barycentre_m)},
      {"ap_p_mm", r.ap_p_m * 1e3}, {"ap_xyz_mm", Vec(r.ap_xyz_m, 1e3)},
      {"rp_l_mm", r.rp_l_m * 1e3}};
  if (orientation) {
    j["ap_abc_rad"] = Vec(r.ap_rad);
    j["s_abc_rad"] = Vec(r.s_rad);
    j["rp_abc_rad"] = Vec(r.rp_rad);
    j["ap_abc_mrad"] = Vec(r.ap_rad, 1e3);
    j["rp_abc_mrad"] = Vec(r.rp_rad, 1e3);
    j["ap_abc_deg"] = Vec(r.ap_rad, deg);
    j["rp_abc_deg"] = Vec(r.rp_rad, deg);
  }
  return j;
}

void AppendTable(const std::vector<Iso9283PoseReport>& poses, bool with,
                 std::string* out) {
  int width = 4;
  for (const Iso9283PoseReport& p : poses) {
    width = std::max(width, static_cast<int>(p.pose.size()));
  }
  char line[512];
  std::snprintf(line, sizeof(line),
                "  %-*s %6s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s\n",
                width, "pose", "cycles", "AP_p", "AP_x", "AP_y", "AP_z", "RP_l",
                "AP_a", "AP_b", "AP_c", "RP_a", "RP_b", "RP_c", "max");
  *out += line;
  std::snprintf(line, sizeof(line),
                "  %-*s %6s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s\n",
                width, "", "", "mm", "mm", "mm", "mm", "mm", "mrad", "mrad",
                "mrad", "+-mrad", "+-mrad", "+-mrad", "deg");
  *out += line;
  for (const Iso9283PoseReport& p : poses) {
    const Iso9283PoseResult& r = with ? p.with : p.without;
    std::snprintf(
        line, sizeof(line), "  %-*s %6d %9.3f %9.3f %9.3f %9.3f %9.3f", width,
        p.pose.c_str(), r.num_cycles, r.ap_p_m * 1e3, r.ap_xyz_m.x() * 1e3,
        r.ap_xyz_m.y() * 1e3, r.ap_xyz_m.z() * 1e3, r.rp_l_m * 1e3);
    *out += line;
    if (p.has_orientation) {
      // The largest orientation figure (|AP| or RP) in degrees.
      const double max_deg =
          std::max(r.ap_rad.cwiseAbs().maxCoeff(), r.rp_rad.maxCoeff()) *
          180.0 / M_PI;
      std::snprintf(
          line, sizeof(line), " %9.4f %9.4f %9.4f %9.4f %9.4f %9.4f %9.5f\n",
          r.ap_rad.x() * 1e3, r.ap_rad.y() * 1e3, r.ap_rad.z() * 1e3,
          r.rp_rad.x() * 1e3, r.rp_rad.y() * 1e3, r.rp_rad.z() * 1e3, max_deg);
    } else {
      std::snprintf(line, sizeof(line), " %9s %9s %9s %9s %9s %9s %9s\n", "-",
                    "-", "-", "-", "-", "-", "-");
    }
    *out += line;
  }
}

}  // namespace

std::string Iso9283CyclesSummary::TableText() const {
  std::string out;
  if (!ok) return "ISO 9283: " + message + "\n";
  out +=
      "ISO 9283 pose accuracy (AP) and repeatability (RP), base frame, "
      "without the model (attained as measured):\n";
  AppendTable(poses, false, &out);
  out +=
      "with the model (predicted after compensation by --robot, first "
      "order: the model's error at each cycle):\n";
  AppendTable(poses, true, &out);
  return out;
}

nlohmann::json Iso9283CyclesSummary::Json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const Iso9283PoseReport& p : poses) {
    const Eigen::Quaterniond q(p.commanded.rotation);
    nlohmann::json j = {{"pose", p.pose},
                        {"first_line", p.first_line},
                        {"marker", p.marker + 1},
                        {"num_cycles", p.without.num_cycles},
                        {"orientation", p.has_orientation},
                        {"commanded",
                         {{"position_m", Vec(p.commanded.position)},
                          {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}}}},
                        {"without", ResultJson(p.without, p.has_orientation)},
                        {"with", ResultJson(p.with, p.has_orientation)}};
    if (!p.has_orientation) j["commanded"].erase("quaternion_wxyz");
    list.push_back(j);
  }
  return {{"poses", list},
          {"with_description",
           "predicted after compensation by the model, first order: "
           "x'_j = x_c + (x_j - model(q_j)), R'_j = R_j model_R(q_j)^T R_c"},
          {"without_description", "attained poses as measured"},
          {"frame", "robot base (registered)"}};
}

bool EvaluateIso9283Cycles(const RobotModel& model,
                           const Eigen::VectorXd& parameters,
                           const std::vector<Measurement>& measurements,
                           const std::vector<int>& lines,
                           const std::vector<CommandedPose>& commanded,
                           Iso9283CyclesSummary* summary) {
  *summary = Iso9283CyclesSummary();
  if (parameters.size() != model.num_parameters()) {
    return Fail("the parameter vector has " +
                    std::to_string(parameters.size()) + " values, the model " +
                    std::to_string(model.num_parameters()),
                summary);
  }
  if (lines.size() != measurements.size()) {
    return Fail("one line per measurement is needed", summary);
  }
  std::map<int, const CommandedPose*> by_line;
  for (const CommandedPose& c : commanded) by_line[c.line] = &c;
  // The base frame in the device's frame.
  const std::vector<const double*> blocks =
      BlockPointers(model, parameters.data());
  Eigen::Matrix3d rb;
  Eigen::Vector3d tb;
  LinkTransform(model.base, blocks[0], 0.0, &rb, &tb);

  struct Group {
    Iso9283PoseReport report;
    MeasurementType type = MeasurementType::kPosition;
    std::vector<Iso9283Sample> attained, predicted;
  };
  std::vector<Group> groups;
  std::map<std::string, int> index;
  std::map<int, int> rows_per_line;
  for (size_t i = 0; i < measurements.size(); ++i) {
    const Measurement& m = measurements[i];
    const int line = lines[i];
    if (++rows_per_line[line] > 1) {
      return Fail(
          LineOf(line) +
              ": marker: several markers on one row: the ISO 9283 figures "
              "are of one measured point per cycle",
          summary);
    }
    const auto it = by_line.find(line);
    if (it == by_line.end()) {
      return Fail(LineOf(line) + ": pose: no commanded pose read for this row",
                  summary);
    }
    const CommandedPose& c = *it->second;
    if (m.type == MeasurementType::kDistance) {
      return Fail(LineOf(line) + ": type: pose '" + c.pose +
                      "': a distance row: ISO 9283 cycles are position or "
                      "pose measurements",
                  summary);
    }
    const bool pose = m.type == MeasurementType::kPose;
    if (pose && !c.has_rotation) {
      return Fail(LineOf(line) + ": pose: '" + c.pose +
                      "': a 6D pose row without a commanded orientation "
                      "(commanded_qw,... or commanded_r11..commanded_r33)",
                  summary);
    }
    auto [gi, inserted] =
        index.emplace(c.pose, static_cast<int>(groups.size()));
    if (inserted) {
      Group g;
      g.report.pose = c.pose;
      g.report.first_line = line;
      g.report.marker = m.marker;
      g.report.has_orientation = pose;
      g.report.commanded.position = c.position;
      if (pose) g.report.commanded.rotation = c.rotation;
      g.type = m.type;
      groups.push_back(g);
    }
    Group& g = groups[gi->second];
    const std::string where = LineOf(line) + ": pose: '" + c.pose +
                              "' (first line " + LineOf(g.report.first_line) +
                              ")";
    if (m.type != g.type) {
      return Fail(where + ": a " + MeasurementTypeName(m.type) + " row among " +
                      MeasurementTypeName(g.type) +
                      " rows: the cycles of a pose are measured alike",
                  summary);
    }
    if (m.marker != g.report.marker) {
      return Fail(where + ": marker " + std::to_string(m.marker + 1) +
                      ", the first cycle's is " +
                      std::to_string(g.report.marker + 1) +
                      ": the cycles of a pose measure one point",
                  summary);
    }
    if ((c.position - g.report.commanded.position).norm() > 1e-9 ||
        (pose && (c.rotation - g.report.commanded.rotation).norm() > 1e-9)) {
      return Fail(where +
                      ": a commanded pose other than the first cycle's: the "
                      "cycles of a label go to one commanded pose",
                  summary);
    }
    // Measured and predicted, in the base frame.
    Eigen::Matrix3d r_model;
    Eigen::Vector3d t_model;
    TargetFrame(model, parameters, m.joints, &r_model, &t_model, m.marker);
    Iso9283Sample a, p;
    a.position = rb.transpose() * (m.position - tb);
    p.position =
        g.report.commanded.position + rb.transpose() * (m.position - t_model);
    if (pose) {
      const Eigen::Matrix3d r_meas =
          m.rotation.norm() > 0
              ? Eigen::AngleAxisd(m.rotation.norm(), m.rotation.normalized())
                    .toRotationMatrix()
              : Eigen::Matrix3d::Identity();
      a.rotation = rb.transpose() * r_meas;
      p.rotation = rb.transpose() * r_meas * r_model.transpose() * rb *
                   g.report.commanded.rotation;
    }
    g.attained.push_back(a);
    g.predicted.push_back(p);
  }
  if (groups.empty()) return Fail("no cycles", summary);
  for (Group& g : groups) {
    std::string error;
    if (g.attained.size() < 2) {
      return Fail(LineOf(g.report.first_line) + ": pose: '" + g.report.pose +
                      "' has 1 cycle: ISO 9283 needs at least 2 cycles to "
                      "each pose (the standard runs 30)",
                  summary);
    }
    if (!Iso9283Pose(g.report.commanded, g.attained, &g.report.without,
                     &error) ||
        !Iso9283Pose(g.report.commanded, g.predicted, &g.report.with, &error)) {
      return Fail(LineOf(g.report.first_line) + ": pose: '" + g.report.pose +
                      "': " + error,
                  summary);
    }
    summary->poses.push_back(g.report);
  }
  summary->ok = true;
  return true;
}

}  // namespace activecal
