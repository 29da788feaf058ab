// The random_agent and gradient_agent nodes against the simulator (test/ros/agents.test): each
// reports every episode in its CSV, and each episode equals the same agent's episode in process.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <string>

#include "agent_test_support.hpp"

namespace occlusion_env {
namespace {

using testing_support::CsvEpisode;

struct Expected {
  int episodes = 0;
  double start_azimuth_rad = 0.0;
};

Expected expected() {
  ros::NodeHandle private_node("~");
  Expected value;
  private_node.getParam("episodes", value.episodes);
  private_node.getParam("start_azimuth", value.start_azimuth_rad);
  return value;
}

void checkAgent(const std::string& agent) {
  std::string csv;
  ASSERT_TRUE(ros::NodeHandle("~").getParam(agent + "_csv", csv));
  const Expected want = expected();
  ASSERT_GT(want.episodes, 0);
  const std::vector<CsvEpisode> episodes = testing_support::waitForRows(csv, want.episodes, 90.0);
  ASSERT_EQ(episodes.size(), static_cast<std::size_t>(want.episodes)) << csv;
  for (const CsvEpisode& episode : episodes) {
    SCOPED_TRACE(agent + " seed " + std::to_string(episode.seed));
    EXPECT_EQ(episode.agent, agent);
    EXPECT_TRUE(episode.completed) << episode.message;
    EXPECT_TRUE(episode.message.empty());
    EXPECT_LE(episode.steps, episode.max_steps);
    EXPECT_EQ(episode.azimuths.size(), static_cast<std::size_t>(episode.steps) + 1);
    EXPECT_EQ(episode.elevations.size(), episode.azimuths.size());
    ASSERT_FALSE(episode.azimuths.empty());
    EXPECT_NEAR(episode.azimuths.front(), want.start_azimuth_rad, 1e-9);
    // Success means no occlusion left (threshold 0 px); otherwise the step limit ended it.
    if (episode.success) {
      EXPECT_EQ(episode.final_occlusion_px, 0);
    } else {
      EXPECT_GT(episode.final_occlusion_px, 0);
      EXPECT_EQ(episode.steps, episode.max_steps);
    }
    testing_support::expectSameAsInProcess(agent, episode, want.start_azimuth_rad);
  }
}

TEST(AgentNodes, RandomAgentRunsEveryEpisodeAsInProcess) {
  checkAgent("random");
}

TEST(AgentNodes, GradientAgentRunsEveryEpisodeAsInProcess) {
  checkAgent("gradient");
  // The gradient agent should solve most of these scenes within 30 steps (4/4 in process).
  std::string csv;
  ros::NodeHandle("~").getParam("gradient_csv", csv);
  int successes = 0;
  for (const CsvEpisode& episode : testing_support::readAgentCsv(csv)) successes += episode.success;
  EXPECT_GE(successes, 3);
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "agents_test");
  ros::NodeHandle node;  // keeps the node up while the tests read parameters
  return RUN_ALL_TESTS();
}
