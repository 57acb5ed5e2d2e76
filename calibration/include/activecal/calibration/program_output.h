// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A design's poses as a controller program (activecal_select's and
// activecal_active's --program_out, --program_language and --controller):
// the request checked before the work, the file made after it
// (io/controller_programs.h).
//
//   ProgramRequest request;
//   if (!MakeProgramRequest(model, "design.script", "urscript", "",
//                           &request, &error)) ...
//   ...the design...
//   OutputFile file;
//   std::string note;
//   if (!MakeProgramFile(model, request, poses, "the design", &file, &note,
//                        &error)) ...
//   ...write file, print note...

#ifndef ACTIVECAL_CALIBRATION_PROGRAM_OUTPUT_H_
#define ACTIVECAL_CALIBRATION_PROGRAM_OUTPUT_H_

#include <string>

#include "activecal/core/robot_model.h"
#include "activecal/io/controller_programs.h"
#include "activecal/io/csv_files.h"
#include "activecal/io/output_files.h"

namespace activecal {

struct ProgramRequest {
  std::string path;  // empty: none
  ProgramLanguage language = ProgramLanguage::kUrScript;
  ControllerConvention convention;
};

// The request for the program file `path` (empty: none) in `language`
// (urscript, krl or rapid: StringToProgramLanguage) with the joint
// convention of the file `controller` (ReadControllerConvention; empty:
// IdentityConvention). False with *error naming the options
// (--program_out, --program_language, --controller): "--controller needs
// --program_out", "--program_language must be urscript, krl or rapid, got
// 'x'", "--controller: <file:line: ...>".
bool MakeProgramRequest(const RobotModel& model, const std::string& path,
                        const std::string& language,
                        const std::string& controller, ProgramRequest* request,
                        std::string* error);

// The program (ControllerProgramText) moving through `poses`, its name the
// file's (the name up to its first dot, every character not a letter or a
// digit made '_', 'p' before a name not starting with a letter, at most 24
// characters), with `comment`; *note "wrote <path>: a <language> program
// through <n> poses\n". False with *error "--program_out: <why>".
bool MakeProgramFile(const RobotModel& model, const ProgramRequest& request,
                     const PoseList& poses, const std::string& comment,
                     OutputFile* file, std::string* note, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_PROGRAM_OUTPUT_H_
