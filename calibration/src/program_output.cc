// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/calibration/program_output.h"

#include <cctype>

namespace activecal {

bool MakeProgramRequest(const RobotModel& model, const std::string& path,
                        const std::string& language,
                        const std::string& controller, ProgramRequest* request,
                        std::string* error) {
  *request = ProgramRequest();
  request->path = path;
  if (path.empty()) {
    if (controller.empty()) return true;
    *error = "--controller needs --program_out";
    return false;
  }
  if (!StringToProgramLanguage(language, &request->language)) {
    *error = "--program_language must be urscript, krl or rapid, got '" +
             language + "'";
    return false;
  }
  if (controller.empty()) {
    request->convention = IdentityConvention(model);
  } else if (!ReadControllerConvention(controller, model, &request->convention,
                                       error)) {
    *error = "--controller: " + *error;
    return false;
  }
  return true;
}

bool MakeProgramFile(const RobotModel& model, const ProgramRequest& request,
                     const PoseList& poses, const std::string& comment,
                     OutputFile* file, std::string* note, std::string* error) {
  ControllerProgramOptions options;
  options.language = request.language;
  options.comment = comment;
  // The program's name: the file's, made an identifier.
  std::string stem = request.path.substr(request.path.rfind('/') + 1);
  stem = stem.substr(0, stem.find('.'));
  std::string name;
  for (char c : stem) {
    name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  }
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) {
    name = "p" + name;
  }
  options.name = name.substr(0, 24);
  file->path = request.path;
  if (!ControllerProgramText(model, request.convention, poses, options,
                             &file->text, error)) {
    *error = "--program_out: " + *error;
    return false;
  }
  *note = "wrote " + request.path + ": a " +
          ProgramLanguageToString(request.language) + " program through " +
          std::to_string(poses.joints.rows()) + " poses\n";
  return true;
}

}  // namespace activecal
