#include "occlusion_env/agents/agent_registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "agents/test_agent.hpp"
#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

// An environment that offers nothing but images: what a real camera gives.
class CameraOnlyEnvironment : public EnvironmentInterface {
 public:
  CameraOnlyEnvironment() {
    observation_.rgb = cv::Mat(64, 64, CV_8UC3, cv::Scalar(10, 20, 30));
    observation_.depth = cv::Mat(64, 64, CV_32FC1, cv::Scalar(2.0f));
  }
  StepResult reset(std::uint64_t, const ResetOptions&) override { return result(); }
  StepResult step(const Action& action) override {
    pose_.azimuth_rad += 0.05 * action.d_azimuth_rad;
    return result();
  }
  std::string describe() const override { return "a camera"; }

 private:
  StepResult result() {
    StepResult result;
    result.observation = &observation_;
    result.info.pose = pose_;
    result.info.occlusion.total_pixels = 7;
    return result;
  }
  Observation observation_;
  SphericalPose pose_;
};

TEST(AgentRegistryTest, CoreAgentsAreListedWithWhatTheyNeed) {
  const AgentRegistry registry = coreAgents();
  ASSERT_GE(registry.entries().size(), 2u);
  for (const AgentEntry& entry : registry.entries()) {
    EXPECT_FALSE(entry.summary.empty()) << entry.name;
    EXPECT_TRUE(entry.make) << entry.name;
  }
  // References (the oracle) are listed but do not compete.
  for (const std::string& name : registry.competitors()) EXPECT_TRUE(registry.at(name).competes);
  EXPECT_LT(registry.competitors().size(), registry.names().size());
  EXPECT_EQ(registry.find("test_circling"), nullptr);
  try {
    registry.at("no_such_agent");
    ADD_FAILURE() << "an unknown agent was found";
  } catch (const InvalidArgumentError& error) {
    // The message lists the known agents.
    for (const std::string& name : registry.names()) {
      EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
    }
  }
}

TEST(AgentRegistryTest, RefusesBadEntries) {
  AgentRegistry registry;
  AgentEntry entry = testing_support::circlingAgentEntry();
  registry.add(entry);
  EXPECT_THROW(registry.add(entry), InvalidArgumentError);  // twice
  entry.name = "Has Space";
  EXPECT_THROW(registry.add(entry), InvalidArgumentError);
  entry.name = "a,b";
  EXPECT_THROW(registry.add(entry), InvalidArgumentError);
  entry.name = "no_factory";
  entry.make = nullptr;
  EXPECT_THROW(registry.add(entry), InvalidArgumentError);
}

TEST(AgentRegistryTest, NeedsAreCheckedAgainstTheEnvironment) {
  const AgentRegistry registry = coreAgents();
  CameraOnlyEnvironment camera;
  for (const AgentEntry& entry : registry.entries()) {
    const std::string unmet = registry.unmetNeed(entry.name, camera);
    if (entry.needs.occlusion_gradient || entry.needs.simulation) {
      EXPECT_FALSE(unmet.empty()) << entry.name;
      EXPECT_THROW(registry.make(entry.name, {camera, ""}), InvalidStateError) << entry.name;
    } else {
      EXPECT_EQ(unmet, "") << entry.name;
      EXPECT_NE(registry.make(entry.name, {camera, ""}), nullptr);
    }
  }
  EXPECT_THROW(camera.occlusionGradient(), InvalidStateError);
}

TEST(AgentRegistryTest, ATestOnlyAgentRunsInProcessThroughTheRegistry) {
  AgentRegistry registry = coreAgents();
  registry.add(testing_support::circlingAgentEntry());
  EnvironmentOptions options;
  options.width = options.height = 96;
  Environment environment(options);
  const std::unique_ptr<Agent> agent = registry.make("test_circling", {environment, ""});
  EpisodeRequest request;
  request.agent = "test_circling";
  request.scene_set = "unit";
  request.seed = 3;
  request.reset.start_azimuth_rad = 0.0;
  EpisodeRunOptions run;
  run.max_steps = 6;
  const EpisodeRecord record = runEpisode(environment, *agent, request, run);
  EXPECT_TRUE(record.completed()) << record.message;
  ASSERT_EQ(record.path.size(), static_cast<std::size_t>(record.steps) + 1);
  for (int t = 1; t <= record.steps; ++t) {
    EXPECT_NEAR(record.path[t].azimuth_rad - record.path[t - 1].azimuth_rad, 0.05, 1e-12);
    EXPECT_EQ(record.path[t].elevation_rad, 0.0);
  }
}

}  // namespace
}  // namespace occlusion_env
