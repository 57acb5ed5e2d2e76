// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The options the restarting design algorithms share (FedorovOptions,
// DetmaxOptions, ExchangeAddExchangeOptions, TaskExchangeOptions), set in
// one place for select_design.cc and active_calibration.cc; not installed.
//
//   FedorovOptions o = RestartOptions<FedorovOptions>(30, 16, seed, 0);
//   o.polish_pool_size = 20000;  // the algorithm's own options after

#ifndef ACTIVECAL_CALIBRATION_SRC_RESTART_OPTIONS_H_
#define ACTIVECAL_CALIBRATION_SRC_RESTART_OPTIONS_H_

#include <cstdint>

namespace activecal {
namespace internal {

// Options (default otherwise) with num_poses, restarts, seed and
// num_threads set.
template <typename Options>
Options RestartOptions(int num_poses, int restarts, uint64_t seed,
                       int num_threads) {
  Options o;
  o.num_poses = num_poses;
  o.restarts = restarts;
  o.seed = seed;
  o.num_threads = num_threads;
  return o;
}

}  // namespace internal
}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_SRC_RESTART_OPTIONS_H_
