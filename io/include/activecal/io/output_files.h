// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Writing output files so that a failed run leaves nothing half-written and
// a set of outputs is all new or all old. Every file of a set is written to
// a temporary file beside its path ("<path>.activecal-<pid>.tmp", same
// directory, so that the rename is atomic); only when every one is complete
// and every path checked are they renamed over their paths, one rename per
// file. A failure before the renames removes the temporaries and leaves no
// file of the set changed.
//
// What POSIX cannot give: the renames of a set are not one atomic step. A
// kill -9 (or power loss) between two renames leaves the files renamed so
// far new, the others old, and the remaining temporaries on disk; the next
// run writing the same paths removes temporaries of ours whose process is
// gone (RemoveStaleTemporaries). A kill -9 before the renames leaves every
// output old (plus temporaries, removed the same way).
//
//   std::string error;
//   if (!CheckWritable("report.json", &error)) ...   // before the work
//   ...
//   OutputSet set;
//   if (!set.Add("a.yaml", a, &error) || !set.Add("b.json", b, &error) ||
//       !set.Commit(&error)) ...                     // none written

#ifndef ACTIVECAL_IO_OUTPUT_FILES_H_
#define ACTIVECAL_IO_OUTPUT_FILES_H_

#include <string>
#include <vector>

namespace activecal {

struct OutputFile {
  std::string path;
  std::string text;
};

// The temporary file `path` is written to by this process:
// "<path>.activecal-<pid>.tmp".
std::string TemporaryPath(const std::string& path);

// Removes the temporaries "<path>.activecal-<pid>.tmp" beside `path` left
// by processes that no longer run (a killed earlier run); returns how many.
// Temporaries of running processes (and other files) are not touched.
int RemoveStaleTemporaries(const std::string& path);

// Removes the temporaries this process is writing or has written and not
// yet renamed (every OutputSet's, CheckWritable's probe, a
// TrackedTemporary's): async-signal-safe (unlink only), for a handler of
// SIGTERM, SIGINT or SIGHUP, so that a killed run leaves none behind. The
// programs install such a handler. A kill -9 cannot be caught: the next
// run removes those (RemoveStaleTemporaries). At most 64 are tracked at
// once; beyond that they are left to RemoveStaleTemporaries. Other threads
// may track and untrack meanwhile: a path is read whole or not at all, so
// only this process's temporaries are removed (one tracked during the call
// may be left, for RemoveStaleTemporaries).
void RemoveOwnTemporaries();

// Installs the programs' handler of SIGTERM, SIGINT and SIGHUP: the
// temporaries not yet renamed are removed (RemoveOwnTemporaries; the old
// files stay as they were), then the signal's default action ends the
// program as it would have without it. The three are blocked while it runs.
// A signal ignored when this is called (nohup's SIGHUP, SIGINT of a
// background job) stays ignored: its disposition is looked at first, so it
// is never caught, not even for an instant. For programs, not libraries.
void RemoveOwnTemporariesOnSignals();

// A temporary file that code writes itself (gnuplot's figure), tracked for
// RemoveOwnTemporaries while this object lives; the file is neither made
// nor removed by it.
class TrackedTemporary {
 public:
  explicit TrackedTemporary(const std::string& path);
  ~TrackedTemporary();
  TrackedTemporary(const TrackedTemporary&) = delete;
  TrackedTemporary& operator=(const TrackedTemporary&) = delete;

 private:
  int slot_;
};

// Whether `a` and `b` name one directory entry ("a.csv", "./a.csv", or
// through a folder's symbolic link): one output file.
bool SameOutputFile(const std::string& a, const std::string& b);

// A set of output files written together (see above). The destructor
// removes temporaries not committed.
class OutputSet {
 public:
  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet() { Discard(); }

  // Writes `text` to the temporary of `path` (removing stale temporaries
  // of `path` first); `path` itself is not touched. False with *error
  // ("cannot write '<path>'", "cannot write '<path>': it is a directory",
  // "cannot write '<path>': it is [the same file as '<other>', which is]
  // already an output of this run ...": a path added twice, or two
  // spellings of one file, "a.csv" and "./a.csv"); the set is then
  // unchanged.
  bool Add(const std::string& path, const std::string& text,
           std::string* error);

  // Checks every path (none may have become a directory) and renames every
  // temporary over its path; the set is then empty. False with *error
  // ("cannot write '<path>': it is a directory", "cannot rename ..."):
  // when the check fails nothing is renamed and every temporary removed.
  bool Commit(std::string* error);

  // Removes every temporary; no path is touched.
  void Discard();

  bool empty() const { return files_.empty(); }

 private:
  std::vector<std::string> paths_;
  std::vector<std::string> files_;  // the temporaries, as paths_
  std::vector<int> slots_;  // their RemoveOwnTemporaries slots, as paths_
};

// Writes `text` to `path` through its temporary. False with *error, the old
// file (if any) kept.
bool WriteFileAtomically(const std::string& path, const std::string& text,
                         std::string* error);

// Writes every file as one set. False with *error; then no file of
// `files` was written.
bool WriteFilesAtomically(const std::vector<OutputFile>& files,
                          std::string* error);

// Whether a file can be created beside `path` (its temporary is created and
// removed; `path` itself is not touched; stale temporaries of `path` are
// removed). False with *error "cannot write '<path>'" or "cannot write
// '<path>': it is a directory".
bool CheckWritable(const std::string& path, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_OUTPUT_FILES_H_
