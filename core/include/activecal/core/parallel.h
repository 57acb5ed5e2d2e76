// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A minimal static-partition parallel for. Each index is handled by exactly
// one call, and work is split into contiguous ranges, so results written per
// index do not depend on the thread count. The threads are kept in a pool
// for the life of the process and reused by every call (the selection
// loops call it once per swap); a call nested in another, or made while
// another thread's call holds the pool, starts threads of its own.

#ifndef ACTIVECAL_CORE_PARALLEL_H_
#define ACTIVECAL_CORE_PARALLEL_H_

#include <cstdint>
#include <functional>

namespace activecal {

// The number of threads to use for a request: num_threads > 0 is taken as
// is, anything else means all hardware threads.
int ResolveNumThreads(int num_threads);

// Calls fn(begin, end, thread_id) over disjoint ranges covering [0, n):
// range t = [t * ceil(n / threads), ...) goes to thread_id t. Runs inline
// when one thread is asked for or n is 1.
void ParallelFor(int64_t n, int num_threads,
                 const std::function<void(int64_t, int64_t, int)>& fn);

}  // namespace activecal

#endif  // ACTIVECAL_CORE_PARALLEL_H_
