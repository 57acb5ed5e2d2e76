// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Writing to a pipe whose reader may have gone (a driver program, gnuplot)
// without SIGPIPE ending the process, and without changing the process's
// disposition of SIGPIPE (which other threads and `activecal_x | head`
// rely on): while a SigpipeBlock lives, SIGPIPE is blocked in the calling
// thread, so such a write fails with EPIPE instead. When it ends, a SIGPIPE
// raised in the meantime is taken off the pending set (one already pending
// before is left), and the thread's signal mask is restored.
//
//   {
//     SigpipeBlock block;
//     n = write(fd, data, size);   // EPIPE, not a signal
//   }

#ifndef ACTIVECAL_IO_SIGPIPE_BLOCK_H_
#define ACTIVECAL_IO_SIGPIPE_BLOCK_H_

#include <signal.h>

namespace activecal {

class SigpipeBlock {
 public:
  SigpipeBlock();
  ~SigpipeBlock();
  SigpipeBlock(const SigpipeBlock&) = delete;
  SigpipeBlock& operator=(const SigpipeBlock&) = delete;

 private:
  sigset_t old_mask_;
  bool was_pending_;
};

}  // namespace activecal

#endif  // ACTIVECAL_IO_SIGPIPE_BLOCK_H_
