// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/sigpipe_block.h"

#include <pthread.h>

#include <cerrno>

namespace activecal {
namespace {

sigset_t SigpipeSet() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGPIPE);
  return set;
}

bool SigpipePending() {
  sigset_t pending;
  sigemptyset(&pending);
  sigpending(&pending);
  return sigismember(&pending, SIGPIPE) == 1;
}

}  // namespace

SigpipeBlock::SigpipeBlock() : was_pending_(SigpipePending()) {
  const sigset_t sigpipe = SigpipeSet();
  pthread_sigmask(SIG_BLOCK, &sigpipe, &old_mask_);
}

SigpipeBlock::~SigpipeBlock() {
  const int saved = errno;
  if (!was_pending_ && SigpipePending()) {
    const sigset_t sigpipe = SigpipeSet();
    const timespec zero{0, 0};
    while (sigtimedwait(&sigpipe, nullptr, &zero) < 0 && errno == EINTR) {
    }
  }
  pthread_sigmask(SIG_SETMASK, &old_mask_, nullptr);
  errno = saved;
}

}  // namespace activecal
