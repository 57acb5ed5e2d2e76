// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A session of the active loop kept in a directory, so that a crash of
// activecal or of the robot cell loses nothing and the loop continues where
// it stopped:
//
//   DIR/session.json      what the session is: the robot and the options
//                         its results depend on (written once)
//   DIR/measurements.csv  every measurement, appended and synced to disk
//                         (fsync) as it comes: the measurements CSV format
//                         (docs/formats.md: activecal_identify reads it)
//                         with three more columns, pose_index (the pool
//                         pose), round, and markers_seen (the rows of that
//                         pose's answer)
//   DIR/excluded.jsonl    every pose the cell could not measure, one JSON
//                         object per line {"pose_index","round","status",
//                         "message"}, synced as it comes
//   DIR/state.json        the loop's state after the last round completed
//                         (round, estimate, designs, measured and excluded
//                         poses, seed), replaced atomically
//
//   std::unique_ptr<ActiveSession> session;
//   ActiveSession::Open(dir, resume, model, identity, &session, &error);
//   SessionMeasurer measurer(session.get(), &driver_measurer);
//   options.round_callback = [&](const ActiveLoopState& s, std::string* e) {
//     return session->SaveState(s, e);
//   };
//   RunActiveLoop(..., &measurer, session->resume_state(), &summary);
//
// Continuing replays nothing: the loop starts after the last completed
// round, and the poses of the round in progress that the log holds are
// answered from it, not measured again. A last line cut by the crash is
// dropped (named in a note); the cell is then asked for that pose again.

#ifndef ACTIVECAL_CALIBRATION_ACTIVE_SESSION_H_
#define ACTIVECAL_CALIBRATION_ACTIVE_SESSION_H_

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "activecal/calibration/active_loop.h"
#include "activecal/core/robot_model.h"

namespace activecal {

// What must be the same to continue a session: (name, value) pairs, e.g.
// ("seed", "1"), ("robot", the robot file's text hash), in a fixed order.
// A value "<file> (hash <h>)" is a file by its content: it matches on <h>
// alone (the file moved or renamed is the same), and a difference names
// both files: "session S was made with cell a.yaml (hash 1713...); this
// run's cell b.yaml differs (hash 1365...)".
using SessionIdentity = std::vector<std::pair<std::string, std::string>>;

class ActiveSession {
 public:
  ~ActiveSession();
  ActiveSession(const ActiveSession&) = delete;
  ActiveSession& operator=(const ActiveSession&) = delete;

  // resume false: starts a session in `dir` (created if missing; refused if
  // it holds a session already). resume true: continues the session in
  // `dir`, refused in one line when its identity differs from `identity`
  // (naming the first difference) or its files do not agree. A directory
  // in use by another process is refused.
  static bool Open(const std::string& dir, bool resume, const RobotModel& model,
                   const SessionIdentity& identity,
                   std::unique_ptr<ActiveSession>* session, std::string* error);

  // The state to continue from; null for a new session or one whose first
  // round never completed.
  const ActiveLoopState* resume_state() const {
    return has_state_ ? &state_ : nullptr;
  }
  // The answers logged after that state (the round in progress), not yet
  // asked for again.
  int pending() const { return static_cast<int>(pending_.size()); }
  // Lines of opening: a cut last line dropped, what was read.
  const std::vector<std::string>& notes() const { return notes_; }

  // The answer logged for `pose` in the round in progress, if any (true
  // and *found). A pose logged in another round than the one asking for it
  // is an error (the session was made differently).
  bool Logged(int64_t pose, int round, PoseAnswer* answer, bool* found,
              std::string* error);
  // Appends an answer to measurements.csv or excluded.jsonl and syncs it.
  bool Record(int64_t pose, int round, const PoseAnswer& answer,
              std::string* error);
  // Replaces state.json. Refused when answers logged in a completed round
  // were never asked for (the loop has gone another way than the log).
  bool SaveState(const ActiveLoopState& state, std::string* error);

  const std::string& dir() const { return dir_; }
  std::string MeasurementsPath() const { return dir_ + "/measurements.csv"; }

 private:
  ActiveSession(std::string dir, const RobotModel& model, int lock_fd);
  bool ReadLogs(std::string* error);
  bool ReadState(std::string* error);

  std::string dir_;
  RobotModel model_;
  int lock_fd_ = -1;
  std::string header_;  // of measurements.csv
  bool has_state_ = false;
  ActiveLoopState state_;
  // Logged answers by pose, in log order, and those not yet accounted for
  // by a saved state or a resumed round.
  struct LoggedAnswer {
    int round = 0;
    PoseAnswer answer;
  };
  std::map<int64_t, LoggedAnswer> logged_;
  std::vector<int64_t> log_order_;       // poses of measurements.csv, in order
  std::vector<int64_t> excluded_order_;  // poses of excluded.jsonl
  std::map<int64_t, int> pending_;       // pose -> round
  std::vector<std::string> notes_;
};

// Answers from the session's log what it holds (the round in progress of a
// resumed session) and otherwise asks `inner`, recording every answer on
// disk before the loop sees it.
class SessionMeasurer : public Measurer {
 public:
  SessionMeasurer(ActiveSession* session, Measurer* inner)
      : session_(session), inner_(inner) {}
  bool Measure(const MeasureBatch& batch, int k, PoseAnswer* answer,
               std::string* error) override;
  // Whether the last answer came from the log.
  bool last_from_log() const { return last_from_log_; }

 private:
  ActiveSession* session_;
  Measurer* inner_;
  bool last_from_log_ = false;
};

// The state as JSON text, and back (exactly: doubles in their shortest
// round-trip form, non-finite ones as "inf", "-inf", "nan"). Measurements
// are not in it: they are in measurements.csv.
std::string ActiveLoopStateJson(const ActiveLoopState& state);
bool ParseActiveLoopStateJson(const std::string& text,
                              const std::string& source, ActiveLoopState* state,
                              std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_ACTIVE_SESSION_H_
