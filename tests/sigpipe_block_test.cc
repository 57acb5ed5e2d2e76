// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/sigpipe_block.h"

#include <gtest/gtest.h>
#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>

namespace activecal {
namespace {

std::atomic<int> g_sigpipes{0};
extern "C" void CountSigpipe(int) { ++g_sigpipes; }

bool SigpipeBlockedHere() {
  sigset_t mask;
  pthread_sigmask(SIG_SETMASK, nullptr, &mask);
  return sigismember(&mask, SIGPIPE) == 1;
}

bool SigpipePendingHere() {
  sigset_t pending;
  sigpending(&pending);
  return sigismember(&pending, SIGPIPE) == 1;
}

// A pipe whose reader has gone: writing to fds[1] raises SIGPIPE.
void BrokenPipe(int fds[2]) {
  ASSERT_EQ(pipe(fds), 0);
  close(fds[0]);
}

class SigpipeBlockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    struct sigaction counting = {};
    counting.sa_handler = CountSigpipe;
    sigemptyset(&counting.sa_mask);
    ASSERT_EQ(sigaction(SIGPIPE, &counting, &previous_), 0);
    g_sigpipes = 0;
  }
  void TearDown() override { sigaction(SIGPIPE, &previous_, nullptr); }

  // The process's disposition of SIGPIPE is still the counting handler.
  static bool DispositionIsOurs() {
    struct sigaction now = {};
    sigaction(SIGPIPE, nullptr, &now);
    return now.sa_handler == CountSigpipe;
  }

  struct sigaction previous_ = {};
};

TEST_F(SigpipeBlockTest, AWriteToAGonePipeIsEpipeNotASignal) {
  int fds[2];
  ASSERT_NO_FATAL_FAILURE(BrokenPipe(fds));
  const char byte = 'x';
  {
    const SigpipeBlock block;
    EXPECT_TRUE(SigpipeBlockedHere());
    errno = 0;
    EXPECT_EQ(write(fds[1], &byte, 1), -1);
    EXPECT_EQ(errno, EPIPE);
  }
  EXPECT_EQ(errno, EPIPE);  // the block's end keeps the write's errno
  EXPECT_FALSE(SigpipeBlockedHere());
  EXPECT_FALSE(SigpipePendingHere());
  EXPECT_EQ(g_sigpipes.load(), 0);
  EXPECT_TRUE(DispositionIsOurs());
  // Without the block the same write raises the signal (the handler runs).
  EXPECT_EQ(write(fds[1], &byte, 1), -1);
  EXPECT_EQ(g_sigpipes.load(), 1);
  close(fds[1]);
}

TEST_F(SigpipeBlockTest, ASigpipePendingBeforeIsLeftPending) {
  sigset_t sigpipe, old;
  sigemptyset(&sigpipe);
  sigaddset(&sigpipe, SIGPIPE);
  ASSERT_EQ(pthread_sigmask(SIG_BLOCK, &sigpipe, &old), 0);
  pthread_kill(pthread_self(), SIGPIPE);
  ASSERT_TRUE(SigpipePendingHere());
  int fds[2];
  ASSERT_NO_FATAL_FAILURE(BrokenPipe(fds));
  const char byte = 'x';
  {
    const SigpipeBlock block;
    EXPECT_EQ(write(fds[1], &byte, 1), -1);
  }
  // Still blocked (the mask as it was) and still pending: the caller's.
  EXPECT_TRUE(SigpipeBlockedHere());
  EXPECT_TRUE(SigpipePendingHere());
  EXPECT_EQ(g_sigpipes.load(), 0);
  ASSERT_EQ(pthread_sigmask(SIG_SETMASK, &old, nullptr), 0);
  EXPECT_EQ(g_sigpipes.load(), 1);  // delivered once unblocked
  close(fds[1]);
}

}  // namespace
}  // namespace activecal
