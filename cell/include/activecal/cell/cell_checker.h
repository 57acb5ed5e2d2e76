// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Whether a real cell can run a pose: CellChecker holds the robot's
// collision geometry, the cell's obstacles and device as FCL objects and
// checks one joint configuration at a time.
//
//   CellChecker checker;
//   if (!checker.Init(model, collision, cell, &error)) { ... }
//   auto workspace = checker.NewWorkspace();     // one per thread
//   const PoseVerdict v = checker.Check(q.data(), workspace.get());
//   if (!v.feasible()) std::cout << checker.Describe(v) << "\n";
//   // "obstacle table (wrist_3_link)"
//
// The checks, cheapest first; a pose's reason is the first that fails:
//
//   1. joint margin     every joint at least its margin inside its range
//                       (both ends allowed: q == min + margin passes)
//   2. out of range     the device's distance to the target outside its
//                       range_m (every camera's, for mocap)
//   3. out of view      the target outside a camera's field of view
//   4. target facing away
//                       the angle between the target's normal and the
//                       direction from the target to the device above the
//                       target's acceptance angle (exactly at it passes)
//   5. self-collision   two links that are not adjacent (and not in the
//                       skip pairs) closer than self_clearance_m
//   6. obstacle <name>  a link closer to the obstacle than clearance_m
//   7. line of sight blocked
//                       the segment from the device to the target, but for
//                       its last line_of_sight_margin_m, crosses a link or
//                       an obstacle (a beam of radius kBeamRadiusM); a
//                       convex shape (not a mesh) of the tip link's frame
//                       that holds the target, or has it on its surface, is
//                       the target's mount, not an occlusion of its beams
//                       (a beam leaves a convex shape once, at the target)
//
// Steps 2-4 and 7 are per target: a target is seen when it passes them
// all (mocap: at least min_cameras cameras pass them), and a pose passes
// when at least one target is seen; when none is, the reason is the step
// at which the last target dropped out. Without a device every pose that
// passes 1, 5 and 6 is feasible.
//
// Frames: the link frames come from the model's forward kinematics at the
// parameters given (the nominal values unless SetParameters is called,
// e.g. with the current estimate), starting from the robot's base frame
// (the base block B is not applied: the cell is in that frame).
// Adjacent links are those of the same frame or of consecutive frames
// (joint j connects frames j - 1 and j). Bodies fixed to the base frame
// are not checked against obstacles (they cannot move; the cell is built
// around them). Distances come from FCL (fcl::distance: GJK on shapes, the
// OBBRSS tree on meshes); a plane's distance is the shape's support in the
// plane's normal (exact for every primitive; a mesh's nearest vertex).

#ifndef ACTIVECAL_CELL_CELL_CHECKER_H_
#define ACTIVECAL_CELL_CELL_CHECKER_H_

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "activecal/cell/cell_file.h"
#include "activecal/cell/robot_collision.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// The radius of the beam of a line of sight (m).
inline constexpr double kBeamRadiusM = 1e-3;

enum class RejectionReason : uint8_t {
  kNone = 0,
  kJointMargin,
  kOutOfRange,
  kOutOfView,
  kFacingAway,
  kSelfCollision,
  kObstacle,
  kLineOfSight,
};
inline constexpr int kNumRejectionReasons = 8;

// "none", "joint_margin", "out_of_range", "out_of_view", "facing_away",
// "self_collision", "obstacle", "line_of_sight".
const char* RejectionReasonToString(RejectionReason reason);
bool StringToRejectionReason(const std::string& name, RejectionReason* reason);
// "joint margin", "out of range", "out of view", "target facing away",
// "self-collision", "obstacle", "line of sight blocked".
const char* RejectionReasonLabel(RejectionReason reason);

// The verdict on one pose.
struct PoseVerdict {
  RejectionReason reason = RejectionReason::kNone;
  // What failed: joint margin: a = the joint (0-based); self-collision:
  // a, b = the two bodies; obstacle: a = the obstacle, b = the body; line
  // of sight: a = the first target's blocking thing (body index, or
  // -1 - obstacle index); otherwise -1.
  int16_t a = -1;
  int16_t b = -1;
  // Bit t set: target t is seen (feasible poses only).
  uint32_t targets_seen = 0;

  bool feasible() const { return reason == RejectionReason::kNone; }
};

// One distance the checks compare with a clearance.
struct PairDistance {
  std::string first, second;  // body names, or body and obstacle
  bool obstacle = false;      // second is an obstacle
  double distance_m = 0.0;    // < 0 (FCL: -1) when they overlap
};

class CellChecker {
 public:
  // What one thread needs to check poses (FCL objects placed at a pose).
  class Workspace {
   public:
    ~Workspace();

   private:
    friend class CellChecker;
    struct Data;
    Workspace();
    std::unique_ptr<Data> data_;
  };

  CellChecker();
  ~CellChecker();
  CellChecker(const CellChecker&) = delete;
  CellChecker& operator=(const CellChecker&) = delete;

  // Builds the checker. False with a message for names the robot does not
  // have (skip pairs, joint margin overrides: "<file>:<line>:<col>:
  // <field>: ..."), a joint range narrower than twice its margin, more
  // than 32 targets or kMaxCellCameras cameras.
  bool Init(const RobotModel& model, const RobotCollisionModel& robot,
            const Cell& cell, std::string* error);
  // The full parameter vector the link frames are computed at (default:
  // model.nominal).
  bool SetParameters(const Eigen::VectorXd& parameters, std::string* error);

  // A workspace per thread (its FCL objects are moved to each pose).
  std::unique_ptr<Workspace> NewWorkspace() const;

  // Checks q (num_joints values, SI).
  PoseVerdict Check(const double* q, Workspace* workspace) const;
  // Checks only the robot's collisions (self and obstacles, with the
  // clearances): what a move between poses is checked for.
  PoseVerdict CheckCollisions(const double* q, Workspace* workspace) const;

  // "joint margin (elbow_joint)", "self-collision (upper_arm_link,
  // wrist_3_link)", "obstacle table (wrist_3_link)", ...
  std::string Describe(const PoseVerdict& verdict) const;
  // The verdict's subject alone: "elbow_joint", "upper_arm_link|wrist_3_link",
  // "wrist_3_link", "" ...
  std::string Detail(const PoseVerdict& verdict) const;

  // Every distance the collision checks use at q, exact (no early exit,
  // no bounding-ball shortcut): each checked body pair and each checked
  // body-obstacle pair, the least over their shapes.
  std::vector<PairDistance> Distances(const double* q,
                                      Workspace* workspace) const;

  // The link frames at q: frames[0] the base frame (identity), frames[j]
  // after link j (rotation, translation in the base frame).
  void LinkFrames(const double* q, std::vector<FixedTransform>* frames) const;
  // The tip frame at q (the last link's frame, then the model's tip).
  FixedTransform TipFrame(const double* q) const;

  const RobotModel& model() const { return model_; }
  // The full parameter vector the frames are computed at.
  const Eigen::VectorXd& parameters() const;
  const Cell& cell() const { return cell_; }
  const RobotCollisionModel& robot() const { return robot_; }
  int num_targets() const { return static_cast<int>(cell_.targets.size()); }
  bool has_geometry() const { return robot_.num_shapes() > 0; }
  // Body pairs checked for self-collision.
  int num_self_pairs() const;
  // The margin of joint j (rad or m).
  double joint_margin(int j) const { return margins_[j]; }

 private:
  struct Impl;
  // CheckCollisions; frames_ready: the workspace holds q's link frames.
  PoseVerdict Collisions(const double* q, Workspace* workspace,
                         bool frames_ready) const;

  RobotModel model_;
  RobotCollisionModel robot_;
  Cell cell_;
  std::vector<double> margins_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace activecal

#endif  // ACTIVECAL_CELL_CELL_CHECKER_H_
