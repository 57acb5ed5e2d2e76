// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The cell wherever a pose is planned (activecal_select, activecal_active,
// activecal_compensate, the Python module): the pool filter that runs the
// cell's checks (cell/pool_filter.h) and keeps their verdicts, the one line
// that says what they removed, the counts as the programs' JSON, and the
// check of a compensated configuration.
//
//   PoolFilterSummary feasibility;
//   SelectionPoolOptions pool_options;
//   pool_options.filter = CellPoolFilter(checker, filter_options,
//                                        &feasibility);
//   BuildSelectionPool(&model, joints, pool_options, &pool, &summary);
//   j.update(CellPoolJson(checker.cell(), feasibility));
//   // {"feasible_poses": 210, "rejected": {"joint_margin": 12, ...,
//   //  "obstacle": {"table": 40, "wall": 2}, ...}}

#ifndef ACTIVECAL_CALIBRATION_CELL_PLANNING_H_
#define ACTIVECAL_CALIBRATION_CELL_PLANNING_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "activecal/calibration/selection_pool.h"
#include "activecal/cell/cell_checker.h"
#include "activecal/cell/cell_file.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/cell/pool_filter.h"
#include "activecal/cell/tour.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// "210 of 1000 poses feasible; rejected: joint margin 12, ..." (the
// counts of PoolFilterSummary::CountsText); when no pose is feasible, then
// "; " and the most frequent reason: for a self-collision or an obstacle the
// pair to blame (RejectionCounts::CollisionDiagnosis: "every pose: link
// 'shoulder_link' collides with obstacle 'table' ..."), else "most often
// (180 of 200 poses): target facing away", followed by the pair when it
// rejected every pose that reached its check ("; every pose that reached
// the obstacle checks (20 of 200): link ...").
std::string FeasibleNote(const CellChecker& checker,
                         const PoolFilterSummary& summary);

// A SelectionPoolOptions::filter: FilterPool(checker, joints, options)
// into *summary (which must outlive the filter), keeping the feasible rows,
// its note FeasibleNote. `checker` must outlive the filter too.
PoolFilter CellPoolFilter(const CellChecker& checker,
                          const PoolFilterOptions& options,
                          PoolFilterSummary* summary);

// Whether the cell's targets are the model's markers, one for one (their
// counts equal, e.g. SetUpCell's targets_as_markers), with more than one:
// then a pose's design rows are those of the markers seen only.
bool CellTargetsAreMarkers(const CellChecker& checker, const RobotModel& model);

// options->filter = CellPoolFilter(checker, filter_options, summary), and,
// when CellTargetsAreMarkers, options->kept_marker_masks =
// &summary->targets_seen: each feasible pose's block then holds the rows
// of the targets it sees only (the unseen ones zero).
void SetCellPoolFilter(const CellChecker& checker, const RobotModel& model,
                       const PoolFilterOptions& filter_options,
                       PoolFilterSummary* summary,
                       SelectionPoolOptions* options);

// What the programs write: {"feasible_poses": N, "rejected": {reason:
// count for every RejectionReason but none, "obstacle": {obstacle name:
// count}}} (reason spelled by RejectionReasonToString).
nlohmann::json CellPoolJson(const Cell& cell, const PoolFilterSummary& summary);

// The names of the cell's targets whose bits are set in `seen`
// (PoseVerdict::targets_seen), in the cell's order.
nlohmann::json TargetsSeenJson(const Cell& cell, uint32_t seen);

// The targets seen as a CSV field: their names in the cell's order, joined
// by ';' ("front;side"), quoted as CSV when a name holds ',' or '"'.
std::string TargetsSeenField(const Cell& cell, uint32_t seen);

// A poses CSV (PosesCsvText: a header line, then one line per pose) with
// one more column, `targets`: TargetsSeenField of seen[k] on pose k's line
// (the poses CSV readers ignore the column). seen: one mask per pose.
std::string PosesCsvWithTargets(const std::string& poses_csv, const Cell& cell,
                                const std::vector<uint32_t>& seen);

// A CompensationOptions::check (kinematics/compensation.h): what a robot
// running a configuration must pass, of the cell's checks: the joint
// margins and the collisions (self, obstacles, with the clearances); not
// the measurement's (range, view, facing, line of sight: a compensated
// program is run, not measured). False with the first failure described
// ("joint margin (elbow_joint)", "obstacle table (wrist_3_link)",
// "self-collision (upper_arm_link, wrist_3_link)"). The checker, set to the
// parameters the program runs on (CellChecker::SetParameters), must
// outlive the check; the check is for one thread at a time.
std::function<bool(const Eigen::VectorXd& joints, std::string* reason)>
CellCompensationCheck(const CellChecker& checker);

// The programs' and the Python module's tour JSON (activecal_select,
// activecal_active --order=shortest; select(order="shortest")).
//
// What a tour's moves were checked for collisions against, for the JSON's
// `tour`: {"moves_checked": true} with a cell and robot collision geometry,
// else {"moves_checked": false, "moves_not_checked": "no --cell" | "no
// collision geometry"} (no_cell: the Python module's "no cell="; the robot
// file, e.g. activecal_simulate
// --true_model_out's YAML, has none: nothing in the cell can be hit).
nlohmann::json MovesCheckedJson(bool with_cell, const CellSetup& cell,
                                const std::string& no_cell = "no --cell");

// For a motion-time estimate at `velocity_limits` (RobotVelocityLimits; <= 0:
// the file gives none): "" when every joint has a limit, else the note
// "joints 1, 2 have no velocity limit in the robot's file: taken at 1 rad/s
// (1 m/s prismatic) for the motion-time estimate".
std::string AssumedVelocityNote(const RobotModel& model,
                                const std::vector<double>& velocity_limits);

// The blocked moves of a tour as the JSON's list: {"from", "to" (places in
// `run`, the tour's order), "from_pose_index", "to_pose_index" (run's
// entries), "reason"}.
nlohmann::json BlockedMovesJson(const std::vector<int>& blocked_moves,
                                const std::vector<std::string>& reasons,
                                const std::vector<int64_t>& run);

// A tour as the JSON's `tour`: motion_time_before_s, motion_time_after_s,
// velocities, resolution_deg, blocked_moves (their count), blocked
// (BlockedMovesJson over `run`), blocked_moves_before, then the entries of
// `moves_checked` (MovesCheckedJson) and, when not empty, velocity_note
// (AssumedVelocityNote).
nlohmann::json TourJson(const TourSummary& tour, double resolution_deg,
                        const std::vector<int64_t>& run,
                        const nlohmann::json& moves_checked,
                        const std::string& velocity_note);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_CELL_PLANNING_H_
