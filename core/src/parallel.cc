#include "activecal/core/parallel.h"

#include <algorithm>
#include <thread>
#include <vector>

namespace activecal {

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
  std::vector<std::thread> workers;
  workers.reserve(threads - 1);
  const int64_t chunk = (n + threads - 1) / threads;
  for (int t = 1; t < threads; ++t) {
    const int64_t begin = std::min(n, t * chunk);
    const int64_t end = std::min(n, begin + chunk);
    workers.emplace_back([&fn, begin, end, t] { fn(begin, end, t); });
  }
  fn(0, std::min(n, chunk), 0);
  for (std::thread& w : workers) w.join();
}

}  // namespace activecal
