// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/cell_planning.h"

#include <memory>
#include <utility>
#include <vector>

namespace activecal {

std::string FeasibleNote(const CellChecker& checker,
                         const PoolFilterSummary& summary) {
  std::string note =
      std::to_string(summary.num_feasible()) + " of " +
      std::to_string(summary.num_poses) +
      " poses feasible; rejected: " + summary.CountsText(checker);
  const RejectionCounts& counts = summary.counts;
  if (summary.num_feasible() != 0 || counts.num_rejected() == 0) return note;
  // None left: name the most frequent reason (the first of equal counts),
  // and for a collision the pair to blame.
  int best = 0;
  for (int r = 1; r < kNumRejectionReasons; ++r) {
    if (counts.rejected[r] > counts.rejected[best]) best = r;
  }
  const RejectionReason reason = static_cast<RejectionReason>(best);
  if (reason == RejectionReason::kSelfCollision ||
      reason == RejectionReason::kObstacle) {
    return note + "; " + counts.CollisionDiagnosis(checker);
  }
  note += "; most often (" + std::to_string(counts.rejected[best]) + " of " +
          std::to_string(counts.num_checked) +
          " poses): " + RejectionReasonLabel(reason);
  // A pair that rejected every pose reaching its check is the blocker
  // still (the earlier checks only came first).
  const std::string diagnosis = counts.CollisionDiagnosis(checker);
  if (diagnosis.rfind("every pose", 0) == 0) note += "; " + diagnosis;
  return note;
}

PoolFilter CellPoolFilter(const CellChecker& checker,
                          const PoolFilterOptions& options,
                          PoolFilterSummary* summary) {
  return [&checker, options, summary](const Eigen::MatrixXd& joints,
                                      std::vector<int64_t>* kept,
                                      std::string* note) {
    if (!FilterPool(checker, joints, options, summary)) {
      *note = summary->message;
      return false;
    }
    *kept = summary->feasible;
    *note = FeasibleNote(checker, *summary);
    return true;
  };
}

bool CellTargetsAreMarkers(const CellChecker& checker,
                           const RobotModel& model) {
  return checker.num_targets() > 1 &&
         checker.num_targets() == model.num_markers();
}

void SetCellPoolFilter(const CellChecker& checker, const RobotModel& model,
                       const PoolFilterOptions& filter_options,
                       PoolFilterSummary* summary,
                       SelectionPoolOptions* options) {
  options->filter = CellPoolFilter(checker, filter_options, summary);
  options->kept_marker_masks =
      CellTargetsAreMarkers(checker, model) ? &summary->targets_seen : nullptr;
}

nlohmann::json CellPoolJson(const Cell& cell,
                            const PoolFilterSummary& summary) {
  nlohmann::json rejected = nlohmann::json::object();
  for (int r = 1; r < kNumRejectionReasons; ++r) {
    const RejectionReason reason = static_cast<RejectionReason>(r);
    if (reason == RejectionReason::kObstacle) {
      nlohmann::json by_obstacle = nlohmann::json::object();
      for (size_t o = 0; o < cell.obstacles.size(); ++o) {
        by_obstacle[cell.obstacles[o].name] =
            o < summary.rejected_by_obstacle.size()
                ? summary.rejected_by_obstacle[o]
                : 0;
      }
      rejected["obstacle"] = std::move(by_obstacle);
    } else {
      rejected[RejectionReasonToString(reason)] = summary.rejected[r];
    }
  }
  return {{"feasible_poses", summary.num_feasible()},
          {"rejected", std::move(rejected)}};
}

nlohmann::json TargetsSeenJson(const Cell& cell, uint32_t seen) {
  nlohmann::json names = nlohmann::json::array();
  for (size_t t = 0; t < cell.targets.size() && t < 32; ++t) {
    if (seen & (1u << t)) names.push_back(cell.targets[t].name);
  }
  return names;
}

std::string TargetsSeenField(const Cell& cell, uint32_t seen) {
  std::string field;
  for (size_t t = 0; t < cell.targets.size() && t < 32; ++t) {
    if (!(seen & (1u << t))) continue;
    if (!field.empty()) field += ';';
    field += cell.targets[t].name;
  }
  if (field.find_first_of(",\"") == std::string::npos) return field;
  std::string quoted = "\"";
  for (char c : field) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + "\"";
}

std::string PosesCsvWithTargets(const std::string& poses_csv, const Cell& cell,
                                const std::vector<uint32_t>& seen) {
  std::string out;
  size_t line = 0, begin = 0;
  while (begin < poses_csv.size()) {
    size_t end = poses_csv.find('\n', begin);
    if (end == std::string::npos) end = poses_csv.size();
    out.append(poses_csv, begin, end - begin);
    if (line == 0) {
      out += ",targets";
    } else if (line - 1 < seen.size()) {
      out += "," + TargetsSeenField(cell, seen[line - 1]);
    }
    out += '\n';
    ++line;
    begin = end + 1;
  }
  return out;
}

std::function<bool(const Eigen::VectorXd& joints, std::string* reason)>
CellCompensationCheck(const CellChecker& checker) {
  std::shared_ptr<CellChecker::Workspace> workspace = checker.NewWorkspace();
  return [&checker, workspace](const Eigen::VectorXd& joints,
                               std::string* reason) {
    // Check() tests the joint margins first; a pose it rejects for a
    // measurement reason is then checked for collisions alone.
    PoseVerdict v = checker.Check(joints.data(), workspace.get());
    switch (v.reason) {
      case RejectionReason::kOutOfRange:
      case RejectionReason::kOutOfView:
      case RejectionReason::kFacingAway:
      case RejectionReason::kLineOfSight:
        v = checker.CheckCollisions(joints.data(), workspace.get());
        break;
      default:
        break;
    }
    if (v.feasible()) return true;
    if (reason) *reason = checker.Describe(v);
    return false;
  };
}

nlohmann::json MovesCheckedJson(bool with_cell, const CellSetup& cell,
                                const std::string& no_cell) {
  bool geometry = false;
  for (const CollisionBody& body : cell.collision.bodies) {
    geometry = geometry || !body.shapes.empty();
  }
  if (with_cell && geometry) return {{"moves_checked", true}};
  return {{"moves_checked", false},
          {"moves_not_checked", with_cell ? "no collision geometry" : no_cell}};
}

std::string AssumedVelocityNote(const RobotModel& model,
                                const std::vector<double>& velocity_limits) {
  std::string joints;
  int count = 0;
  bool prismatic = false;
  for (size_t j = 0; j < velocity_limits.size(); ++j) {
    if (velocity_limits[j] > 0) continue;
    joints += (count++ ? ", " : "") + std::to_string(j + 1);
    prismatic =
        prismatic || (j < model.links.size() &&
                      model.links[j].joint_type == JointType::kPrismatic);
  }
  if (count == 0) return "";
  return std::string(count == 1 ? "joint " : "joints ") + joints +
         (count == 1 ? " has" : " have") +
         " no velocity limit in the robot's file: taken at 1 rad/s" +
         (prismatic ? " (1 m/s prismatic)" : "") +
         " for the motion-time estimate";
}

nlohmann::json BlockedMovesJson(const std::vector<int>& blocked_moves,
                                const std::vector<std::string>& reasons,
                                const std::vector<int64_t>& run) {
  nlohmann::json list = nlohmann::json::array();
  for (size_t b = 0; b < blocked_moves.size(); ++b) {
    const int k = blocked_moves[b];
    list.push_back({{"from", k},
                    {"to", k + 1},
                    {"from_pose_index", run[k]},
                    {"to_pose_index", run[k + 1]},
                    {"reason", b < reasons.size() ? reasons[b] : ""}});
  }
  return list;
}

nlohmann::json TourJson(const TourSummary& tour, double resolution_deg,
                        const std::vector<int64_t>& run,
                        const nlohmann::json& moves_checked,
                        const std::string& velocity_note) {
  nlohmann::json t = {{"motion_time_before_s", tour.time_before_s},
                      {"motion_time_after_s", tour.time_after_s},
                      {"velocities", tour.velocities},
                      {"resolution_deg", resolution_deg},
                      {"blocked_moves", tour.blocked_moves.size()},
                      {"blocked", BlockedMovesJson(tour.blocked_moves,
                                                   tour.blocked_reasons, run)},
                      {"blocked_moves_before", tour.blocked_before}};
  t.update(moves_checked);
  if (!velocity_note.empty()) t["velocity_note"] = velocity_note;
  return t;
}

}  // namespace activecal
