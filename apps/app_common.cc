// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "app_common.h"

#include <fcntl.h>
#include <gflags/gflags.h>
#include <glog/logging.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <utility>
#include <vector>

#include "activecal/calibration/program_output.h"
#include "activecal/calibration/robot_setup.h"
#include "activecal/calibration/selection_pool.h"
#include "activecal/estimation/identification.h"
#include "activecal/io/output_files.h"
#include "activecal/report/closest_name.h"
#include "activecal/selection/criteria.h"

DEFINE_bool(quiet, false,
            "Print only errors (stderr) and the one-line result (stdout, "
            "where the program has one): no notes, tables, warnings or "
            "progress lines. Output files are the same.");
DEFINE_string(robot, "",
              "Robot description: an activecal robot YAML file or a URDF "
              "file (.urdf; docs/formats.md). Empty: the built-in PUMA 560 "
              "of Sun & Hollerbach, the same as data/puma560.yaml.");
DEFINE_string(base_link, "",
              "URDF robots: the link the calibrated chain starts at (default: "
              "the URDF's root).");
DEFINE_string(tip_link, "",
              "URDF robots: the link the calibrated chain ends at (default: "
              "the only leaf; several leaves are listed in the error).");
DEFINE_string(frames, "",
              "Metrology frames (YAML, docs/formats.md): the robot base in "
              "the device's frame and the markers, e.g. from "
              "activecal_identify --frames_out.");

namespace activecal {
namespace app {
namespace {
std::string g_program = "activecal";
int g_result_fd = STDOUT_FILENO;  // where PrintResult writes
OutputSet& PendingOutputs() {
  static OutputSet* set = new OutputSet();  // never destroyed: see Fail
  return *set;
}
}  // namespace

const std::string& ProgramName() { return g_program; }

void Fail(const std::string& message) {
  PendingOutputs().Discard();
  std::cerr << g_program << ": error: " << message << std::endl;
  std::exit(1);
}

namespace {

// "unknown command line flag 'x' (did you mean --y?)" (gflags' words) for an
// argument naming no declared flag; empty for a known flag or an argument that
// is not a flag.
std::string UnknownFlagMessage(const std::string& arg) {
  if (arg.size() < 2 || arg[0] != '-') return "";
  const size_t start = arg[1] == '-' ? 2 : 1;
  const std::string name = arg.substr(start, arg.find('=') - start);
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) {
    return "";  // a negative number, "--"
  }
  gflags::CommandLineFlagInfo info;
  if (gflags::GetCommandLineFlagInfo(name.c_str(), &info)) return "";
  // --noflag for a bool flag.
  if (name.rfind("no", 0) == 0 &&
      gflags::GetCommandLineFlagInfo(name.substr(2).c_str(), &info) &&
      info.type == "bool") {
    return "";
  }
  std::vector<gflags::CommandLineFlagInfo> flags;
  gflags::GetAllFlags(&flags);
  std::vector<std::string> names;
  for (const gflags::CommandLineFlagInfo& f : flags) {
    // The program's own flags (apps/) and gflags' help flags.
    if (f.filename.find("/apps/") != std::string::npos ||
        f.filename.find("gflags") != std::string::npos) {
      names.push_back(f.name);
    }
  }
  const std::string best = ClosestName(name, names);
  std::string message = "unknown command line flag '" + name + "'";
  message += best.empty() ? " (see --help)" : " (did you mean --" + best + "?)";
  return message;
}

}  // namespace

void Init(int* argc, char*** argv, const char* usage) {
  RemoveOwnTemporariesOnSignals();
  g_program = (*argv)[0];
  const size_t slash = g_program.rfind('/');
  if (slash != std::string::npos) g_program = g_program.substr(slash + 1);
  gflags::SetUsageMessage(usage);
  gflags::SetVersionString("0.1.0");
  // --help lists the program's own flags (those defined under apps/), not
  // the ~100 of glog and gflags; --helpfull still lists them all.
  static char help_flag[] = "--helpmatch=/apps/";
  for (int i = 1; i < *argc; ++i) {
    const std::string arg = (*argv)[i];
    if (arg == "--") break;  // the end of the flags
    if (arg == "--help" || arg == "-help" || arg == "-h") {
      (*argv)[i] = help_flag;
      continue;
    }
    // A mistyped flag: one line naming it and the closest declared one,
    // before gflags' own message (which names no alternative).
    const std::string unknown = UnknownFlagMessage(arg);
    if (!unknown.empty()) Fail(unknown);
  }
  gflags::ParseCommandLineFlags(argc, argv, true);
  FLAGS_logtostderr = true;
  // Below FATAL, glog stays silent: a failing run prints exactly one line
  // (ours), never Ceres' own LOG(ERROR) beside it, e.g. from
  // ceres::Covariance on a rank-deficient Jacobian.
  FLAGS_minloglevel = google::GLOG_FATAL;
  google::InitGoogleLogging((*argv)[0]);
  if (*argc > 1) {
    Fail(std::string("unexpected argument '") + (*argv)[1] +
         "' (flags are written --name=value; see --help)");
  }
  if (FLAGS_quiet) {
    // Everything the program prints on stdout goes to /dev/null; the
    // result line (PrintResult) to the real stdout.
    std::fflush(stdout);
    g_result_fd = dup(STDOUT_FILENO);
    const int null = open("/dev/null", O_WRONLY);
    if (g_result_fd < 0 || null < 0 || dup2(null, STDOUT_FILENO) < 0) {
      Fail("--quiet: cannot redirect stdout");
    }
    close(null);
  }
}

int Run(int argc, char** argv, const char* usage, int (*program)()) {
  Init(&argc, &argv, usage);
  return Finish(program());
}

bool Quiet() { return FLAGS_quiet; }

bool IsDefault(const char* flag) {
  return gflags::GetCommandLineFlagInfoOrDie(flag).is_default;
}

void PrintResult(const std::string& line) {
  std::fflush(stdout);
  const std::string text = line + "\n";
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n =
        write(g_result_fd, text.data() + done, text.size() - done);
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
}

void PrintProgress(const std::string& line) {
  if (FLAGS_quiet) return;
  std::fprintf(stderr, "%s: %s\n", g_program.c_str(), line.c_str());
  std::fflush(stderr);
}

void WriteTextOrDie(const std::string& path, const std::string& text) {
  std::string error;
  if (!AddOutput(path, text, &error)) Fail(error);
}

void WriteFilesOrDie(const std::vector<OutputFile>& files,
                     const std::map<std::string, std::string>& options) {
  for (const OutputFile& file : files) {
    std::string error;
    if (AddOutput(file.path, file.text, &error)) continue;
    const auto option = options.find(file.path);
    Fail(option == options.end() ? error : option->second + ": " + error);
  }
}

bool AddOutput(const std::string& path, const std::string& text,
               std::string* error) {
  return PendingOutputs().Add(path, text, error);
}

void CommitOutputsOrDie() {
  std::string error;
  if (!PendingOutputs().Commit(&error)) Fail(error);
}

int Finish(int status) {
  CommitOutputsOrDie();
  return status;
}

void CheckTourFlagsOrDie(const std::string& order, double resolution_deg) {
  if (order != "none" && order != "shortest") {
    Fail("--order must be none or shortest, got '" + order + "'");
  }
  if (!(resolution_deg > 0 && resolution_deg <= 10)) {
    // Coarser steps check little more than the end points of a move.
    Fail("--order_resolution_deg must be in (0, 10], got " +
         gflags::GetCommandLineFlagInfoOrDie("order_resolution_deg")
             .current_value +
         ": a move is checked at joint steps of at most this many degrees; "
         "coarser steps check little more than its end points");
  }
}

void CheckWritableOrDie(const std::string& path, const std::string& flag) {
  if (path.empty()) return;
  // The outputs checked so far, by flag: two flags on one file would have
  // the second's text replace the first's (OutputSet refuses it, but only
  // after the work).
  static auto* checked = new std::vector<std::pair<std::string, std::string>>();
  for (const auto& [known_flag, known_path] : *checked) {
    if (known_flag != flag && SameOutputFile(known_path, path)) {
      Fail("--" + flag + ": '" + path + "' is the file of --" + known_flag +
           " ('" + known_path + "'): two outputs cannot share a file");
    }
  }
  checked->emplace_back(flag, path);
  std::string error;
  if (!CheckWritable(path, &error)) Fail("--" + flag + ": " + error);
}

void WriteJsonOrDie(const std::string& path, const nlohmann::json& json) {
  WriteTextOrDie(path, json.dump(2) + "\n");
}

CellSetup SetUpCellOrDie(const std::string& cell_path, bool targets_as_markers,
                         RobotDescription* robot,
                         const std::string& collision_fallback) {
  CellSetupOptions options;
  options.collision_fallback_path = collision_fallback;
  options.cell_path = cell_path;
  options.robot_path = FLAGS_robot;
  options.chain = Chain();
  options.targets_as_markers = targets_as_markers;
  CellSetup cell;
  std::string error;
  if (!SetUpCell(options, robot, &cell, &error)) Fail("--cell: " + error);
  for (const std::string& note : cell.notes) {
    std::printf("  --cell: note: %s\n", note.c_str());
  }
  return cell;
}

UrdfChainOptions Chain() { return {FLAGS_base_link, FLAGS_tip_link}; }

RobotDescription LoadRobotOrDie() {
  RobotDescription robot;
  std::string note, error;
  if (!SetUpRobot({FLAGS_robot, Chain(), FLAGS_frames}, &robot, &note,
                  &error)) {
    Fail(error);
  }
  std::printf("%s", note.c_str());
  return robot;
}

ProgressLine::ProgressLine(std::string label)
    : tty_(isatty(2)),
      clock_(g_program + ": " + label, tty_,
             // 0: every update a line (what the tests of the lines use).
             ProgressAfterNs(std::getenv("ACTIVECAL_PROGRESS_AFTER_S"),
                             kProgressAfterNs),
             NowNs()) {}

ProgressLine::~ProgressLine() {
  if (tty_ && clock_.printed()) std::cerr << std::endl;
}

ProgressCallback ProgressLine::callback() {
  return [this](int64_t done, int64_t total) { Update(done, total); };
}

void ProgressLine::Update(int64_t done, int64_t total) {
  if (FLAGS_quiet) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string line = clock_.Update(done, total, NowNs());
  if (line.empty()) return;
  if (tty_) {
    std::cerr << "\r" << line << "\033[K" << std::flush;
  } else {
    std::cerr << line << std::endl;
  }
}

std::function<ProgressCallback(const std::string& stage)> StageProgressLines() {
  return [](const std::string& stage) {
    auto line = std::make_shared<ProgressLine>(stage);
    return ProgressCallback(
        [line](int64_t done, int64_t total) { line->Update(done, total); });
  };
}

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double Seconds(int64_t start_ns) { return (NowNs() - start_ns) * 1e-9; }

ProgramRequest ProgramRequestOrDie(const RobotModel& model,
                                   const std::string& path,
                                   const std::string& language,
                                   const std::string& controller) {
  ProgramRequest request;
  std::string error;
  if (!MakeProgramRequest(model, path, language, controller, &request,
                          &error)) {
    Fail(error);
  }
  CheckWritableOrDie(path, "program_out");
  return request;
}

void WriteProgramOrDie(const RobotModel& model, const ProgramRequest& request,
                       const PoseList& poses, const std::string& comment) {
  if (request.path.empty()) return;
  OutputFile file;
  std::string note, error;
  if (!MakeProgramFile(model, request, poses, comment, &file, &note, &error)) {
    Fail(error);
  }
  WriteTextOrDie(file.path, file.text);
  std::printf("%s", note.c_str());
}

}  // namespace app
}  // namespace activecal
