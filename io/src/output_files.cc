// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/output_files.h"

#include <sys/stat.h>

#include <cstdio>
#include <fstream>

namespace activecal {

bool WriteFileAtomically(const std::string& path, const std::string& text,
                         std::string* error) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      *error = "cannot open '" + tmp + "' for writing";
      return false;
    }
    out << text;
    out.flush();
    if (!out) {
      *error = "failed writing '" + tmp + "'";
      std::remove(tmp.c_str());
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = "cannot rename '" + tmp + "' to '" + path + "'";
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

bool WriteFilesAtomically(const std::vector<OutputFile>& files,
                          std::string* error) {
  for (const OutputFile& file : files) {
    struct stat info;
    if (stat(file.path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
      *error = "cannot write '" + file.path + "': it is a directory";
      return false;
    }
  }
  std::vector<std::string> written;
  auto remove_written = [&] {
    for (const std::string& tmp : written) std::remove(tmp.c_str());
  };
  for (const OutputFile& file : files) {
    const std::string tmp = file.path + ".tmp";
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (out) {
      written.push_back(tmp);
      out << file.text;
      out.flush();
    }
    if (!out) {
      remove_written();
      *error = "cannot write '" + file.path + "'";
      return false;
    }
  }
  for (size_t k = 0; k < files.size(); ++k) {
    if (std::rename(written[k].c_str(), files[k].path.c_str()) != 0) {
      remove_written();
      *error = "cannot rename '" + written[k] + "' to '" + files[k].path + "'";
      return false;
    }
  }
  return true;
}

bool CheckWritable(const std::string& path, std::string* error) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::app);
    if (!out) {
      *error = "cannot write '" + path + "'";
      return false;
    }
  }
  std::remove(tmp.c_str());
  return true;
}

}  // namespace activecal
