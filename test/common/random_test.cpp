#include "occlusion_env/common/random.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace occlusion_env {
namespace {

TEST(RandomSourceTest, SameSeedSameStreamOtherSeedOtherStream) {
  RandomSource a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 100; ++i) {
    const std::uint64_t x = a.nextU64();
    EXPECT_EQ(x, b.nextU64());
    differs = differs || x != c.nextU64();
  }
  EXPECT_TRUE(differs);
}

TEST(RandomSourceTest, KnownFirstDrawPinsTheAlgorithm) {
  // splitmix64-seeded xoshiro256**: a change of algorithm would change every scene of every seed.
  RandomSource random(0);
  const std::uint64_t first = random.nextU64();
  RandomSource again(0);
  EXPECT_EQ(first, again.nextU64());
  EXPECT_EQ(first, 0x99ec5f36cb75f2b4ULL);
}

TEST(RandomSourceTest, UniformAndNormalMoments) {
  RandomSource random(7);
  const int n = 200000;
  double sum = 0, sum_sq = 0, normal_sum = 0, normal_sq = 0;
  std::vector<int> buckets(5, 0);
  for (int i = 0; i < n; ++i) {
    const double u = random.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum_sq += u * u;
    const double z = random.normal(1.0, 2.0);
    normal_sum += z;
    normal_sq += (z - 1.0) * (z - 1.0);
    ++buckets[random.below(5)];
  }
  EXPECT_NEAR(sum / n, 0.5, 0.005);
  EXPECT_NEAR(sum_sq / n - 0.25, 1.0 / 12.0, 0.003);
  EXPECT_NEAR(normal_sum / n, 1.0, 0.02);
  EXPECT_NEAR(std::sqrt(normal_sq / n), 2.0, 0.02);
  for (int count : buckets) EXPECT_NEAR(count, n / 5, n / 100);
}

}  // namespace
}  // namespace occlusion_env
