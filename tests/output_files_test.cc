// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// io/output_files.h: a set of outputs is all new or all old, a failure
// leaves no temporary file, and a killed run's temporaries are removed by
// the next run writing the same paths (issue #24, item 1 of the remainder).

#include "activecal/io/output_files.h"

#include <dirent.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace activecal {
namespace {

// A fresh folder under the test's temporary directory.
std::string MakeFolder(const std::string& name) {
  const char* tmp = std::getenv("TMPDIR");
  std::string dir = std::string(tmp ? tmp : "/tmp") + "/activecal_out_" + name +
                    "_" + std::to_string(getpid());
  std::string command = "rm -rf '" + dir + "'";
  EXPECT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(mkdir(dir.c_str(), 0755), 0);
  return dir;
}

std::set<std::string> Names(const std::string& dir) {
  std::set<std::string> names;
  DIR* d = opendir(dir.c_str());
  while (const dirent* e = readdir(d)) {
    const std::string n = e->d_name;
    if (n != "." && n != "..") names.insert(n);
  }
  closedir(d);
  return names;
}

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void Write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A fresh folder (MakeFolder) holding a.csv with the text "old a".
std::string FolderWithOldA(const std::string& name) {
  const std::string dir = MakeFolder(name);
  Write(dir + "/a.csv", "old a");
  return dir;
}

TEST(OutputSetTest, CommitWritesEveryFileAndLeavesNoTemporary) {
  const std::string dir = FolderWithOldA("commit");
  OutputSet set;
  std::string error;
  ASSERT_TRUE(set.Add(dir + "/a.csv", "new a", &error)) << error;
  ASSERT_TRUE(set.Add(dir + "/b.json", "new b", &error)) << error;
  // Nothing is visible before the commit.
  EXPECT_EQ(Read(dir + "/a.csv"), "old a");
  EXPECT_EQ(Names(dir).count("b.json"), 0u);
  ASSERT_TRUE(set.Commit(&error)) << error;
  EXPECT_TRUE(set.empty());
  EXPECT_EQ(Read(dir + "/a.csv"), "new a");
  EXPECT_EQ(Read(dir + "/b.json"), "new b");
  EXPECT_EQ(Names(dir), (std::set<std::string>{"a.csv", "b.json"}));
}

TEST(OutputSetTest, AFailedCommitChangesNoFileOfTheSet) {
  const std::string dir = MakeFolder("fail");
  Write(dir + "/poses.csv", "old poses");
  Write(dir + "/design.json", "old design");
  OutputSet set;
  std::string error;
  ASSERT_TRUE(set.Add(dir + "/poses.csv", "new poses", &error)) << error;
  ASSERT_TRUE(set.Add(dir + "/rejected.csv", "new rejected", &error));
  ASSERT_TRUE(set.Add(dir + "/design.json", "new design", &error));
  // The last output cannot be renamed into any more: it became a folder.
  ASSERT_EQ(std::remove((dir + "/design.json").c_str()), 0);
  ASSERT_EQ(mkdir((dir + "/design.json").c_str(), 0755), 0);
  EXPECT_FALSE(set.Commit(&error));
  EXPECT_EQ(error, "cannot write '" + dir + "/design.json': it is a directory");
  // The first two were not renamed either, and no temporary is left.
  EXPECT_EQ(Read(dir + "/poses.csv"), "old poses");
  EXPECT_EQ(Names(dir), (std::set<std::string>{"poses.csv", "design.json"}));
  EXPECT_TRUE(set.empty());
}

TEST(OutputSetTest, DiscardAndTheDestructorRemoveTheTemporaries) {
  const std::string dir = MakeFolder("discard");
  std::string error;
  {
    OutputSet set;
    ASSERT_TRUE(set.Add(dir + "/a.csv", "a", &error));
    EXPECT_EQ(Names(dir).size(), 1u);  // the temporary
    EXPECT_EQ(*Names(dir).begin(),
              "a.csv.activecal-" + std::to_string(getpid()) + ".tmp");
  }
  EXPECT_TRUE(Names(dir).empty());
  // A path that cannot be written: the error, the set unchanged.
  OutputSet set;
  EXPECT_FALSE(set.Add(dir + "/no_such_dir/a.csv", "a", &error));
  EXPECT_EQ(error, "cannot write '" + dir + "/no_such_dir/a.csv'");
  EXPECT_TRUE(set.empty());
  EXPECT_TRUE(Names(dir).empty());
}

TEST(OutputSetTest, StaleTemporariesOfDeadProcessesAreRemoved) {
  const std::string dir = MakeFolder("stale");
  // A process that has exited: its pid is free (until reused).
  const pid_t child = fork();
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  const std::string dead = dir + "/poses.csv.activecal-" +
                           std::to_string(static_cast<long>(child)) + ".tmp";
  // One of a process that runs (the test's parent), and other names.
  const std::string alive = dir + "/poses.csv.activecal-" +
                            std::to_string(static_cast<long>(getppid())) +
                            ".tmp";
  const std::string other = dir + "/poses.csv.tmp";
  const std::string other_path = dir + "/design.json.activecal-" +
                                 std::to_string(static_cast<long>(child)) +
                                 ".tmp";
  for (const std::string& f : {dead, alive, other, other_path}) Write(f, "x");
  std::string error;
  ASSERT_TRUE(CheckWritable(dir + "/poses.csv", &error)) << error;
  std::set<std::string> names = Names(dir);
  EXPECT_EQ(names.count(dead.substr(dir.size() + 1)), 0u);
  EXPECT_EQ(names.count(alive.substr(dir.size() + 1)), 1u);
  EXPECT_EQ(names.count(other.substr(dir.size() + 1)), 1u);
  EXPECT_EQ(names.count(other_path.substr(dir.size() + 1)), 1u);
  // Writing design.json removes its own.
  OutputSet set;
  ASSERT_TRUE(set.Add(dir + "/design.json", "d", &error));
  ASSERT_TRUE(set.Commit(&error));
  names = Names(dir);
  EXPECT_EQ(names.count(other_path.substr(dir.size() + 1)), 0u);
  EXPECT_EQ(names.size(), 3u);  // alive, other, design.json
}

TEST(OutputSetTest, WriteFilesAtomicallyWritesAllOrNone) {
  const std::string dir = MakeFolder("all");
  std::string error;
  EXPECT_FALSE(WriteFilesAtomically(
      {{dir + "/a.yaml", "a"}, {dir + "/missing/b.json", "b"}}, &error));
  EXPECT_TRUE(Names(dir).empty());
  EXPECT_TRUE(WriteFilesAtomically({{dir + "/a.yaml", "a"}}, &error));
  EXPECT_EQ(Names(dir), (std::set<std::string>{"a.yaml"}));
  EXPECT_FALSE(CheckWritable(dir, &error));
  EXPECT_EQ(error, "cannot write '" + dir + "': it is a directory");
}

// Two outputs of one run on one file (a flag given the path of another, or
// "a.csv" and "./a.csv"): the second is refused before it is written, so
// that the run fails having written nothing (the two spellings shared one
// temporary: the first rename moved it, the second found it gone, and the
// run failed with one of its outputs already replaced).
TEST(OutputSetTest, TwoOutputsOnOneFileAreRefused) {
  const std::string dir = FolderWithOldA("same");
  OutputSet set;
  std::string error;
  ASSERT_TRUE(set.Add(dir + "/a.csv", "poses", &error)) << error;
  EXPECT_FALSE(set.Add(dir + "/a.csv", "design", &error));
  EXPECT_EQ(error, "cannot write '" + dir +
                       "/a.csv': it is already an output of this run (two "
                       "outputs cannot share a file)");
  EXPECT_FALSE(set.Add(dir + "/./a.csv", "design", &error));
  EXPECT_EQ(error, "cannot write '" + dir +
                       "/./a.csv': it is the same file as '" + dir +
                       "/a.csv', which is already an output of this run (two "
                       "outputs cannot share a file)");
  mkdir((dir + "/sub").c_str(), 0755);
  EXPECT_FALSE(set.Add(dir + "/sub/../a.csv", "design", &error));
  // The refused ones changed nothing: the first is still pending.
  EXPECT_EQ(Read(dir + "/a.csv"), "old a");
  ASSERT_TRUE(set.Add(dir + "/b.csv", "b", &error)) << error;
  ASSERT_TRUE(set.Commit(&error)) << error;
  EXPECT_EQ(Read(dir + "/a.csv"), "poses");
  EXPECT_EQ(Names(dir), (std::set<std::string>{"a.csv", "b.csv", "sub"}));
  // WriteFilesAtomically: nothing written.
  EXPECT_FALSE(WriteFilesAtomically(
      {{dir + "/c.yaml", "c"}, {dir + "/./c.yaml", "c2"}}, &error));
  EXPECT_EQ(Names(dir), (std::set<std::string>{"a.csv", "b.csv", "sub"}));
}

TEST(OutputSetTest, RemoveOwnTemporariesTakesOnlyWhatIsNotRenamed) {
  const std::string dir = FolderWithOldA("own");
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(dir + "/done.json", "done", &error));
  OutputSet set;
  ASSERT_TRUE(set.Add(dir + "/a.csv", "new a", &error)) << error;
  ASSERT_TRUE(set.Add(dir + "/b.json", "new b", &error)) << error;
  Write(dir + "/figure.tmp", "drawn");
  {
    const TrackedTemporary figure(dir + "/figure.tmp");
    EXPECT_EQ(Names(dir).size(), 5u);  // a, done, 2 temporaries, figure
    RemoveOwnTemporaries();            // what a SIGTERM handler calls
  }
  EXPECT_EQ(Names(dir), (std::set<std::string>{"a.csv", "done.json"}));
  EXPECT_EQ(Read(dir + "/a.csv"), "old a");
  // The set's temporaries are gone: its commit says so, and changes nothing.
  EXPECT_FALSE(set.Commit(&error));
  EXPECT_EQ(error.rfind("cannot rename '" + TemporaryPath(dir + "/a.csv"), 0),
            0u)
      << error;
  EXPECT_EQ(Read(dir + "/a.csv"), "old a");
  // Untracked once destroyed: a later file of that name is not removed.
  Write(dir + "/figure.tmp", "kept");
  RemoveOwnTemporaries();
  EXPECT_EQ(Read(dir + "/figure.tmp"), "kept");
}

extern "C" void RemoveOwnTemporariesAndExit(int) {
  RemoveOwnTemporaries();
  _exit(3);
}

TEST(OutputSetTest, AProcessKilledBeforeItsCommitLeavesTheOldFilesOnly) {
  const std::string dir = FolderWithOldA("killed");
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    signal(SIGTERM, RemoveOwnTemporariesAndExit);
    OutputSet set;
    std::string error;
    const bool added = set.Add(dir + "/a.csv", "new a", &error) &&
                       set.Add(dir + "/b.json", "new b", &error);
    const char byte = added ? 'y' : 'n';
    if (write(ready[1], &byte, 1) != 1) _exit(4);
    for (;;) pause();  // killed here, before the commit
  }
  char byte = 0;
  ASSERT_EQ(read(ready[0], &byte, 1), 1);
  EXPECT_EQ(byte, 'y');
  EXPECT_EQ(Names(dir).size(), 3u);  // a.csv and the two temporaries
  kill(child, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3) << status;
  EXPECT_EQ(Names(dir), (std::set<std::string>{"a.csv"}));
  EXPECT_EQ(Read(dir + "/a.csv"), "old a");
  close(ready[0]);
  close(ready[1]);
}

// A handler's RemoveOwnTemporaries runs while other threads track and
// untrack: it removes only paths that were tracked, never one read half
// from the old path of a slot and half from the new (every such mixture
// exists as a file here and must survive).
TEST(OutputSetTest, RemoveOwnTemporariesNeverReadsAPathHalfRewritten) {
  const std::string dir = MakeFolder("torn");
  const std::string a(6, 'a'), b(6, 'b');
  std::vector<std::string> mixtures;
  for (int bits = 1; bits < 63; ++bits) {
    std::string name;
    for (int k = 0; k < 6; ++k) name += (bits >> k & 1) ? 'b' : 'a';
    mixtures.push_back(name);
    Write(dir + "/" + name, "keep");
  }
  std::atomic<bool> stop{false};
  std::thread tracker([&] {
    for (int k = 0; !stop.load(); ++k) {
      const TrackedTemporary temporary(dir + "/" + (k % 2 ? b : a));
    }
  });
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (std::chrono::steady_clock::now() < end) RemoveOwnTemporaries();
  stop = true;
  tracker.join();
  for (const std::string& name : mixtures) {
    EXPECT_EQ(Read(dir + "/" + name), "keep") << name;
  }
}

}  // namespace
}  // namespace activecal
