#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/agents/gradient_agent.hpp"
#include "occlusion_env/agents/random_agent.hpp"
#include "occlusion_env/env/environment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

EnvironmentOptions smallOptions() {
  EnvironmentOptions options;  // embedded objects
  options.width = options.height = 128;
  return options;
}

// One episode of `agent` on `env` from `seed`, at most `max_steps` steps.
EpisodeRecord run(EnvironmentInterface& env, Agent& agent, std::uint64_t seed,
                  const ResetOptions& reset, int max_steps) {
  EpisodeRequest request;
  request.agent = "test";
  request.scene_set = "test";
  request.seed = seed;
  request.reset = reset;
  EpisodeRunOptions options;
  options.max_steps = max_steps;
  return runEpisode(env, agent, request, options);
}

TEST(AgentTest, RandomAgentIsDeterministicPerSeedAndGivesUnitDirections) {
  RandomAgent first(5), second(99);
  second.reset(5);
  const Observation images;
  const RigObservation observation = rigObservationOf(images, StepInfo{});
  double mean_azimuth = 0.0, mean_elevation = 0.0;
  bool differs_from_other_seed = false;
  RandomAgent other(6);
  for (int t = 0; t < 1000; ++t) {
    const Action a = first.act(observation);
    const Action b = second.act(observation);
    const Action c = other.act(observation);
    EXPECT_EQ(a.d_azimuth_rad, b.d_azimuth_rad);
    EXPECT_EQ(a.d_elevation_rad, b.d_elevation_rad);
    EXPECT_NEAR(std::hypot(a.d_azimuth_rad, a.d_elevation_rad), 1.0, 1e-12);
    differs_from_other_seed |= a.d_azimuth_rad != c.d_azimuth_rad;
    mean_azimuth += a.d_azimuth_rad / 1000;
    mean_elevation += a.d_elevation_rad / 1000;
  }
  EXPECT_TRUE(differs_from_other_seed);
  // Uniform directions: the mean of 1000 unit vectors lies near 0 (standard error ~0.022).
  EXPECT_LT(std::abs(mean_azimuth), 0.1);
  EXPECT_LT(std::abs(mean_elevation), 0.1);
}

TEST(AgentTest, GradientAgentStepsDownhillAndFallsBackToRandomMoves) {
  GradientResult next;
  GradientAgent agent([&next]() { return next; }, 3);
  next.valid = true;
  next.gradient = {3.0, -4.0};
  const Observation images;
  const RigObservation observation = rigObservationOf(images, StepInfo{});
  Action action = agent.act(observation);
  EXPECT_NEAR(action.d_azimuth_rad, -0.6, 1e-12);
  EXPECT_NEAR(action.d_elevation_rad, 0.8, 1e-12);
  EXPECT_EQ(agent.randomMoves(), 0);

  next = {};  // invalid, zero
  next.reason = "zero gradient";
  action = agent.act(observation);
  EXPECT_NEAR(std::hypot(action.d_azimuth_rad, action.d_elevation_rad), 1.0, 1e-12);
  EXPECT_EQ(agent.randomMoves(), 1);
  EXPECT_EQ(agent.lastGradient().reason, "zero gradient");
  agent.reset(3);
  EXPECT_EQ(agent.randomMoves(), 0);
  EXPECT_THROW(GradientAgent{OcclusionGradientSource{}}, InvalidArgumentError);
}

TEST(AgentTest, GradientAgentReducesOcclusionAndBeatsRandomMoves) {
  EnvironmentOptions options;  // embedded objects, 256 px
  Environment env(options);
  GradientAgent gradient_agent([&env] { return env.occlusionGradient(); });
  RandomAgent random_agent;
  ResetOptions reset;
  reset.start_azimuth_rad = 0.0;
  int gradient_successes = 0, random_successes = 0, gradient_steps = 0, random_steps = 0;
  std::int64_t start_occlusion = 0, final_occlusion = 0;  // summed over the scenes [px]
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    start_occlusion += env.reset(seed, reset).info.occlusion.total_pixels;
    const EpisodeRecord episode = run(env, gradient_agent, seed, reset, 50);
    final_occlusion += episode.final_occlusion_px;
    gradient_successes += episode.success();
    gradient_steps += episode.countedSteps();
    const EpisodeRecord random = run(env, random_agent, seed, reset, 50);
    random_successes += random.success();
    random_steps += random.countedSteps();
  }
  std::cout << "[agents] 10 scenes: gradient " << gradient_successes << " successes, "
            << gradient_steps / 10.0 << " steps on average; random " << random_successes
            << " successes, " << random_steps / 10.0 << "\n";
  // A fixed-length step can overshoot or stall where L_s has a local minimum, so not every
  // episode succeeds; together they must.
  EXPECT_LT(final_occlusion, start_occlusion / 4);
  EXPECT_GE(gradient_successes, 7);
  EXPECT_LT(gradient_steps, random_steps);
}

TEST(AgentTest, RunnerIsConsistent) {
  EnvironmentOptions options = smallOptions();
  options.max_steps = 30;
  Environment env(options);
  RandomAgent agent(0);
  for (std::uint64_t seed = 0; seed < 5; ++seed) {
    const EpisodeRecord episode = run(env, agent, seed, {}, 20);
    ASSERT_EQ(episode.path.size(), static_cast<std::size_t>(episode.steps) + 1);
    EXPECT_LE(episode.steps, 20);
    EXPECT_GE(episode.steps, 1);
    EXPECT_TRUE(episode.completed()) << episode.message;
    EXPECT_EQ(episode.success(), episode.final_occlusion_px == 0);
    EXPECT_EQ(episode.success(), episode.steps < 20);
    EXPECT_EQ(episode.final_occlusion_px, env.info().occlusion.total_pixels);
    EXPECT_EQ(env.info().step_index, episode.steps);
    EXPECT_GT(episode.wall_time_s, 0.0);
    EXPECT_DOUBLE_EQ(episode.path.back().azimuth_rad, env.info().pose.azimuth_rad);
    for (int t = 1; t <= episode.steps; ++t) {
      const double moved =
          std::hypot(episode.path[t].azimuth_rad - episode.path[t - 1].azimuth_rad,
                     episode.path[t].elevation_rad - episode.path[t - 1].elevation_rad);
      EXPECT_NEAR(moved, options.step_size_rad, 1e-9);  // far from the clamp and the wrap
    }
    // The same seed gives the same episode.
    const EpisodeRecord again = run(env, agent, seed, {}, 20);
    ASSERT_EQ(again.path.size(), episode.path.size());
    for (std::size_t t = 0; t < episode.path.size(); ++t) {
      EXPECT_EQ(again.path[t].azimuth_rad, episode.path[t].azimuth_rad);
      EXPECT_EQ(again.path[t].elevation_rad, episode.path[t].elevation_rad);
    }
  }
  // The environment's own truncation ends the episode before the runner's limit.
  options.max_steps = 3;
  Environment short_env(options);
  const EpisodeRecord truncated = run(short_env, agent, 1, {}, 50);
  EXPECT_LE(truncated.steps, 3);
  EXPECT_TRUE(truncated.success() || truncated.end == EpisodeEnd::kTruncated);
  EXPECT_THROW(run(short_env, agent, 1, {}, -1), InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
