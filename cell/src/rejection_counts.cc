// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/cell/rejection_counts.h"

#include <cstdio>

#include "activecal/core/text_table.h"

namespace activecal {
namespace {

// The order the counts are printed in (the issue's).
constexpr RejectionReason kCountOrder[] = {
    RejectionReason::kJointMargin, RejectionReason::kSelfCollision,
    RejectionReason::kObstacle,    RejectionReason::kOutOfRange,
    RejectionReason::kOutOfView,   RejectionReason::kFacingAway,
    RejectionReason::kLineOfSight};

bool IsCollision(RejectionReason r) {
  return r == RejectionReason::kSelfCollision ||
         r == RejectionReason::kObstacle;
}

std::string BodyName(const CellChecker& checker, int b) {
  const auto& bodies = checker.robot().bodies;
  return b >= 0 && b < static_cast<int>(bodies.size()) ? bodies[b].name
                                                       : std::string("?");
}

// The pair's distance at its first pose ("0.027 m apart", "overlapping"),
// or empty when the checker does not list it.
std::string PairDistanceText(const CellChecker& checker,
                             const RejectionCounts::Collision& c,
                             const std::string& first,
                             const std::string& second) {
  if (c.first_joints.size() !=
      static_cast<size_t>(checker.model().num_joints())) {
    return "";
  }
  auto workspace = checker.NewWorkspace();
  const bool obstacle = c.reason == RejectionReason::kObstacle;
  for (const PairDistance& d :
       checker.Distances(c.first_joints.data(), workspace.get())) {
    if (d.obstacle != obstacle) continue;
    const bool match = (d.first == first && d.second == second) ||
                       (!obstacle && d.first == second && d.second == first);
    if (!match) continue;
    return d.distance_m < 0 ? "overlapping"
                            : FormatNumber("%.3g", d.distance_m) + " m apart";
  }
  return "";
}

}  // namespace

std::string RejectionCountsText(
    const CellChecker& checker,
    const std::array<int64_t, kNumRejectionReasons>& rejected,
    const std::vector<int64_t>& rejected_by_obstacle) {
  std::string text;
  auto add = [&](const std::string& label, int64_t n) {
    text += (text.empty() ? "" : ", ") + label + " " + std::to_string(n);
  };
  const bool cameras = checker.cell().has_device &&
                       checker.cell().device.type != DeviceType::kLaserTracker;
  for (RejectionReason r : kCountOrder) {
    if (r == RejectionReason::kObstacle) {
      for (size_t o = 0; o < checker.cell().obstacles.size(); ++o) {
        add("obstacle " + checker.cell().obstacles[o].name,
            o < rejected_by_obstacle.size() ? rejected_by_obstacle[o] : 0);
      }
      continue;
    }
    if (r == RejectionReason::kOutOfView && !cameras) continue;
    add(RejectionReasonLabel(r), rejected[static_cast<int>(r)]);
  }
  return text;
}

void RejectionCounts::Add(const PoseVerdict& v, const double* q,
                          int num_joints) {
  ++num_checked;
  if (v.feasible()) {
    ++num_feasible;
    return;
  }
  ++rejected[static_cast<int>(v.reason)];
  if (v.reason == RejectionReason::kObstacle && v.a >= 0) {
    if (rejected_by_obstacle.size() <= static_cast<size_t>(v.a)) {
      rejected_by_obstacle.resize(v.a + 1, 0);
    }
    ++rejected_by_obstacle[v.a];
  }
  if (!IsCollision(v.reason)) return;
  for (Collision& c : collisions) {
    if (c.reason == v.reason && c.a == v.a && c.b == v.b) {
      ++c.count;
      return;
    }
  }
  Collision c;
  c.reason = v.reason;
  c.a = v.a;
  c.b = v.b;
  c.count = 1;
  c.first_joints.assign(q, q + num_joints);
  collisions.push_back(std::move(c));
}

void RejectionCounts::Merge(const RejectionCounts& other) {
  num_checked += other.num_checked;
  num_feasible += other.num_feasible;
  for (int k = 0; k < kNumRejectionReasons; ++k)
    rejected[k] += other.rejected[k];
  if (rejected_by_obstacle.size() < other.rejected_by_obstacle.size()) {
    rejected_by_obstacle.resize(other.rejected_by_obstacle.size(), 0);
  }
  for (size_t o = 0; o < other.rejected_by_obstacle.size(); ++o) {
    rejected_by_obstacle[o] += other.rejected_by_obstacle[o];
  }
  for (const Collision& theirs : other.collisions) {
    bool found = false;
    for (Collision& c : collisions) {
      if (c.reason == theirs.reason && c.a == theirs.a && c.b == theirs.b) {
        c.count += theirs.count;
        found = true;
        break;
      }
    }
    if (!found) collisions.push_back(theirs);
  }
}

int64_t RejectionCounts::num_collisions() const {
  return rejected[static_cast<int>(RejectionReason::kSelfCollision)] +
         rejected[static_cast<int>(RejectionReason::kObstacle)];
}

const RejectionCounts::Collision* RejectionCounts::MostFrequentCollision()
    const {
  const Collision* best = nullptr;
  for (const Collision& c : collisions) {
    if (best == nullptr || c.count > best->count) best = &c;
  }
  return best;
}

std::string RejectionCounts::CountsText(const CellChecker& checker) const {
  return RejectionCountsText(checker, rejected, rejected_by_obstacle);
}

std::string RejectionCounts::CollisionDiagnosis(
    const CellChecker& checker) const {
  const Collision* c = MostFrequentCollision();
  if (c == nullptr) return "";
  // The poses that reached the pair's check: those rejected by it or by a
  // later check (obstacles after self-collision, the line of sight last),
  // and the feasible.
  const bool obstacle = c->reason == RejectionReason::kObstacle;
  const int64_t reached =
      rejected[static_cast<int>(RejectionReason::kObstacle)] +
      (obstacle ? 0
                : rejected[static_cast<int>(RejectionReason::kSelfCollision)]) +
      rejected[static_cast<int>(RejectionReason::kLineOfSight)] + num_feasible;
  std::string head;
  if (c->count == num_checked) {
    head = "every pose: ";
  } else if (c->count == reached) {
    head = std::string("every pose that reached the ") +
           (obstacle ? "obstacle" : "collision") + " checks (" +
           std::to_string(reached) + " of " + std::to_string(num_checked) +
           "): ";
  } else {
    head = "most often (" + std::to_string(c->count) + " of " +
           std::to_string(num_checked) + " poses): ";
  }
  const Cell& cell = checker.cell();
  if (obstacle) {
    const std::string link = BodyName(checker, c->b);
    const std::string obstacle =
        c->a >= 0 && c->a < static_cast<int>(cell.obstacles.size())
            ? cell.obstacles[c->a].name
            : std::string("?");
    std::string apart = PairDistanceText(checker, *c, link, obstacle);
    apart += (apart.empty() ? "" : ", ") + std::string("clearance_m ") +
             FormatNumber("%.3g", cell.clearance_m);
    return head + "link '" + link + "' collides with obstacle '" + obstacle +
           "' (" + apart + "); is '" + obstacle +
           "' clear of the robot's base (the cell is in the robot's base "
           "frame), and clearance_m less than that link can keep from it?";
  }
  const std::string first = BodyName(checker, c->a);
  const std::string second = BodyName(checker, c->b);
  std::string apart = PairDistanceText(checker, *c, first, second);
  apart += (apart.empty() ? "" : ", ") + std::string("self_clearance_m ") +
           FormatNumber("%.3g", cell.self_clearance_m);
  return head + "links '" + first + "' and '" + second + "' collide (" + apart +
         "); lower self_clearance_m or add the pair to skip_pairs";
}

}  // namespace activecal
