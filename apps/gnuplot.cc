#include "gnuplot.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace activecal {
namespace app {

bool GnuplotAvailable() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

std::string GnuplotData(const std::string& name,
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

bool RunGnuplot(const std::string& script, const std::string& png_path,
                std::string* error) {
  const std::string tmp = png_path + ".tmp";
  const std::string log = png_path + ".gnuplot.log";
  // The output path is quoted for gnuplot; refuse quotes in it.
  if (png_path.find_first_of("'\"\n") != std::string::npos) {
    *error = "the plot path must not contain quotes: " + png_path;
    return false;
  }
  const std::string command = "gnuplot 2>'" + log + "'";
  FILE* pipe = popen(command.c_str(), "w");
  if (pipe == nullptr) {
    *error = "cannot run gnuplot";
    return false;
  }
  const std::string full =
      "set terminal pngcairo size 1000,650 enhanced font 'sans,11'\n"
      "set output '" +
      tmp + "'\n" + script + "\nunset output\n";
  std::fwrite(full.data(), 1, full.size(), pipe);
  const int status = pclose(pipe);
  std::ifstream in(log);
  std::string first;
  std::getline(in, first);
  std::remove(log.c_str());
  if (status != 0) {
    std::remove(tmp.c_str());
    *error = "gnuplot failed" + (first.empty() ? "" : ": " + first);
    return false;
  }
  if (std::rename(tmp.c_str(), png_path.c_str()) != 0) {
    std::remove(tmp.c_str());
    *error = "cannot write " + png_path;
    return false;
  }
  return true;
}

}  // namespace app
}  // namespace activecal
