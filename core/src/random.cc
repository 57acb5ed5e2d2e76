// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/core/random.h"

#include <cmath>
#include <unordered_set>

namespace activecal {

double Random::Uniform() {
  return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
}

uint64_t Random::UniformInt(uint64_t n) {
  // Rejection sampling on the largest multiple of n.
  const uint64_t limit = UINT64_MAX - UINT64_MAX % n;
  uint64_t x;
  do {
    x = engine_();
  } while (x >= limit);
  return x % n;
}

double Random::Gaussian() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u, v, s;
  do {
    u = 2.0 * Uniform() - 1.0;
    v = 2.0 * Uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double f = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v * f;
  has_spare_ = true;
  return u * f;
}

std::vector<int64_t> Random::SampleWithoutReplacement(int64_t n, int64_t k) {
  std::vector<int64_t> out;
  out.reserve(k);
  if (2 * k > n) {
    // Dense case: partial Fisher-Yates over all of [0, n).
    std::vector<int64_t> all(n);
    for (int64_t i = 0; i < n; ++i) all[i] = i;
    for (int64_t i = 0; i < k; ++i) {
      const int64_t j = i + static_cast<int64_t>(UniformInt(n - i));
      std::swap(all[i], all[j]);
      out.push_back(all[i]);
    }
    return out;
  }
  std::unordered_set<int64_t> seen;
  while (static_cast<int64_t>(out.size()) < k) {
    const int64_t x = static_cast<int64_t>(UniformInt(n));
    if (seen.insert(x).second) out.push_back(x);
  }
  return out;
}

uint64_t Random::StreamSeed(uint64_t seed, uint64_t stream) {
  // splitmix64 of a combination: well-mixed, cheap, platform independent.
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace activecal
