// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Writing output files so that a failed run leaves nothing half-written:
// each file goes to a temporary file beside its path ("<path>.tmp") and is
// renamed over the path; several files are all written to temporaries
// before any is renamed, so that a failure to write one leaves none of
// them (and no temporary file) behind.
//
//   std::string error;
//   if (!CheckWritable("report.json", &error)) ...   // before the work
//   ...
//   if (!WriteFilesAtomically({{"a.yaml", a}, {"b.json", b}}, &error)) ...

#ifndef ACTIVECAL_IO_OUTPUT_FILES_H_
#define ACTIVECAL_IO_OUTPUT_FILES_H_

#include <string>
#include <vector>

namespace activecal {

struct OutputFile {
  std::string path;
  std::string text;
};

// Writes `text` to `path` through "<path>.tmp". False with *error ("cannot
// open '<path>.tmp' for writing", ...), the old file (if any) kept.
bool WriteFileAtomically(const std::string& path, const std::string& text,
                         std::string* error);

// Writes every file (see above). Refuses a path that is a directory before
// writing anything. False with *error ("cannot write '<path>'", "cannot
// write '<path>': it is a directory", "cannot rename ..."); then no file
// of `files` was written.
bool WriteFilesAtomically(const std::vector<OutputFile>& files,
                          std::string* error);

// Whether a file can be created beside `path` (a temporary file is created
// and removed; `path` itself is not touched). False with *error "cannot
// write '<path>'".
bool CheckWritable(const std::string& path, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_OUTPUT_FILES_H_
