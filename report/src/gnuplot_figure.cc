// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/report/gnuplot_figure.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "activecal/io/output_files.h"
#include "activecal/io/sigpipe_block.h"

namespace activecal {

bool GnuplotAvailable() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

std::string GnuplotDataBlock(const std::string& name,
                             const std::vector<std::vector<double>>& rows) {
  std::ostringstream out;
  out.precision(17);
  out << "$" << name << " << EOD\n";
  for (const std::vector<double>& row : rows) {
    for (size_t k = 0; k < row.size(); ++k) out << (k ? " " : "") << row[k];
    out << "\n";
  }
  out << "EOD\n";
  return out.str();
}

bool RenderGnuplotPng(const std::string& script, const std::string& png_path,
                      std::string* png, std::string* error) {
  // The output set's temporary name (removed by a later run if this one is
  // killed while gnuplot draws: RemoveStaleTemporaries).
  const std::string scratch_path = TemporaryPath(png_path);
  const TrackedTemporary tracked(scratch_path);
  // gnuplot's messages, removed here and, if the run is killed while
  // gnuplot draws, by the programs' signal handler.
  const std::string log = png_path + ".gnuplot.log";
  const TrackedTemporary tracked_log(log);
  // The output path is quoted for gnuplot; refuse quotes in it.
  if (png_path.find_first_of("'\"\n") != std::string::npos) {
    *error = "the plot path must not contain quotes: " + png_path;
    return false;
  }
  // A folder that does not exist or cannot be written: said here, before
  // the shell fails to open the log and gnuplot's early exit ends the
  // process with SIGPIPE.
  {
    std::ofstream probe(scratch_path);
    if (!probe) {
      *error = "cannot write " + png_path;
      return false;
    }
  }
  std::remove(scratch_path.c_str());
  const std::string command = "gnuplot 2>'" + log + "'";
  FILE* pipe = popen(command.c_str(), "w");
  if (pipe == nullptr) {
    *error = "cannot run gnuplot";
    return false;
  }
  const std::string full =
      "set terminal pngcairo size 1000,650 enhanced font 'sans,11'\n"
      "set output '" +
      scratch_path + "'\n" + script + "\nunset output\n";
  // gnuplot may exit before it has read the script: a failed write, not
  // a SIGPIPE (pclose flushes what fwrite buffered: both under the block).
  int status = 0;
  {
    const SigpipeBlock block;
    std::fwrite(full.data(), 1, full.size(), pipe);
    status = pclose(pipe);
  }
  std::ifstream in(log);
  std::string first;
  std::getline(in, first);
  std::remove(log.c_str());
  if (status != 0) {
    std::remove(scratch_path.c_str());
    *error = "gnuplot failed" + (first.empty() ? "" : ": " + first);
    return false;
  }
  {
    std::ifstream figure(scratch_path, std::ios::binary);
    std::ostringstream bytes;
    bytes << figure.rdbuf();
    *png = bytes.str();
  }
  std::remove(scratch_path.c_str());
  return true;
}

bool MakeGnuplotFigure(const std::string& script, const std::string& png_path,
                       const std::string& option, OutputFile* png,
                       std::string* note, std::string* error) {
  *png = OutputFile();
  if (!GnuplotAvailable()) {
    *note = "  " + option + ": gnuplot is not installed; no plot\n";
    return true;
  }
  std::string bytes;
  if (!RenderGnuplotPng(script, png_path, &bytes, error)) {
    *error = option + ": " + *error;
    return false;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(png_path, ec)) {
    *error = option + ": cannot write '" + png_path + "': it is a directory";
    return false;
  }
  *png = {png_path, bytes};
  *note = "  " + option + ": wrote " + png_path + "\n";
  return true;
}

}  // namespace activecal
