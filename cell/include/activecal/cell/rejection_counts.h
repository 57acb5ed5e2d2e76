// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Why the poses a cell checked were rejected: the count per reason (the
// obstacle ones per obstacle) and per pair of things that collided, and,
// for a cell that admits no pose, which link and which obstacle (or which
// two links) are to blame, with their distance, so that the user can fix
// the cell file.
//
//   RejectionCounts counts;
//   for (...) counts.Add(checker.Check(q, w), q, num_joints);
//   counts.CountsText(checker);
//   // "joint margin 0, self-collision 0, obstacle table 4000, out of
//   //  range 0, target facing away 0, line of sight blocked 0"
//   counts.CollisionDiagnosis(checker);
//   // "every pose: link 'shoulder_link' collides with obstacle 'table'
//   //  (0.027 m apart, clearance_m 0.05) - is 'table' clear of the
//   //  robot's base (the cell is in its base frame), and clearance_m
//   //  less than that link can keep from it?"
//
// Deterministic: Merge in a fixed order (e.g. draw order) gives the same
// counts, pairs and example poses whatever the thread count.

#ifndef ACTIVECAL_CELL_REJECTION_COUNTS_H_
#define ACTIVECAL_CELL_REJECTION_COUNTS_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "activecal/cell/cell_checker.h"

namespace activecal {

// "joint margin 12, self-collision 3, obstacle table 40, obstacle wall 2,
// out of range 0, out of view 0, target facing away 120, line of sight
// blocked 1" (out of view only for cameras; every obstacle of the cell,
// in its order). rejected: index RejectionReason; rejected_by_obstacle:
// index the cell's obstacles (missing entries count 0).
std::string RejectionCountsText(
    const CellChecker& checker,
    const std::array<int64_t, kNumRejectionReasons>& rejected,
    const std::vector<int64_t>& rejected_by_obstacle);

struct RejectionCounts {
  // One pair that collided: self-collision (a, b: the two bodies) or
  // obstacle (a: the obstacle, b: the body), as in PoseVerdict.
  struct Collision {
    RejectionReason reason = RejectionReason::kNone;
    int a = -1;
    int b = -1;
    int64_t count = 0;
    // The joints of the first pose it rejected.
    std::vector<double> first_joints;
  };

  int64_t num_checked = 0;  // verdicts added, feasible ones too
  int64_t num_feasible = 0;
  std::array<int64_t, kNumRejectionReasons> rejected{};
  std::vector<int64_t> rejected_by_obstacle;  // grows as needed
  // In order of first appearance.
  std::vector<Collision> collisions;

  // Counts one verdict on the pose q (num_joints values).
  void Add(const PoseVerdict& verdict, const double* q, int num_joints);
  // Adds other's counts after this one's (other's pairs new here keep
  // other's example pose).
  void Merge(const RejectionCounts& other);

  int64_t num_rejected() const { return num_checked - num_feasible; }
  // The poses rejected by a collision (self or obstacle).
  int64_t num_collisions() const;
  // The pair with the largest count (the first seen of equal counts);
  // null when no pose was rejected by a collision.
  const Collision* MostFrequentCollision() const;

  // RejectionCountsText of these counts.
  std::string CountsText(const CellChecker& checker) const;
  // Empty when no pose was rejected by a collision. Otherwise the most
  // frequent pair, its distance at the first pose it rejected and the
  // clearance, and what to look at in the cell file:
  //   every pose: ...            the pair rejected every pose checked
  //   every pose that reached the obstacle checks (N of M): ...
  //                              the pair rejected every pose that passed
  //                              the earlier checks (joints, targets,
  //                              self-collision; "collision checks" for a
  //                              self pair): none of them is feasible
  //   most often (N of M poses): ...   otherwise
  std::string CollisionDiagnosis(const CellChecker& checker) const;
};

}  // namespace activecal

#endif  // ACTIVECAL_CELL_REJECTION_COUNTS_H_
