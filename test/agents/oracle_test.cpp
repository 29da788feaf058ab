// The oracle: its agent realises the bound it computes, a finer lattice never needs more steps,
// and no agent beats it on the scenes checked.
#include "occlusion_env/agents/oracle.hpp"

#include <gtest/gtest.h>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

EnvironmentOptions smallOptions() {
  EnvironmentOptions options;
  options.width = options.height = 96;
  return options;
}

TEST(OracleTest, TheOracleAgentRealisesTheBoundAndNoAgentBeatsIt) {
  Environment environment(smallOptions());
  const AgentRegistry registry = coreAgents();
  EpisodeRunOptions run;
  run.max_steps = 50;
  for (std::uint64_t seed = 0; seed < 6; ++seed) {
    EpisodeRequest request{"oracle", "unit", seed, {}};
    request.reset.start_azimuth_rad = 0.0;
    const StepResult start = environment.reset(seed, request.reset);
    OcclusionOracle oracle(environment);
    const OracleAnswer bound = oracle.query(start.info.pose);
    ASSERT_GT(bound.steps, 0) << "scenes start occluded";
    ASSERT_EQ(bound.path.size(), static_cast<std::size_t>(bound.steps));
    for (const Action& move : bound.path) {
      EXPECT_NEAR(std::hypot(move.d_azimuth_rad, move.d_elevation_rad), 0.05, 1e-12);
    }
    // The registered oracle agent uses a quarter-step lattice: never more steps than half a step.
    OracleOptions finer_options;
    finer_options.lattice_spacing_steps = 0.25;
    OcclusionOracle finer(environment, finer_options);
    const OracleAnswer finer_bound = finer.query(start.info.pose);
    EXPECT_LE(finer_bound.steps, bound.steps) << "seed " << seed;

    const auto oracle_agent = registry.make("oracle", {environment, ""});
    const EpisodeRecord record = runEpisode(environment, *oracle_agent, request, run);
    EXPECT_TRUE(record.success()) << "seed " << seed << ": " << record.message;
    EXPECT_EQ(record.steps, finer_bound.steps)
        << "seed " << seed << ": the agent realises its bound";
    for (const std::string& name : registry.competitors()) {
      request.agent = name;
      const auto agent = registry.make(name, {environment, ""});
      const EpisodeRecord other = runEpisode(environment, *agent, request, run);
      EXPECT_GE(other.countedSteps(), record.steps) << name << " beat the oracle on seed " << seed;
    }
  }
}

TEST(OracleTest, UnoccludedPoseNeedsNoStepAndOptionsAreChecked) {
  Environment environment(smallOptions());
  ResetOptions reset;
  reset.start_azimuth_rad = 0.0;
  environment.reset(2, reset);
  OcclusionOracle oracle(environment);
  // Far to the side the objects no longer overlap: 0 steps, no path, the target is the pose.
  const SphericalPose side{M_PI / 2, 0.0};
  const OracleAnswer answer = oracle.query(side);
  if (answer.steps == 0) {
    EXPECT_TRUE(answer.path.empty());
    EXPECT_TRUE(std::isnan(answer.firstDirectionRad()));
  }
  OracleOptions bad;
  bad.lattice_spacing_steps = 0.0;
  EXPECT_THROW(OcclusionOracle(environment, bad), InvalidArgumentError);
  bad = {};
  bad.circle_directions = 2;
  EXPECT_THROW(OcclusionOracle(environment, bad), InvalidArgumentError);
  Environment fresh(smallOptions());
  OcclusionOracle no_episode(fresh);
  EXPECT_THROW(no_episode.query({0.0, 0.0}), InvalidStateError);
}

}  // namespace
}  // namespace occlusion_env
