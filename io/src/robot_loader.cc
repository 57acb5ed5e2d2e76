// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/robot_loader.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "activecal/io/csv_files.h"
#include "activecal/io/frames_file.h"

extern char** environ;

namespace activecal {

namespace {

bool EndsWith(const std::string& path, const std::string& suffix) {
  if (path.size() < suffix.size()) return false;
  std::string tail = path.substr(path.size() - suffix.size());
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return tail == suffix;
}

// The first executable `name` in PATH's folders ("" if none).
std::string FindOnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return "";
  std::string folders = path;
  size_t begin = 0;
  while (begin <= folders.size()) {
    size_t end = folders.find(':', begin);
    if (end == std::string::npos) end = folders.size();
    const std::string folder = folders.substr(begin, end - begin);
    const std::string candidate = (folder.empty() ? "." : folder) + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    begin = end + 1;
  }
  return "";
}

// A temporary file, removed when it goes out of scope.
struct TempFile {
  std::string path;
  int fd = -1;
  TempFile() {
    const char* dir = std::getenv("TMPDIR");
    std::string pattern =
        std::string(dir && *dir ? dir : "/tmp") + "/activecal_xacro_XXXXXX";
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    fd = mkstemp(name.data());
    if (fd >= 0) path = name.data();
  }
  ~TempFile() {
    if (fd >= 0) {
      close(fd);
      unlink(path.c_str());
    }
  }
};

// The first line of `text` that is not blank, without its end.
std::string FirstLine(const std::string& text) {
  size_t begin = 0;
  while (begin < text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(begin, end - begin);
    while (!line.empty() &&
           std::isspace(static_cast<unsigned char>(line.back())))
      line.pop_back();
    if (line.find_first_not_of(" \t") != std::string::npos) return line;
    begin = end + 1;
  }
  return "";
}

// Runs `xacro path`, its output into *xml.
bool RunXacro(const std::string& xacro, const std::string& path,
              std::string* xml, std::string* error) {
  TempFile out, err;
  if (out.fd < 0 || err.fd < 0) {
    *error = path + ": cannot create a temporary file for xacro's output";
    return false;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out.fd, 1);
  posix_spawn_file_actions_adddup2(&actions, err.fd, 2);
  std::vector<std::string> args = {xacro, path};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned =
      posix_spawn(&pid, xacro.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    *error = path + ": cannot run " + xacro + ": " + std::strerror(spawned);
    return false;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  std::string messages;
  ReadTextFile(err.path, &messages, nullptr);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string first = FirstLine(messages);
    *error = path + ": xacro failed (" +
             (WIFEXITED(status)
                  ? "exit status " + std::to_string(WEXITSTATUS(status))
                  : std::string("killed")) +
             ")" + (first.empty() ? "" : ": " + first);
    return false;
  }
  if (!ReadTextFile(out.path, xml, error)) return false;
  if (xml->find_first_not_of(" \t\r\n") == std::string::npos) {
    *error = path + ": xacro wrote nothing";
    return false;
  }
  return true;
}

}  // namespace

bool IsXacroPath(const std::string& path) { return EndsWith(path, ".xacro"); }

bool IsUrdfPath(const std::string& path) {
  return EndsWith(path, ".urdf") || IsXacroPath(path);
}

bool ReadUrdfText(const std::string& path, std::string* xml,
                  std::string* error) {
  if (!IsXacroPath(path)) return ReadTextFile(path, xml, error);
  std::string ignored;
  if (!ReadTextFile(path, &ignored, error))
    return false;  // names a missing file
  const std::string xacro = FindOnPath("xacro");
  if (xacro.empty()) {
    *error = path + " is a xacro file: run `xacro " + path +
             " > robot.urdf` (xacro is not installed)";
    return false;
  }
  return RunXacro(xacro, path, xml, error);
}

bool LoadRobot(const std::string& path, const RobotLoadOptions& options,
               RobotDescription* robot, std::string* error) {
  RobotDescription loaded;
  if (IsUrdfPath(path)) {
    std::string xml, why;
    if (!ReadUrdfText(path, &xml, &why)) {
      if (error) *error = why;
      return false;
    }
    if (!ParseUrdfRobot(xml, path, options.chain, &loaded, error)) {
      return false;
    }
  } else {
    if (!options.chain.base_link.empty() || !options.chain.tip_link.empty()) {
      if (error) {
        *error = path +
                 ": --base_link and --tip_link choose a chain of a URDF "
                 "file; this is not one (no .urdf or .xacro ending)";
      }
      return false;
    }
    if (!LoadRobotFile(path, &loaded, error)) return false;
  }
  if (!options.frames_path.empty() &&
      !LoadFramesFile(options.frames_path, &loaded, error)) {
    return false;
  }
  *robot = std::move(loaded);
  return true;
}

}  // namespace activecal
