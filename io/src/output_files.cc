// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/output_files.h"

#include <dirent.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace activecal {
namespace {

constexpr char kMark[] = ".activecal-";
constexpr char kSuffix[] = ".tmp";

bool IsDirectory(const std::string& path) {
  struct stat info;
  return stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode);
}

// The folder and the file name of `path` ("." when it has no folder).
void SplitPath(const std::string& path, std::string* dir, std::string* base) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) {
    *dir = ".";
    *base = path;
  } else {
    *dir = slash == 0 ? "/" : path.substr(0, slash);
    *base = path.substr(slash + 1);
  }
}

// The directory entry `path` names: its folder resolved (realpath: "./a"
// and "a", or a folder reached through a symbolic link, are one entry),
// then its file name. Two paths with the same entry are one output: their
// temporaries are one file and the second rename would find it gone.
std::string EntryOf(const std::string& path) {
  std::string dir, base;
  SplitPath(path, &dir, &base);
  char* resolved = realpath(dir.c_str(), nullptr);
  if (resolved != nullptr) {
    dir = resolved;
    std::free(resolved);
  }
  return dir + "/" + base;
}

bool WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return false;
  out << text;
  out.flush();
  return static_cast<bool>(out);
}

}  // namespace

bool SameOutputFile(const std::string& a, const std::string& b) {
  return EntryOf(a) == EntryOf(b);
}

std::string TemporaryPath(const std::string& path) {
  return path + kMark + std::to_string(static_cast<long>(getpid())) + kSuffix;
}

int RemoveStaleTemporaries(const std::string& path) {
  std::string dir, base;
  SplitPath(path, &dir, &base);
  const std::string prefix = base + kMark;
  const std::string suffix = kSuffix;
  DIR* folder = opendir(dir.c_str());
  if (folder == nullptr) return 0;
  std::vector<std::string> stale;
  while (const dirent* entry = readdir(folder)) {
    const std::string name = entry->d_name;
    if (name.size() <= prefix.size() + suffix.size() ||
        name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    const std::string digits =
        name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos ||
        digits.size() > 9) {
      continue;
    }
    const long pid = std::strtol(digits.c_str(), nullptr, 10);
    if (pid <= 0 || pid == static_cast<long>(getpid())) continue;
    // A process that still runs may be writing it.
    if (kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    stale.push_back(dir + "/" + name);
  }
  closedir(folder);
  int removed = 0;
  for (const std::string& file : stale) {
    if (!IsDirectory(file) && std::remove(file.c_str()) == 0) ++removed;
  }
  return removed;
}

namespace {

// The temporaries RemoveOwnTemporaries removes: fixed slots, so that a
// signal handler reads them without a lock or an allocation. A slot is
// claimed (used), its path written between two steps of its generation
// (odd while it is written: a seqlock), then published (ready). The
// handler copies a path and uses it only if the generation was even and
// unchanged around the copy: a slot another thread reuses meanwhile is
// never read half old, half new. Its characters are atomics (relaxed), so
// that reading one while it is written is no data race.
constexpr int kNumSlots = 64;
constexpr size_t kMaxPath = 4096;
struct TemporarySlot {
  std::atomic<bool> used{false};
  std::atomic<bool> ready{false};
  std::atomic<unsigned> generation{0};
  std::atomic<char> path[kMaxPath];
};
TemporarySlot g_slots[kNumSlots];

int Track(const std::string& tmp) {
  if (tmp.size() >= kMaxPath) return -1;
  for (int k = 0; k < kNumSlots; ++k) {
    TemporarySlot& slot = g_slots[k];
    bool unused = false;
    if (!slot.used.compare_exchange_strong(unused, true)) continue;
    const unsigned generation = slot.generation.load(std::memory_order_relaxed);
    slot.generation.store(generation + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    for (size_t i = 0; i <= tmp.size(); ++i) {
      slot.path[i].store(tmp.c_str()[i], std::memory_order_relaxed);
    }
    slot.generation.store(generation + 2, std::memory_order_release);
    slot.ready.store(true, std::memory_order_release);
    return k;
  }
  return -1;
}

void Untrack(int slot) {
  if (slot < 0) return;
  g_slots[slot].ready.store(false, std::memory_order_release);
  g_slots[slot].used.store(false, std::memory_order_release);
}

// The path of `slot` as one Track wrote it, into `path`; false when the
// slot holds none or was being rewritten during the copy.
bool CopyTrackedPath(const TemporarySlot& slot, char (&path)[kMaxPath]) {
  if (!slot.ready.load(std::memory_order_acquire)) return false;
  const unsigned before = slot.generation.load(std::memory_order_acquire);
  if (before % 2 != 0) return false;
  size_t i = 0;
  for (; i + 1 < kMaxPath; ++i) {
    path[i] = slot.path[i].load(std::memory_order_relaxed);
    if (path[i] == '\0') break;
  }
  path[i] = '\0';
  std::atomic_thread_fence(std::memory_order_acquire);
  return slot.generation.load(std::memory_order_relaxed) == before;
}

}  // namespace

void RemoveOwnTemporaries() {
  for (const TemporarySlot& slot : g_slots) {
    char path[kMaxPath];
    if (CopyTrackedPath(slot, path)) unlink(path);
  }
}

namespace {

// The handler of RemoveOwnTemporariesOnSignals: the temporaries, then the
// signal's default action.
extern "C" void RemoveTemporariesAndDie(int signal_number) {
  RemoveOwnTemporaries();
  signal(signal_number, SIG_DFL);
  raise(signal_number);
}

}  // namespace

void RemoveOwnTemporariesOnSignals() {
  constexpr int kSignals[] = {SIGTERM, SIGINT, SIGHUP};
  struct sigaction action = {};
  action.sa_handler = RemoveTemporariesAndDie;
  sigemptyset(&action.sa_mask);
  for (const int signal_number : kSignals) {
    sigaddset(&action.sa_mask, signal_number);
  }
  for (const int signal_number : kSignals) {
    struct sigaction current = {};
    if (sigaction(signal_number, nullptr, &current) != 0 ||
        current.sa_handler == SIG_IGN) {
      continue;
    }
    sigaction(signal_number, &action, nullptr);
  }
}

TrackedTemporary::TrackedTemporary(const std::string& path)
    : slot_(Track(path)) {}

TrackedTemporary::~TrackedTemporary() { Untrack(slot_); }

bool OutputSet::Add(const std::string& path, const std::string& text,
                    std::string* error) {
  if (IsDirectory(path)) {
    *error = "cannot write '" + path + "': it is a directory";
    return false;
  }
  for (const std::string& known : paths_) {
    if (!SameOutputFile(known, path)) continue;
    *error =
        "cannot write '" + path + "': " +
        (known == path ? std::string("it is")
                       : "it is the same file as '" + known + "', which is") +
        " already an output of this run (two outputs cannot share a "
        "file)";
    return false;
  }
  RemoveStaleTemporaries(path);
  const std::string tmp = TemporaryPath(path);
  const int slot = Track(tmp);
  if (!WriteText(tmp, text)) {
    std::remove(tmp.c_str());
    Untrack(slot);
    *error = "cannot write '" + path + "'";
    return false;
  }
  paths_.push_back(path);
  files_.push_back(tmp);
  slots_.push_back(slot);
  return true;
}

bool OutputSet::Commit(std::string* error) {
  for (const std::string& path : paths_) {
    if (IsDirectory(path)) {
      *error = "cannot write '" + path + "': it is a directory";
      Discard();
      return false;
    }
  }
  for (size_t k = 0; k < paths_.size(); ++k) {
    const bool renamed = std::rename(files_[k].c_str(), paths_[k].c_str()) == 0;
    if (renamed) Untrack(slots_[k]);
    if (!renamed) {
      *error = "cannot rename '" + files_[k] + "' to '" + paths_[k] + "'";
      if (k > 0) {
        *error += " (" + std::to_string(k) + " of the " +
                  std::to_string(paths_.size()) +
                  " outputs were already replaced)";
      }
      paths_.erase(paths_.begin(), paths_.begin() + k);
      files_.erase(files_.begin(), files_.begin() + k);
      slots_.erase(slots_.begin(), slots_.begin() + k);
      Discard();
      return false;
    }
  }
  paths_.clear();
  files_.clear();
  slots_.clear();
  return true;
}

void OutputSet::Discard() {
  for (size_t k = 0; k < files_.size(); ++k) {
    std::remove(files_[k].c_str());
    Untrack(slots_[k]);
  }
  paths_.clear();
  files_.clear();
  slots_.clear();
}

bool WriteFileAtomically(const std::string& path, const std::string& text,
                         std::string* error) {
  return WriteFilesAtomically({{path, text}}, error);
}

bool WriteFilesAtomically(const std::vector<OutputFile>& files,
                          std::string* error) {
  for (const OutputFile& file : files) {
    if (IsDirectory(file.path)) {
      *error = "cannot write '" + file.path + "': it is a directory";
      return false;
    }
  }
  OutputSet set;
  for (const OutputFile& file : files) {
    if (!set.Add(file.path, file.text, error)) return false;
  }
  return set.Commit(error);
}

bool CheckWritable(const std::string& path, std::string* error) {
  if (IsDirectory(path)) {
    *error = "cannot write '" + path + "': it is a directory";
    return false;
  }
  RemoveStaleTemporaries(path);
  const std::string tmp = TemporaryPath(path);
  TrackedTemporary tracked(tmp);
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
