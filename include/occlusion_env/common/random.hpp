// A seeded random source whose draws are identical on every platform and standard library
// (std::normal_distribution and friends are not), so that a seed fixes a scene everywhere.
#pragma once

#include <cstdint>

namespace occlusion_env {

class RandomSource {
 public:
  explicit RandomSource(std::uint64_t seed);

  std::uint64_t nextU64();                    // splitmix64-seeded xoshiro256**
  double uniform();                           // [0, 1)
  double uniform(double lo, double hi);       // [lo, hi)
  double normal(double mean, double stddev);  // Box-Muller
  /// Uniform integer in [0, n); n > 0.
  std::uint64_t below(std::uint64_t n);

 private:
  std::uint64_t state_[4];
};

}  // namespace occlusion_env
