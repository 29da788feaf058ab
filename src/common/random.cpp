#include "occlusion_env/common/random.hpp"

#include <cmath>

namespace occlusion_env {
namespace {

std::uint64_t splitMix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t rotateLeft(std::uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}

}  // namespace

RandomSource::RandomSource(std::uint64_t seed) {
  std::uint64_t mix = seed;
  for (std::uint64_t& word : state_) word = splitMix64(mix);
}

std::uint64_t RandomSource::nextU64() {
  const std::uint64_t result = rotateLeft(state_[1] * 5, 7) * 9;
  const std::uint64_t t = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = rotateLeft(state_[3], 45);
  return result;
}

double RandomSource::uniform() {
  // The top 53 bits give every double in [0, 1) on a 2^-53 grid.
  return static_cast<double>(nextU64() >> 11) * 0x1.0p-53;
}

double RandomSource::uniform(double lo, double hi) {
  return lo + (hi - lo) * uniform();
}

double RandomSource::normal(double mean, double stddev) {
  // Box-Muller; 1 - u lies in (0, 1], so the logarithm is finite.
  const double u1 = 1.0 - uniform();
  const double u2 = uniform();
  return mean + stddev * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

std::uint64_t RandomSource::below(std::uint64_t n) {
  // Rejection sampling: no modulo bias.
  const std::uint64_t limit = ~std::uint64_t{0} - (~std::uint64_t{0} % n);
  std::uint64_t draw;
  do {
    draw = nextU64();
  } while (draw >= limit);
  return draw % n;
}

}  // namespace occlusion_env
