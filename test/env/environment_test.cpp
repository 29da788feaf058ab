#include "occlusion_env/env/environment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

EnvironmentOptions smallOptions() {
  EnvironmentOptions options;  // embedded objects
  options.width = 128;
  options.height = 128;
  return options;
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  for (int row = 0; row < a.rows; ++row) {
    if (std::memcmp(a.ptr(row), b.ptr(row), a.cols * a.elemSize()) != 0) return false;
  }
  return true;
}

bool identical(const Observation& a, const Observation& b) {
  return identical(a.rgb, b.rgb) && identical(a.depth, b.depth) &&
         identical(a.instance, b.instance) && identical(a.amodal_bits, b.amodal_bits) &&
         identical(a.occlusion_mask, b.occlusion_mask);
}

Observation copyOf(const Observation& observation) {
  return {observation.rgb.clone(), observation.depth.clone(), observation.instance.clone(),
          observation.amodal_bits.clone(), observation.occlusion_mask.clone()};
}

TEST(EnvironmentTest, ResetShowsOcclusionFromTheStartPose) {
  Environment env(smallOptions());
  const StepResult result = env.reset(11);
  ASSERT_NE(result.observation, nullptr);
  EXPECT_GT(result.info.occlusion.total_pixels, 0);
  EXPECT_EQ(result.info.step_index, 0);
  EXPECT_FALSE(result.terminated);
  EXPECT_LE(std::abs(result.info.pose.azimuth_rad), M_PI / 32.0);
  EXPECT_DOUBLE_EQ(result.info.pose.elevation_rad, 0.0);
  EXPECT_EQ(env.scene().objects.size(), 3u);
  const Observation& observation = *result.observation;
  EXPECT_EQ(observation.rgb.type(), CV_8UC3);
  EXPECT_EQ(observation.depth.type(), CV_32FC1);
  EXPECT_EQ(observation.rgb.size(), cv::Size(128, 128));
  EXPECT_EQ(cv::countNonZero(observation.occlusion_mask),
            result.info.occlusion.occluded_area_pixels);
  // Depth: NaN on the background, within the scene's reach elsewhere.
  int hits = 0;
  for (int row = 0; row < 128; ++row) {
    for (int col = 0; col < 128; ++col) {
      const float depth = observation.depth.at<float>(row, col);
      const bool background = observation.instance.at<std::uint8_t>(row, col) == 0;
      EXPECT_EQ(std::isnan(depth), background);
      if (!background) {
        ++hits;
        EXPECT_GT(depth, 0.5f);
        EXPECT_LT(depth, 6.0f);
      }
    }
  }
  EXPECT_GT(hits, 100);
}

TEST(EnvironmentTest, SameSeedGivesBitIdenticalObservationsAcrossEnvironments) {
  Environment first(smallOptions());
  Environment second(smallOptions());
  const Observation a = copyOf(*first.reset(1234).observation);
  second.reset(99);  // other state in between must not matter
  const Observation b = copyOf(*second.reset(1234).observation);
  EXPECT_TRUE(identical(a, b));
  EXPECT_EQ(first.info().pose.azimuth_rad, second.info().pose.azimuth_rad);
  for (int t = 0; t < 5; ++t) {
    const StepResult ra = first.step({0.3, 1.0});
    const StepResult rb = second.step({0.3, 1.0});
    EXPECT_EQ(ra.reward, rb.reward);
    EXPECT_TRUE(identical(*ra.observation, *rb.observation));
  }
  const Observation other = copyOf(*second.reset(1235).observation);
  EXPECT_FALSE(identical(a, other));
}

TEST(EnvironmentTest, NormalisedStepMovesExactlyOneUnitAlongTheAction) {
  Environment env(smallOptions());
  const SphericalPose start = env.reset(5).info.pose;
  const StepResult result = env.step({3.0, 4.0});
  EXPECT_NEAR(result.info.pose.azimuth_rad - start.azimuth_rad, 0.05 * 0.6, 1e-12);
  EXPECT_NEAR(result.info.pose.elevation_rad - start.elevation_rad, 0.05 * 0.8, 1e-12);
  EXPECT_EQ(result.info.step_index, 1);
}

TEST(EnvironmentTest, ExtremeFiniteActionsStillMoveOneUnit) {
  Environment env(smallOptions());
  for (const Action action : {Action{1e-320, 0.0}, Action{0.0, -1e308}, Action{1e308, 1e308},
                              Action{-4.9e-324, 4.9e-324}}) {
    const SphericalPose before = env.reset(5).info.pose;
    const SphericalPose after = env.step(action).info.pose;
    const double moved = std::hypot(after.azimuth_rad - before.azimuth_rad,
                                    after.elevation_rad - before.elevation_rad);
    EXPECT_NEAR(moved, 0.05, 1e-9) << action.d_azimuth_rad << ", " << action.d_elevation_rad;
  }
}

TEST(EnvironmentTest, UnnormalisedStepIsClippedToTheStepSize) {
  EnvironmentOptions options = smallOptions();
  options.normalize_action = false;
  Environment env(options);
  const SphericalPose start = env.reset(5).info.pose;
  const SphericalPose small = env.step({0.01, 0.0}).info.pose;
  EXPECT_NEAR(small.azimuth_rad - start.azimuth_rad, 0.01, 1e-12);
  const SphericalPose big = env.step({0.0, -2.0}).info.pose;
  EXPECT_NEAR(big.elevation_rad - small.elevation_rad, -0.05, 1e-12);
}

TEST(EnvironmentTest, ZeroActionIsANoOpStep) {
  Environment env(smallOptions());
  const StepResult start = env.reset(8);
  const Observation before = copyOf(*start.observation);
  const StepResult result = env.step({0.0, 0.0});
  EXPECT_EQ(result.info.step_index, 1);
  EXPECT_EQ(result.info.pose.azimuth_rad, start.info.pose.azimuth_rad);
  EXPECT_TRUE(identical(before, *result.observation));
  EXPECT_DOUBLE_EQ(result.reward, -0.2);  // no change, not solved: the step penalty alone
}

TEST(EnvironmentTest, ViewFromRendersAPoseOutsideTheEpisodesSteps) {
  Environment stepped(smallOptions());
  stepped.reset(5);
  const StepResult moved = stepped.step({1.0, 1.0});
  const Observation expected = copyOf(*moved.observation);

  Environment placed(smallOptions());
  EXPECT_THROW(placed.viewFrom(moved.info.pose), InvalidStateError);
  placed.reset(5);
  EXPECT_THROW(placed.viewFrom({NAN, 0.0}), InvalidArgumentError);
  const StepInfo& info = placed.viewFrom(moved.info.pose);
  EXPECT_EQ(info.step_index, 0);  // not a step
  EXPECT_EQ(info.pose.azimuth_rad, moved.info.pose.azimuth_rad);
  EXPECT_EQ(info.occlusion.total_pixels, moved.info.occlusion.total_pixels);
  EXPECT_TRUE(identical(expected, placed.observation()));
  EXPECT_EQ(placed.step({0.0, 1.0}).info.step_index, 1);  // the episode goes on from there
  // Beyond the elevation limit it stops at the limit, as a step would.
  EXPECT_DOUBLE_EQ(placed.viewFrom({0.0, 2.0}).pose.elevation_rad,
                   placed.options().elevation_limit_rad);
}

TEST(EnvironmentTest, MoveOutsideEpisodeMovesAsAStepWithoutTheRule) {
  Environment stepped(smallOptions());
  stepped.reset(5);
  stepped.step({1.0, 0.5});
  const StepResult second = stepped.step({-0.3, 1.0});
  const Observation expected = copyOf(*second.observation);

  Environment moved(smallOptions());
  EXPECT_THROW(moved.moveOutsideEpisode({1.0, 0.5}), InvalidStateError);
  moved.reset(5);
  moved.moveOutsideEpisode({1.0, 0.5});
  const StepInfo& info = moved.moveOutsideEpisode({-0.3, 1.0});
  EXPECT_EQ(info.step_index, 2);  // its moves counted
  EXPECT_EQ(info.last_action.d_azimuth_rad, -0.3);
  EXPECT_EQ(info.last_action.d_elevation_rad, 1.0);
  EXPECT_EQ(info.pose.azimuth_rad, second.info.pose.azimuth_rad);
  EXPECT_EQ(info.pose.elevation_rad, second.info.pose.elevation_rad);
  EXPECT_EQ(info.occlusion.total_pixels, second.info.occlusion.total_pixels);
  EXPECT_TRUE(identical(expected, moved.observation()));
  EXPECT_THROW(moved.moveOutsideEpisode({NAN, 0.0}), InvalidArgumentError);
  // The episode's rule never saw those moves: the next step is its first.
  EXPECT_EQ(moved.step({0.0, 1.0}).info.step_index, 1);
}

TEST(EnvironmentTest, RewardAndFlagsFollowTheOcclusion) {
  EnvironmentOptions options = smallOptions();
  options.max_steps = 4;
  Environment env(options);
  StepResult previous = env.reset(21);
  const double normalizer = env.reward().normalizer();
  EXPECT_DOUBLE_EQ(normalizer, static_cast<double>(previous.info.occlusion.union_pixels));
  for (int t = 1; t <= 4; ++t) {
    const StepResult result = env.step({1.0, 0.0});
    const bool solved = result.info.occlusion.total_pixels == 0;
    const double expected =
        (previous.info.occlusion.total_pixels - result.info.occlusion.total_pixels) / normalizer +
        (solved ? 5.0 : -0.2);
    EXPECT_DOUBLE_EQ(result.reward, expected);
    EXPECT_EQ(result.terminated, solved);
    EXPECT_EQ(result.truncated, !solved && t == 4);
    previous = result;
    if (result.terminated || result.truncated) break;
  }
  EXPECT_THROW(env.step({1.0, 0.0}), InvalidStateError);  // the episode is over
}

TEST(EnvironmentTest, BadInputIsAnErrorAndLeavesTheStateUnchanged) {
  Environment env(smallOptions());
  EXPECT_THROW(env.step({0.1, 0.0}), InvalidStateError);
  EXPECT_THROW(env.renderAt({0.0, 0.0}), InvalidStateError);
  env.reset(3);
  env.step({1.0, 0.0});
  const StepInfo before = env.info();
  const Observation observation = copyOf(env.observation());
  EXPECT_THROW(env.step({NAN, 0.0}), InvalidArgumentError);
  EXPECT_THROW(env.step({0.0, INFINITY}), InvalidArgumentError);
  ResetOptions unknown;
  unknown.object_ids = {"embedded/no_such_thing"};
  EXPECT_THROW(env.reset(4, unknown), InvalidArgumentError);
  ResetOptions bad_category;
  bad_category.categories = {"spaceship"};
  EXPECT_THROW(env.reset(4, bad_category), InvalidArgumentError);
  ResetOptions bad_preset;
  bad_preset.preset = "three_chairs";
  EXPECT_THROW(env.reset(4, bad_preset), InvalidArgumentError);
  ResetOptions bad_pose;
  bad_pose.start_elevation_rad = 2.0;
  EXPECT_THROW(env.reset(4, bad_pose), InvalidArgumentError);
  // A NaN start elevation is not "beyond the limit": the message says what is wrong.
  bad_pose.start_elevation_rad = std::nan("");
  try {
    env.reset(4, bad_pose);
    ADD_FAILURE() << "a NaN start elevation was accepted";
  } catch (const InvalidArgumentError& error) {
    EXPECT_NE(std::string(error.what()).find("finite"), std::string::npos) << error.what();
  }
  EXPECT_EQ(env.info().step_index, before.step_index);
  EXPECT_EQ(env.info().pose.azimuth_rad, before.pose.azimuth_rad);
  EXPECT_TRUE(identical(observation, env.observation()));
  // The renderer still draws the current scene: a zero step reproduces the observation.
  env.step({0.0, 0.0});
  EXPECT_TRUE(identical(observation, env.observation()));
}

TEST(EnvironmentTest, SceneWithoutOcclusionIsRedrawnThenAClearError) {
  Environment env(smallOptions());
  env.reset(3);
  const Observation observation = copyOf(env.observation());
  // Side by side, far apart: never occluded, so every draw is rejected.
  ResetOptions apart;
  apart.start_azimuth_rad = M_PI / 2.0;
  apart.object_ids = {"embedded/mug", "embedded/mug"};
  try {
    env.reset(4, apart);
    FAIL() << "expected SceneGenerationError";
  } catch (const SceneGenerationError& error) {
    EXPECT_NE(std::string(error.what()).find("20 draws"), std::string::npos) << error.what();
  }
  env.step({0.0, 0.0});
  EXPECT_TRUE(identical(observation, env.observation()));
}

TEST(EnvironmentTest, RejectsImpossibleOptions) {
  EnvironmentOptions options = smallOptions();
  options.width = 0;
  EXPECT_THROW(Environment{options}, InvalidArgumentError);
  options = smallOptions();
  options.radius_m = -1.0;
  EXPECT_THROW(Environment{options}, InvalidArgumentError);
  options = smallOptions();
  options.preset = "nonsense";
  EXPECT_THROW(Environment{options}, InvalidArgumentError);
  options = smallOptions();
  options.catalog.source = "nowhere";
  EXPECT_THROW(Environment{options}, InvalidArgumentError);
  options = smallOptions();
  options.step_size_rad = NAN;
  EXPECT_THROW(Environment{options}, InvalidArgumentError);
}

TEST(EnvironmentTest, TwoChairsPresetAndStartOverrides) {
  Environment env(smallOptions());
  ResetOptions overrides;
  overrides.preset = "two_chairs";
  overrides.start_azimuth_rad = 0.01;
  overrides.start_elevation_rad = 0.2;
  const StepResult result = env.reset(2, overrides);
  ASSERT_EQ(env.scene().objects.size(), 2u);
  EXPECT_EQ(env.scene().objects[0].model->info.category, "chair");
  EXPECT_DOUBLE_EQ(result.info.pose.azimuth_rad, 0.01);
  EXPECT_DOUBLE_EQ(result.info.pose.elevation_rad, 0.2);
}

}  // namespace
}  // namespace occlusion_env
