#include <gtest/gtest.h>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"
#include "occlusion_env/occlusion/reward.hpp"

namespace occlusion_env {
namespace {

// A 4x4 hand-made image: object 0 covers columns 0-2, object 1 columns 1-3, object 2 row 0.
cv::Mat handMadeBits() {
  cv::Mat bits(4, 4, CV_8UC1, cv::Scalar(0));
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) {
      std::uint8_t value = 0;
      if (col <= 2) value |= 1;
      if (col >= 1) value |= 2;
      if (row == 0) value |= 4;
      bits.at<std::uint8_t>(row, col) = value;
    }
  }
  bits.at<std::uint8_t>(3, 3) |= 0x80;  // a bit beyond the object count is ignored
  return bits;
}

TEST(OcclusionTest, PairListHoldsTwentyEightPairsInline) {
  PairOcclusionList pairs;
  EXPECT_TRUE(pairs.empty());
  for (int i = 0; i < 28; ++i) pairs.push_back({i, i + 1, i * 10});
  EXPECT_EQ(pairs.size(), 28u);
  EXPECT_THROW(pairs.push_back({0, 1, 0}), InvalidArgumentError);
  EXPECT_THROW(pairs.resize(29), InvalidArgumentError);
  EXPECT_EQ(pairs.size(), 28u);
  PairOcclusionList copy = pairs;
  copy[3].pixels = -1;
  EXPECT_EQ(pairs[3].pixels, 30);
  copy.resize(2);
  copy.resize(4);  // regrown slots are zero, not the old pairs
  EXPECT_EQ(copy[3].pixels, 0);
  EXPECT_EQ(copy[3].first, 0);
  std::int64_t sum = 0;
  for (const PairOcclusion& pair : pairs) sum += pair.pixels;
  EXPECT_EQ(sum, 10 * 27 * 28 / 2);
  copy.clear();
  EXPECT_TRUE(copy.empty());
}

TEST(OcclusionTest, CountsPairsAsEquationNine) {
  cv::Mat mask;
  const OcclusionStats stats = computeOcclusion(handMadeBits(), 3, &mask);
  ASSERT_EQ(stats.pairs.size(), 3u);
  EXPECT_EQ(stats.pairs[0].first, 0);
  EXPECT_EQ(stats.pairs[0].second, 1);
  EXPECT_EQ(stats.pairs[0].pixels, 8);  // columns 1-2, 4 rows
  EXPECT_EQ(stats.pairs[1].pixels, 3);  // (0,2): row 0, columns 0-2
  EXPECT_EQ(stats.pairs[2].pixels, 3);  // (1,2): row 0, columns 1-3
  EXPECT_EQ(stats.total_pixels, 14);
  // Row 0 is covered everywhere by two or more; rows 1-3 at columns 1-2.
  EXPECT_EQ(stats.occluded_area_pixels, 4 + 3 * 2);
  EXPECT_EQ(stats.union_pixels, 16);
  ASSERT_EQ(mask.type(), CV_8UC1);
  EXPECT_EQ(cv::countNonZero(mask), 10);
  EXPECT_EQ(mask.at<std::uint8_t>(1, 1), 255);
  EXPECT_EQ(mask.at<std::uint8_t>(1, 0), 0);
}

TEST(OcclusionTest, TripleOverlapCountsThreePairs) {
  cv::Mat bits(1, 2, CV_8UC1, cv::Scalar(7));
  const OcclusionStats stats = computeOcclusion(bits, 3);
  EXPECT_EQ(stats.total_pixels, 6);
  EXPECT_EQ(stats.occluded_area_pixels, 2);
}

TEST(OcclusionTest, NoOverlapIsZero) {
  cv::Mat bits(2, 2, CV_8UC1, cv::Scalar(0));
  bits.at<std::uint8_t>(0, 0) = 1;
  bits.at<std::uint8_t>(1, 1) = 2;
  const OcclusionStats stats = computeOcclusion(bits, 2);
  EXPECT_EQ(stats.total_pixels, 0);
  EXPECT_EQ(stats.union_pixels, 2);
}

TEST(OcclusionTest, ARegionGivesTheSameFiguresAndLeavesTheMaskOutsideIt) {
  cv::Mat bits(6, 7, CV_8UC1, cv::Scalar(0));
  handMadeBits().copyTo(bits(cv::Rect(2, 1, 4, 4)));
  cv::Mat whole_mask;
  const OcclusionStats whole = computeOcclusion(bits, 3, &whole_mask);

  cv::Mat mask;  // allocated here: 0 outside the region
  const OcclusionStats inside = computeOcclusion(bits, 3, cv::Rect(1, 1, 5, 5), &mask);
  EXPECT_EQ(inside.total_pixels, whole.total_pixels);
  EXPECT_EQ(inside.occluded_area_pixels, whole.occluded_area_pixels);
  EXPECT_EQ(inside.union_pixels, whole.union_pixels);
  ASSERT_EQ(inside.pairs.size(), whole.pairs.size());
  for (std::size_t p = 0; p < whole.pairs.size(); ++p) {
    EXPECT_EQ(inside.pairs[p].pixels, whole.pairs[p].pixels);
  }
  EXPECT_EQ(cv::countNonZero(mask != whole_mask), 0);

  // A reused mask keeps its pixels outside the region; a region beyond the image is clipped.
  mask.at<std::uint8_t>(0, 0) = 7;
  computeOcclusion(bits, 3, cv::Rect(1, 1, 50, 50), &mask);
  EXPECT_EQ(mask.at<std::uint8_t>(0, 0), 7);
  EXPECT_EQ(mask.at<std::uint8_t>(2, 3), 255);
}

TEST(OcclusionTest, RejectsBadInput) {
  EXPECT_THROW(computeOcclusion(cv::Mat(2, 2, CV_32FC1), 2), InvalidArgumentError);
  EXPECT_THROW(computeOcclusion(cv::Mat(2, 2, CV_8UC1), 0), InvalidArgumentError);
  EXPECT_THROW(computeOcclusion(cv::Mat(2, 2, CV_8UC1), 9), InvalidArgumentError);
}

OcclusionStats firstFrame(std::int64_t occlusion, std::int64_t union_pixels) {
  OcclusionStats stats;
  stats.total_pixels = occlusion;
  stats.union_pixels = union_pixels;
  return stats;
}

TEST(RewardTest, UnionNormalisation) {
  RewardFunction reward;  // union is the default
  reward.startEpisode(firstFrame(400, 2000));
  EXPECT_DOUBLE_EQ(reward.normalizer(), 2000.0);
  EXPECT_DOUBLE_EQ(reward(400, 300), 100.0 / 2000.0 - 0.2);
  EXPECT_DOUBLE_EQ(reward(300, 0), 300.0 / 2000.0 + 5.0);
  EXPECT_DOUBLE_EQ(reward(300, 350), -50.0 / 2000.0 - 0.2);
}

TEST(RewardTest, IntersectionNormalisation) {
  RewardOptions options;
  options.normalization = RewardNormalization::kIntersection;
  RewardFunction reward(options);
  reward.startEpisode(firstFrame(400, 2000));
  EXPECT_DOUBLE_EQ(reward.normalizer(), 400.0);
  EXPECT_DOUBLE_EQ(reward(400, 300), 0.25 - 0.2);
  EXPECT_DOUBLE_EQ(reward(100, 0), 0.25 + 5.0);
}

TEST(RewardTest, NoNormalisationAndThreshold) {
  RewardOptions options;
  options.normalization = RewardNormalization::kNone;
  options.success_threshold_pixels = 10;
  options.success_bonus = 2.0;
  options.step_penalty = -1.0;
  RewardFunction reward(options);
  reward.startEpisode(firstFrame(400, 2000));
  EXPECT_DOUBLE_EQ(reward.normalizer(), 1.0);
  EXPECT_DOUBLE_EQ(reward(30, 10), 20.0 + 2.0);
  EXPECT_DOUBLE_EQ(reward(30, 11), 19.0 - 1.0);
  EXPECT_TRUE(reward.solved(10));
  EXPECT_FALSE(reward.solved(11));
}

TEST(RewardTest, NormaliserNeverBelowOne) {
  RewardOptions options;
  options.normalization = RewardNormalization::kIntersection;
  RewardFunction reward(options);
  reward.startEpisode(firstFrame(0, 0));
  EXPECT_DOUBLE_EQ(reward.normalizer(), 1.0);
}

TEST(RewardTest, ParsesNormalisationNames) {
  for (const auto value : {RewardNormalization::kUnion, RewardNormalization::kIntersection,
                           RewardNormalization::kNone}) {
    EXPECT_EQ(parseRewardNormalization(toString(value)), value);
  }
  EXPECT_THROW(parseRewardNormalization("Union"), InvalidArgumentError);
  EXPECT_THROW(parseRewardNormalization(""), InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
