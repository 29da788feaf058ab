#include "occlusion_env/common/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

TEST(StatisticsTest, MeanOfNoValuesIsNaNNotZero) {
  EXPECT_DOUBLE_EQ(mean({1.0, 2.0, 6.0}), 3.0);
  EXPECT_DOUBLE_EQ(mean({-2.5}), -2.5);
  EXPECT_TRUE(std::isnan(mean({})));  // no steps measured is not 0 steps
}

TEST(StatisticsTest, MedianOfAnOddCountIsTheMiddleOfAnEvenCountTheMeanOfTheTwo) {
  EXPECT_DOUBLE_EQ(median({5.0, 1.0, 3.0}), 3.0);
  EXPECT_DOUBLE_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);  // not the upper middle, 3
  EXPECT_DOUBLE_EQ(median({7.0}), 7.0);
  EXPECT_TRUE(std::isnan(median({})));
}

TEST(StatisticsTest, PercentileTakesTheNearestRankOfTheSortedValues) {
  std::vector<double> values;
  for (int i = 100; i >= 0; --i) values.push_back(i);  // 0..100, unsorted
  EXPECT_DOUBLE_EQ(percentile(values, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(percentile(values, 0.9), 90.0);
  EXPECT_DOUBLE_EQ(percentile(values, 1.0), 100.0);
  // 0.025 * 3 = 0.075 rounds to rank 0; 0.975 * 3 = 2.925 to rank 3, not down to 2.
  EXPECT_DOUBLE_EQ(percentile({40.0, 10.0, 30.0, 20.0}, 0.025), 10.0);
  EXPECT_DOUBLE_EQ(percentile({40.0, 10.0, 30.0, 20.0}, 0.975), 40.0);
  EXPECT_TRUE(std::isnan(percentile({}, 0.5)));
  EXPECT_THROW(percentile(values, 1.5), InvalidArgumentError);
  EXPECT_THROW(percentile(values, std::nan("")), InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
