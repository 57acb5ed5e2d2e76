// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/parallel.h"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace activecal {
namespace {

// Set in the threads of the pool, and in a caller while it runs its share
// of a pool job: a ParallelFor inside either does not wait for the pool it
// runs on (and never locks the run mutex its own thread may hold).
thread_local bool tl_in_pool_worker = false;
thread_local bool tl_owns_pool = false;

// Threads kept for the life of the process; Run hands them one job at a
// time. Created on first use and never destroyed (no static destructor to
// race with threads at exit).
class WorkerPool {
 public:
  // Runs job(1), ..., job(count - 1) on pool threads while the caller runs
  // job(0); returns when all are done. One Run at a time (the caller holds
  // run_mutex()).
  void Run(int count, const std::function<void(int)>& job) {
    std::unique_lock<std::mutex> lock(mutex_);
    while (static_cast<int>(workers_.size()) < count - 1) {
      const int index = static_cast<int>(workers_.size()) + 1;
      workers_.emplace_back([this, index] { WorkerLoop(index); });
    }
    job_ = &job;
    active_ = count - 1;
    remaining_ = count - 1;
    ++generation_;
    lock.unlock();
    wake_.notify_all();
    job(0);
    lock.lock();
    done_.wait(lock, [this] { return remaining_ == 0; });
    job_ = nullptr;
  }

  std::mutex& run_mutex() { return run_mutex_; }

 private:
  void WorkerLoop(int index) {
    tl_in_pool_worker = true;
    uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return generation_ != seen; });
      seen = generation_;
      if (index > active_) continue;
      const std::function<void(int)>* job = job_;
      lock.unlock();
      (*job)(index);
      lock.lock();
      if (--remaining_ == 0) done_.notify_one();
    }
  }

  std::mutex run_mutex_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  const std::function<void(int)>* job_ = nullptr;
  int active_ = 0;
  int remaining_ = 0;
  uint64_t generation_ = 0;
};

WorkerPool& Pool() {
  static WorkerPool* pool = new WorkerPool;
  return *pool;
}

}  // namespace

int ResolveNumThreads(int num_threads) {
  if (num_threads > 0) return num_threads;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

void ParallelFor(int64_t n, int num_threads,
                 const std::function<void(int64_t, int64_t, int)>& fn) {
  if (n <= 0) return;
  const int threads =
      static_cast<int>(std::min<int64_t>(ResolveNumThreads(num_threads), n));
  if (threads <= 1) {
    fn(0, n, 0);
    return;
  }
  // Static partition: thread t gets [t * chunk, (t + 1) * chunk) whoever
  // runs it, so results written per index do not depend on the threads.
  const int64_t chunk = (n + threads - 1) / threads;
  // An exception in any part is kept (the first one) and rethrown once every
  // part has finished, so no thread is left running on a dead stack.
  std::mutex error_mutex;
  std::exception_ptr error;
  const auto run_part = [&](int t) {
    try {
      const int64_t begin = std::min(n, t * chunk);
      const int64_t end = std::min(n, begin + chunk);
      fn(begin, end, t);
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  };
  WorkerPool& pool = Pool();
  std::unique_lock<std::mutex> owner(pool.run_mutex(), std::defer_lock);
  if (!tl_in_pool_worker && !tl_owns_pool && owner.try_lock()) {
    tl_owns_pool = true;
    pool.Run(threads, run_part);
    tl_owns_pool = false;
  } else {
    // Nested in a pool job, or the pool busy with another caller's loop:
    // threads of our own, as many as asked.
    std::vector<std::thread> workers;
    workers.reserve(threads - 1);
    for (int t = 1; t < threads; ++t) workers.emplace_back(run_part, t);
    run_part(0);
    for (std::thread& w : workers) w.join();
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace activecal
