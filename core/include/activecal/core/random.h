// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// A seeded random source whose streams are the same on every platform and
// standard library: std::mt19937_64 (fully specified by the standard) with
// our own uniform, integer and Gaussian transforms (the std:: distributions
// are implementation-defined).

#ifndef ACTIVECAL_CORE_RANDOM_H_
#define ACTIVECAL_CORE_RANDOM_H_

#include <cstdint>
#include <random>
#include <vector>

namespace activecal {

class Random {
 public:
  explicit Random(uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1), 53 random bits.
  double Uniform();
  // Uniform integer in [0, n), n > 0, without modulo bias.
  uint64_t UniformInt(uint64_t n);
  // Standard normal (Marsaglia's polar method).
  double Gaussian();
  // k distinct integers from [0, n), in the order drawn. Requires k <= n.
  std::vector<int64_t> SampleWithoutReplacement(int64_t n, int64_t k);

  // A seed for an independent stream, e.g. one per restart. Deterministic in
  // (seed, stream) and independent of how many numbers were drawn.
  static uint64_t StreamSeed(uint64_t seed, uint64_t stream);

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace activecal

#endif  // ACTIVECAL_CORE_RANDOM_H_
