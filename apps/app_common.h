// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Helpers shared by the activecal programs (not part of the library).
//
// Flags: each flag shared by several programs is defined in the file of the
// function that reads it (--robot, --base_link, --tip_link, --frames in
// app_common.cc with LoadRobotOrDie; --parameter_set in
// app_parameter_set.cc; --strict_limits in app_measurements.cc;
// --columns_strict in app_columns_strict.cc). The programs link this code as
// a static library, whose files the linker takes only when a program calls
// one of their functions: a program has, and lists in --help, exactly the
// flags it reads (tests/cli_test.sh checks every program).

#ifndef ACTIVECAL_APPS_APP_COMMON_H_
#define ACTIVECAL_APPS_APP_COMMON_H_

#include <gflags/gflags_declare.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "activecal/calibration/pool_builder.h"
#include "activecal/calibration/program_output.h"
#include "activecal/cell/cell_setup.h"
#include "activecal/core/candidate_pool.h"
#include "activecal/core/lattice.h"
#include "activecal/core/measurement.h"
#include "activecal/core/parameter_sets.h"
#include "activecal/core/robot_model.h"
#include "activecal/estimation/evaluation.h"
#include "activecal/estimation/identification.h"
#include "activecal/io/controller_programs.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/output_files.h"
#include "activecal/io/robot_file.h"
#include "activecal/report/progress_line.h"
#include "activecal/selection/design.h"

// --robot (with --base_link, --tip_link, --frames), shared by every program.
DECLARE_string(robot);
DECLARE_string(frames);
DECLARE_string(base_link);
DECLARE_string(tip_link);
// A program that reads it links app_parameter_set.cc, so has the flag.
DECLARE_string(parameter_set);

namespace activecal {
namespace app {

// The robot of --robot (YAML, or a URDF chain between --base_link and
// --tip_link) with the frames of --frames, or the built-in PUMA 560 of the
// paper (with its true values) when --robot is empty. Dies with
// file:line:field on errors.
RobotDescription LoadRobotOrDie();

// The URDF chain of --base_link and --tip_link.
UrdfChainOptions Chain();

// The cell file `cell_path` (a program's --cell) on *robot, with --robot's
// collision geometry (--base_link, --tip_link); the cell's targets become
// the markers when targets_as_markers. Prints the setup's notes
// ("  --cell: note: ..."); dies with "--cell: <file>:<line>:<col>: <field>:
// ..." on errors.
// collision_fallback: a file of the same chain whose collision geometry is
// used when --robot's file has none (CellSetupOptions).
CellSetup SetUpCellOrDie(const std::string& cell_path, bool targets_as_markers,
                         RobotDescription* robot,
                         const std::string& collision_fallback = "");

// The parameter set of --parameter_set (default: full for a URDF robot,
// file otherwise). Dies on an unknown name. (app_parameter_set.cc)
ParameterSet ParameterSetOrDie(bool urdf_robot);

// The measurements file `path` read with --strict_limits,
// --columns_strict and --column_map. Prints the reader's warning ("<program>:
// warning: ...", joint readings beyond the limits) and notes (ignored columns,
// markers not seen) on stdout; dies with "--<flag>: file:line: ..." on errors.
// (app_measurements.cc)
// *lines (may be null): the file line of each measurement.
std::vector<Measurement> ReadMeasurementsOrDie(
    const std::string& path, const RobotModel& model,
    const std::string& flag = "measurements",
    std::vector<int>* lines = nullptr);

// `measurements` with the known distances of the points file `path`
// appended (nothing without a path); dies with "--points: file:line: ..."
// on a bad file or a label no type=point row names. (app_points.cc)
std::vector<Measurement> WithPointsFileOrDie(
    const std::string& path, std::vector<Measurement> measurements);

// The commanded poses (ISO 9283 cycles: pose, commanded_x_m, ...) of the
// measurements file `path`, read with --column_map; dies with "--<flag>:
// file:line: ..." on errors. (app_measurements.cc)
std::vector<CommandedPose> ReadCommandedPosesOrDie(
    const std::string& path, const RobotModel& model,
    const std::string& flag = "measurements");

// The map of --column_map (none without the flag); dies on a bad map.
// (app_column_map.cc)
const std::optional<ColumnMap>& ColumnMapOrDie();

// --columns_strict: refuse columns activecal does not read.
// (app_columns_strict.cc)
bool ColumnsStrict();

// The program's name, as Init found it ("activecal_select").
const std::string& ProgramName();

// Prints "<program>: error: <message>" on stderr and exits with status 1.
[[noreturn]] void Fail(const std::string& message);

// The enum value of --<flag>=<text> (a StringToX of the library), or dies
// with "--<flag> must be <choices>, got '<text>'".
template <typename Enum>
void EnumFlagOrDie(bool (*string_to)(const std::string&, Enum*),
                   const std::string& flag, const std::string& text,
                   const std::string& choices, Enum* value) {
  if (!string_to(text, value)) {
    Fail("--" + flag + " must be " + choices + ", got '" + text + "'");
  }
}

// Parses gflags and sets up glog; logs go to stderr, warnings and above.
// With --quiet (every program has it), stdout goes to /dev/null from here
// on: only PrintResult's line and the errors (stderr) are printed.
void Init(int* argc, char*** argv, const char* usage);
// A program's whole main: Init with `usage` (the first lines of --help),
// then `program`, then the pending outputs committed (Finish); returns the
// exit status.
int Run(int argc, char** argv, const char* usage, int (*program)());
// A program's main function, Run with `usage` and `program`:
//   ACTIVECAL_APP_MAIN(kUsage, activecal::Main)
#define ACTIVECAL_APP_MAIN(usage, program)                  \
  int main(int argc, char** argv) {                         \
    return activecal::app::Run(argc, argv, usage, program); \
  }

// --quiet was given.
bool Quiet();

// Whether --<flag> was left at its default.
bool IsDefault(const char* flag);

// The program's one-line result, on stdout even with --quiet (its last
// line: a script reads it with `tail -1`).
void PrintResult(const std::string& line);

// "<program>: <line>" on stderr, flushed at once, unless --quiet: what a
// run that can take more than 2 s is doing (stdout stays the same for
// scripts whether or not progress is printed).
void PrintProgress(const std::string& line);

// The program's outputs are one set (io/output_files.h): WriteTextOrDie and
// WriteJsonOrDie write the file to a temporary beside its path and keep it
// pending; Finish (the end of main) or CommitOutputsOrDie renames every
// pending file over its path, and Fail removes them, so that a run that
// fails writes nothing, and one that succeeds writes everything.
void WriteJsonOrDie(const std::string& path, const nlohmann::json& json);
// Dies with "--<flag>: cannot write '<path>' ..." unless a file can be
// created beside `path` (empty: nothing to check; a directory is refused):
// checked before the work. Removes stale temporaries of `path` left by a
// killed run.
void CheckWritableOrDie(const std::string& path, const std::string& flag);
// The tour flags of select and active: dies with one line unless --order is
// none or shortest and --order_resolution_deg is in (0, 10] (the value
// named as the user wrote it).
void CheckTourFlagsOrDie(const std::string& order, double resolution_deg);
void WriteTextOrDie(const std::string& path, const std::string& text);
// WriteTextOrDie of each file; one whose path `options` names fails as
// "<option>: <error>" (a figure: "--selection_plot: cannot write ...").
void WriteFilesOrDie(const std::vector<OutputFile>& files,
                     const std::map<std::string, std::string>& options = {});
// WriteTextOrDie's pending write, false with *error instead of dying.
bool AddOutput(const std::string& path, const std::string& text,
               std::string* error);
// Renames every pending output over its path now (e.g. a file another
// process must read while this one still runs).
void CommitOutputsOrDie();
// The end of main: commits the pending outputs and returns `status`.
int Finish(int status);

// A progress line on stderr, "<program>: <label>: 12288/15625 (41000/s,
// 0.1 s left)", once the step has taken kProgressAfterNs (2 s: a short
// step prints nothing), flushed as it is written: on a terminal rewritten
// in place at most 5 times a second; in a file or a pipe one line every
// 2 s and the last one. Never with --quiet; never on stdout (what scripts
// read stays the same). Thread-safe. The environment variable
// ACTIVECAL_PROGRESS_AFTER_S replaces the 2 s (0: every update a line, as
// tests/progress_cli_test.sh runs it).
inline constexpr int64_t kProgressAfterNs = 2000000000;
class ProgressLine {
 public:
  explicit ProgressLine(std::string label);
  ~ProgressLine();  // finishes the line
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // A callback for the library's options (PoolJacobianOptions::progress,
  // FedorovOptions::progress, ...), valid while this object lives.
  ProgressCallback callback();
  void Update(int64_t done, int64_t total);

 private:
  bool tty_;
  std::mutex mutex_;
  ProgressLineClock clock_;  // report/progress_line.h
};

// For the library's stage progress options (SelectOptions::progress,
// PaperExampleOptions::progress, ...): each stage its own ProgressLine,
// labelled with the stage's name, living as long as its callback.
std::function<ProgressCallback(const std::string& stage)> StageProgressLines();

// The options of a library workflow with program_name (the texts' program)
// and progress (SelectOptions, PaperExampleOptions, ...): this program's
// name, and its stages' progress lines (StageProgressLines).
template <typename Options>
void NameProgramAndShowStages(Options* options) {
  options->program_name = ProgramName();
  options->progress = StageProgressLines();
}

double Seconds(int64_t start_ns);
int64_t NowNs();

// A controller program to write (--program_out, --program_language,
// --controller of activecal_select and activecal_active): checked before the
// work (MakeProgramRequest, calibration/program_output.h), written after it.
// Dies with "--program_language: ..." or "--controller: file:line: ..." on
// bad values, or when `path` cannot be written.
ProgramRequest ProgramRequestOrDie(const RobotModel& model,
                                   const std::string& path,
                                   const std::string& language,
                                   const std::string& controller);
// Writes `poses` as the program (its name from the file's name); prints
// one line saying so.
void WriteProgramOrDie(const RobotModel& model, const ProgramRequest& request,
                       const PoseList& poses, const std::string& comment);

}  // namespace app
}  // namespace activecal

#endif  // ACTIVECAL_APPS_APP_COMMON_H_
