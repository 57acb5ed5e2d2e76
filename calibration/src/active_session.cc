// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/active_session.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "activecal/io/csv_files.h"

namespace activecal {

using nlohmann::json;

namespace {

// A session identity value "<file> (hash <h>)" (SessionIdentity): true
// with the two parts. A session made before the file was named stored
// "with content hash <h>": its file reads "(not recorded)".
bool HashedFile(const std::string& value, std::string* file,
                std::string* hash) {
  const std::string old_form = "with content hash ";
  if (value.rfind(old_form, 0) == 0) {
    *file = "(not recorded)";
    *hash = value.substr(old_form.size());
    return true;
  }
  const std::string mark = " (hash ";
  const size_t at = value.rfind(mark);
  if (at == std::string::npos || value.empty() || value.back() != ')') {
    return false;
  }
  *file = value.substr(0, at);
  *hash = value.substr(at + mark.size(), value.size() - 1 - (at + mark.size()));
  return !file->empty() && !hash->empty();
}

constexpr int kSessionFormat = 1;

std::string Errno() { return std::strerror(errno); }

bool Exists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

// Writes all of `text` to fd.
bool WriteAll(int fd, const std::string& text, std::string* error) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      *error = Errno();
      return false;
    }
    done += static_cast<size_t>(n);
  }
  return true;
}

bool SyncDirectory(const std::string& dir, std::string* error) {
  const int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0 || fsync(fd) != 0) {
    *error = "cannot sync the directory '" + dir + "': " + Errno();
    if (fd >= 0) close(fd);
    return false;
  }
  close(fd);
  return true;
}

// Writes `text` to the file `path` opened with `flags` and syncs it to
// disk; *error names the file.
bool WriteSynced(const std::string& path, int flags, const std::string& text,
                 std::string* error) {
  const int fd =
      open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | flags, 0644);
  std::string why;
  if (fd < 0 || !WriteAll(fd, text, &why) || fsync(fd) != 0) {
    if (why.empty()) why = Errno();
    *error = "cannot write '" + path + "': " + why;
    if (fd >= 0) close(fd);
    return false;
  }
  close(fd);
  return true;
}

// Appends `text` to `path` and syncs it to disk (a new file's directory
// entry too).
bool AppendSynced(const std::string& path, const std::string& dir,
                  const std::string& text, std::string* error) {
  const bool fresh = !Exists(path);
  return WriteSynced(path, O_APPEND, text, error) &&
         (!fresh || SyncDirectory(dir, error));
}

// Replaces `path` atomically: a synced temporary file renamed over it.
bool ReplaceSynced(const std::string& path, const std::string& dir,
                   const std::string& text, std::string* error) {
  const std::string tmp = path + ".tmp";
  if (!WriteSynced(tmp, O_TRUNC, text, error)) {
    unlink(tmp.c_str());
    return false;
  }
  if (rename(tmp.c_str(), path.c_str()) != 0) {
    *error = "cannot rename '" + tmp + "' to '" + path + "': " + Errno();
    unlink(tmp.c_str());
    return false;
  }
  return SyncDirectory(dir, error);
}

// The text of a file cut after its last newline; *cut says whether an
// unfinished last line was dropped (and the file truncated to match).
bool ReadWholeLines(const std::string& path, std::string* text, bool* cut,
                    std::string* error) {
  *cut = false;
  text->clear();
  if (!Exists(path)) return true;
  if (!ReadTextFile(path, text, error)) return false;
  if (text->empty() || text->back() == '\n') return true;
  const size_t last = text->rfind('\n');
  text->resize(last == std::string::npos ? 0 : last + 1);
  *cut = true;
  if (truncate(path.c_str(), static_cast<off_t>(text->size())) != 0) {
    *error = "cannot truncate '" + path + "': " + Errno();
    return false;
  }
  return true;
}

json JsonNumber(double v) {
  if (std::isfinite(v)) return v;
  if (std::isnan(v)) return "nan";
  return v > 0 ? "inf" : "-inf";
}

double ReadNumber(const json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.get<std::string>();
  if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  throw std::runtime_error("'" + s + "' is not a number");
}

json ExcludedJson(const ExcludedPose& e) {
  return {{"pose_index", e.pose},
          {"round", e.round},
          {"status", e.status},
          {"message", e.message}};
}

ExcludedPose ExcludedFromJson(const json& j) {
  ExcludedPose e;
  e.pose = j.at("pose_index").get<int64_t>();
  e.round = j.at("round").get<int>();
  e.status = j.at("status").get<std::string>();
  e.message = j.at("message").get<std::string>();
  return e;
}

// The measurement the header is made from: every column a row of the log
// can use (the orientation, a sigma; the marker when there are several).
Measurement HeaderTemplate(const RobotModel& model) {
  Measurement t;
  t.type = MeasurementType::kPose;
  t.joints = Eigen::VectorXd::Zero(model.num_joints());
  t.marker = model.num_markers() > 1 ? 1 : 0;
  t.sigma_m.setConstant(1.0);
  return t;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

std::string LogHeader(const RobotModel& model) {
  return Lines(MeasurementsCsvText(model, {HeaderTemplate(model)}))[0] +
         ",pose_index,round,markers_seen";
}

bool LogRow(const RobotModel& model, const Measurement& m, std::string* row,
            std::string* error) {
  if (m.type == MeasurementType::kDistance || m.sigma_rad != 0 ||
      (m.sigma_m[0] != m.sigma_m[1] || m.sigma_m[0] != m.sigma_m[2])) {
    *error =
        "the session log keeps positions and poses with one sigma for the "
        "three axes";
    return false;
  }
  *row = Lines(MeasurementsCsvText(model, {HeaderTemplate(model), m}))[2];
  return true;
}

// The last `n` comma-separated fields of a line, as integers.
bool TrailingIntegers(const std::string& line, int n,
                      std::vector<int64_t>* values) {
  values->assign(n, 0);
  size_t end = line.size();
  for (int k = n - 1; k >= 0; --k) {
    const size_t comma = line.rfind(',', end == 0 ? 0 : end - 1);
    if (comma == std::string::npos) return false;
    const std::string field = line.substr(comma + 1, end - comma - 1);
    if (field.empty() ||
        field.find_first_not_of("0123456789") != std::string::npos) {
      return false;
    }
    (*values)[k] = std::stoll(field);
    end = comma;
  }
  return true;
}

}  // namespace

std::string ActiveLoopStateJson(const ActiveLoopState& state) {
  json j;
  j["round"] = state.round;
  j["seed"] = state.seed;
  j["estimate"] = json::array();
  for (Eigen::Index i = 0; i < state.estimate.size(); ++i) {
    j["estimate"].push_back(JsonNumber(state.estimate[i]));
  }
  j["measured"] = state.measured;
  j["excluded"] = json::array();
  for (const ExcludedPose& e : state.excluded) {
    j["excluded"].push_back(ExcludedJson(e));
  }
  j["rounds"] = json::array();
  for (const ActiveRound& r : state.rounds) {
    j["rounds"].push_back(
        {{"num_poses", r.num_poses},
         {"batch", r.batch},
         {"excluded", r.excluded},
         {"predicted_task_rms_m", JsonNumber(r.predicted_task_rms_m)},
         {"true_task_rms_m", JsonNumber(r.true_task_rms_m)},
         {"parameter_change_task_rms_m",
          JsonNumber(r.parameter_change_task_rms_m)},
         {"parameter_change_max_abs", JsonNumber(r.parameter_change_max_abs)},
         {"residual_sigma_m", JsonNumber(r.residual_sigma_m)},
         {"residuals_exceed_noise", r.residuals_exceed_noise}});
  }
  return j.dump(1) + "\n";
}

bool ParseActiveLoopStateJson(const std::string& text,
                              const std::string& source, ActiveLoopState* state,
                              std::string* error) {
  *state = ActiveLoopState();
  try {
    const json j = json::parse(text);
    state->round = j.at("round").get<int>();
    state->seed = j.at("seed").get<uint64_t>();
    const json& e = j.at("estimate");
    state->estimate.resize(e.size());
    for (size_t i = 0; i < e.size(); ++i) state->estimate[i] = ReadNumber(e[i]);
    state->measured = j.at("measured").get<std::vector<int64_t>>();
    for (const json& x : j.at("excluded")) {
      state->excluded.push_back(ExcludedFromJson(x));
    }
    for (const json& x : j.at("rounds")) {
      ActiveRound r;
      r.num_poses = x.at("num_poses").get<int>();
      r.batch = x.at("batch").get<std::vector<int64_t>>();
      r.excluded = x.at("excluded").get<std::vector<int64_t>>();
      r.predicted_task_rms_m = ReadNumber(x.at("predicted_task_rms_m"));
      r.true_task_rms_m = ReadNumber(x.at("true_task_rms_m"));
      r.parameter_change_task_rms_m =
          ReadNumber(x.at("parameter_change_task_rms_m"));
      r.parameter_change_max_abs = ReadNumber(x.at("parameter_change_max_abs"));
      r.residual_sigma_m = ReadNumber(x.at("residual_sigma_m"));
      r.residuals_exceed_noise = x.at("residuals_exceed_noise").get<bool>();
      state->rounds.push_back(r);
    }
  } catch (const std::exception& e) {
    *error = source + ": not a state activecal wrote: " + e.what();
    return false;
  }
  return true;
}

ActiveSession::ActiveSession(std::string dir, const RobotModel& model,
                             int lock_fd)
    : dir_(std::move(dir)), model_(model), lock_fd_(lock_fd) {
  header_ = LogHeader(model_);
}

ActiveSession::~ActiveSession() {
  if (lock_fd_ >= 0) close(lock_fd_);  // releases the lock
}

bool ActiveSession::Open(const std::string& dir, bool resume,
                         const RobotModel& model,
                         const SessionIdentity& identity,
                         std::unique_ptr<ActiveSession>* session,
                         std::string* error) {
  const std::string where = "--session: '" + dir + "'";
  const std::string session_file = dir + "/session.json";
  if (!resume) {
    if (!Exists(dir) && mkdir(dir.c_str(), 0755) != 0) {
      *error = where + ": cannot create the directory: " + Errno();
      return false;
    }
    for (const char* f :
         {"session.json", "measurements.csv", "excluded.jsonl", "state.json"}) {
      if (Exists(dir + "/" + f)) {
        *error = where + " holds a session already (" + f +
                 "): continue it with --resume, or choose a new directory";
        return false;
      }
    }
  } else if (!Exists(session_file)) {
    *error = "--resume: '" + dir + "' holds no session (no session.json)";
    return false;
  }
  const std::string lock_path = dir + "/.lock";
  const int lock_fd =
      open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd < 0) {
    *error = where + ": cannot create '" + lock_path + "': " + Errno();
    return false;
  }
  if (flock(lock_fd, LOCK_EX | LOCK_NB) != 0) {
    close(lock_fd);
    *error = where + " is in use by another activecal process";
    return false;
  }
  std::unique_ptr<ActiveSession> s(new ActiveSession(dir, model, lock_fd));
  if (!resume) {
    json j;
    j["activecal_session"] = kSessionFormat;
    j["identity"] = json::object();
    for (const auto& [key, value] : identity) j["identity"][key] = value;
    if (!ReplaceSynced(session_file, dir, j.dump(1) + "\n", error)) {
      *error = where + ": " + *error;
      return false;
    }
    *session = std::move(s);
    return true;
  }
  std::string text;
  if (!ReadTextFile(session_file, &text, error)) return false;
  json j;
  try {
    j = json::parse(text);
    if (j.at("activecal_session").get<int>() != kSessionFormat) {
      *error = session_file + ": a session of another format (" +
               j["activecal_session"].dump() + ")";
      return false;
    }
    const json& stored = j.at("identity");
    for (const auto& [key, value] : identity) {
      if (!stored.contains(key)) {
        *error = session_file + ": the session has no '" + key +
                 "': it was made by another activecal version";
        return false;
      }
      const std::string was = stored[key].get<std::string>();
      std::string was_label, was_hash, label, hash;
      if (HashedFile(was, &was_label, &was_hash) &&
          HashedFile(value, &label, &hash)) {
        // A file by its content: moved or renamed, the same.
        if (was_hash == hash) continue;
        *error = "session " + dir + " was made with " + key + " " + was_label +
                 " (hash " + was_hash + "); this run's " + key + " " + label +
                 " differs (hash " + hash +
                 "): a session continues with the robot and options it was "
                 "made with (or start a new --session)";
        return false;
      }
      if (was != value) {
        // "cell none" reads as a cell named none: "no cell".
        const bool cell = key == "cell";
        *error = where + " was made with " +
                 (cell && was == "none" ? "no cell" : key + " " + was) +
                 ", this run has " +
                 (cell && value == "none" ? "no cell" : value) +
                 ": a session continues with the robot and options it was "
                 "made with (or start a new --session)";
        return false;
      }
    }
    for (const auto& item : stored.items()) {
      bool known = false;
      for (const auto& kv : identity) known |= kv.first == item.key();
      if (!known) {
        *error = session_file + ": the session has '" + item.key() +
                 "', which this activecal does not know";
        return false;
      }
    }
  } catch (const json::exception& e) {
    *error = session_file + ": not a session activecal wrote: " + e.what();
    return false;
  }
  if (!s->ReadLogs(error) || !s->ReadState(error)) return false;
  *session = std::move(s);
  return true;
}

bool ActiveSession::ReadLogs(std::string* error) {
  const std::string path = MeasurementsPath();
  std::string text;
  bool cut = false;
  if (!ReadWholeLines(path, &text, &cut, error)) return false;
  if (cut) {
    notes_.push_back(path +
                     ": dropped an unfinished last line (cut by the crash); "
                     "that pose is measured again");
  }
  const std::vector<std::string> lines = Lines(text);
  if (!lines.empty()) {
    if (lines[0] != header_) {
      *error = path + ":1: the header is not the one this session writes (" +
               header_ + ")";
      return false;
    }
    std::vector<Measurement> measurements;
    MeasurementsCsvReport report;
    if (lines.size() > 1 &&
        !ParseMeasurementsCsv(text, path, model_, MeasurementsCsvOptions(),
                              &measurements, &report, error)) {
      return false;
    }
    for (const std::string& w : report.warnings) notes_.push_back(w);
    // Group the rows by pose: consecutive rows of one pose, as many as its
    // markers_seen says.
    size_t i = 0;
    while (i < measurements.size()) {
      const int line = report.lines[i];
      std::vector<int64_t> fields;
      if (!TrailingIntegers(lines[line - 1], 3, &fields)) {
        *error = path + ":" + std::to_string(line) +
                 ": pose_index, round, markers_seen: expected integers";
        return false;
      }
      const int64_t pose = fields[0];
      const int64_t seen = fields[2];
      if (logged_.count(pose)) {
        *error = path + ":" + std::to_string(line) + ": pose_index: pose " +
                 std::to_string(pose) + " is logged twice";
        return false;
      }
      LoggedAnswer a;
      a.round = static_cast<int>(fields[1]);
      size_t k = i;
      for (; k < measurements.size() && k < i + static_cast<size_t>(seen);
           ++k) {
        std::vector<int64_t> f;
        if (!TrailingIntegers(lines[report.lines[k] - 1], 3, &f) ||
            f != fields) {
          break;
        }
        a.answer.measurements.push_back(measurements[k]);
      }
      if (seen < 1 || k - i != static_cast<size_t>(seen)) {
        if (k == measurements.size() && seen >= 1) {
          // The crash came between the rows of one answer: drop it.
          const size_t keep = report.lines[i] - 1;
          std::string kept;
          for (size_t l = 0; l < keep; ++l) kept += lines[l] + "\n";
          if (truncate(path.c_str(), static_cast<off_t>(kept.size())) != 0) {
            *error = "cannot truncate '" + path + "': " + Errno();
            return false;
          }
          notes_.push_back(path + ":" + std::to_string(line) +
                           ": dropped the unfinished answer for pose " +
                           std::to_string(pose) + " (cut by the crash)");
          break;
        }
        *error = path + ":" + std::to_string(line) + ": pose " +
                 std::to_string(pose) + " has " + std::to_string(k - i) +
                 " rows, markers_seen says " + std::to_string(seen);
        return false;
      }
      logged_[pose] = a;
      log_order_.push_back(pose);
      i = k;
    }
  }
  const std::string excluded_path = dir_ + "/excluded.jsonl";
  if (!ReadWholeLines(excluded_path, &text, &cut, error)) return false;
  if (cut) {
    notes_.push_back(excluded_path +
                     ": dropped an unfinished last line (cut by the crash)");
  }
  int number = 0;
  for (const std::string& line : Lines(text)) {
    ++number;
    ExcludedPose e;
    try {
      e = ExcludedFromJson(json::parse(line));
    } catch (const std::exception& x) {
      *error = excluded_path + ":" + std::to_string(number) +
               ": not a line activecal wrote: " + x.what();
      return false;
    }
    if (logged_.count(e.pose)) {
      *error = excluded_path + ":" + std::to_string(number) +
               ": pose_index: pose " + std::to_string(e.pose) +
               " is logged twice";
      return false;
    }
    LoggedAnswer a;
    a.round = e.round;
    a.answer.status = e.status;
    a.answer.message = e.message;
    logged_[e.pose] = a;
    excluded_order_.push_back(e.pose);
  }
  return true;
}

bool ActiveSession::ReadState(std::string* error) {
  const std::string path = dir_ + "/state.json";
  size_t measured_prefix = 0, excluded_prefix = 0;
  int round_in_progress = 0;
  if (Exists(path)) {
    std::string text;
    if (!ReadTextFile(path, &text, error) ||
        !ParseActiveLoopStateJson(text, path, &state_, error)) {
      return false;
    }
    has_state_ = true;
    round_in_progress = state_.round;
    const std::string mismatch =
        path + " does not match " + MeasurementsPath() + " and excluded.jsonl";
    if (state_.measured.size() > log_order_.size() ||
        state_.excluded.size() > excluded_order_.size()) {
      *error = mismatch + ": the state has more poses than the logs";
      return false;
    }
    for (size_t k = 0; k < state_.measured.size(); ++k) {
      if (state_.measured[k] != log_order_[k]) {
        *error = mismatch + ": measured pose " + std::to_string(k + 1) +
                 " is " + std::to_string(state_.measured[k]) +
                 " in the state, " + std::to_string(log_order_[k]) +
                 " in the log";
        return false;
      }
      const auto& m = logged_[log_order_[k]].answer.measurements;
      state_.measurements.insert(state_.measurements.end(), m.begin(), m.end());
    }
    for (size_t k = 0; k < state_.excluded.size(); ++k) {
      if (state_.excluded[k].pose != excluded_order_[k]) {
        *error =
            mismatch + ": excluded pose " + std::to_string(k + 1) + " differs";
        return false;
      }
    }
    measured_prefix = state_.measured.size();
    excluded_prefix = state_.excluded.size();
  }
  auto add_pending = [&](int64_t pose) {
    const int round = logged_[pose].round;
    if (round != round_in_progress) {
      *error = MeasurementsPath() + ": pose " + std::to_string(pose) +
               " is logged in round " + std::to_string(round) +
               " after the state of round " +
               std::to_string(round_in_progress) + " (state.json)";
      return false;
    }
    pending_[pose] = round;
    return true;
  };
  for (size_t k = measured_prefix; k < log_order_.size(); ++k) {
    if (!add_pending(log_order_[k])) return false;
  }
  for (size_t k = excluded_prefix; k < excluded_order_.size(); ++k) {
    if (!add_pending(excluded_order_[k])) return false;
  }
  notes_.push_back(dir_ + ": " + std::to_string(log_order_.size()) +
                   " poses measured, " +
                   std::to_string(excluded_order_.size()) + " excluded, " +
                   std::to_string(has_state_ ? state_.round : 0) +
                   " rounds completed; continuing with round " +
                   std::to_string(round_in_progress) +
                   (pending_.empty() ? ""
                                     : " (" + std::to_string(pending_.size()) +
                                           " of its answers are in the log)"));
  return true;
}

bool ActiveSession::Logged(int64_t pose, int round, PoseAnswer* answer,
                           bool* found, std::string* error) {
  *found = false;
  const auto it = pending_.find(pose);
  if (it == pending_.end()) return true;
  if (it->second != round) {
    *error = MeasurementsPath() + ": pose " + std::to_string(pose) +
             " was answered in round " + std::to_string(it->second) +
             ", the continued loop asks for it in round " +
             std::to_string(round) +
             ": the session was made by another activecal build or options";
    return false;
  }
  *answer = logged_[pose].answer;
  pending_.erase(it);
  *found = true;
  return true;
}

bool ActiveSession::Record(int64_t pose, int round, const PoseAnswer& answer,
                           std::string* error) {
  if (logged_.count(pose)) {
    *error = dir_ + ": pose " + std::to_string(pose) + " is logged already";
    return false;
  }
  if (answer.measured()) {
    std::string text;
    struct stat st;
    if (stat(MeasurementsPath().c_str(), &st) != 0 || st.st_size == 0) {
      text = header_ + "\n";
    }
    for (const Measurement& m : answer.measurements) {
      std::string row;
      if (!LogRow(model_, m, &row, error)) return false;
      text += row + "," + std::to_string(pose) + "," + std::to_string(round) +
              "," + std::to_string(answer.measurements.size()) + "\n";
    }
    if (!AppendSynced(MeasurementsPath(), dir_, text, error)) return false;
    log_order_.push_back(pose);
  } else {
    ExcludedPose e;
    e.pose = pose;
    e.round = round;
    e.status = answer.status;
    e.message = answer.message;
    if (!AppendSynced(dir_ + "/excluded.jsonl", dir_,
                      ExcludedJson(e).dump() + "\n", error)) {
      return false;
    }
    excluded_order_.push_back(pose);
  }
  LoggedAnswer a;
  a.round = round;
  a.answer = answer;
  logged_[pose] = a;
  return true;
}

bool ActiveSession::SaveState(const ActiveLoopState& state,
                              std::string* error) {
  for (const auto& [pose, round] : pending_) {
    if (round < state.round) {
      *error = MeasurementsPath() + ": pose " + std::to_string(pose) +
               " was answered in round " + std::to_string(round) +
               ", which the continued loop completed without asking for it: "
               "the session was made by another activecal build or options";
      return false;
    }
  }
  return ReplaceSynced(dir_ + "/state.json", dir_, ActiveLoopStateJson(state),
                       error);
}

bool SessionMeasurer::Measure(const MeasureBatch& batch, int k,
                              PoseAnswer* answer, std::string* error) {
  const int64_t pose = batch.poses[k];
  bool found = false;
  if (!session_->Logged(pose, batch.round, answer, &found, error)) {
    return false;
  }
  last_from_log_ = found;
  if (found) return true;
  if (!inner_->Measure(batch, k, answer, error)) return false;
  return session_->Record(pose, batch.round, *answer, error);
}

}  // namespace activecal
