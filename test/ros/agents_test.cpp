// The random_agent and gradient_agent nodes against the simulator (test/ros/agents.test): each
// reports every episode in its CSV, and each episode equals the same agent's episode in process.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <string>

#include "agent_test_support.hpp"
#include "occlusion_env/ros/agent_node.hpp"

namespace occlusion_env {
namespace {

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
  const std::vector<EpisodeRecord> episodes =
      testing_support::waitForRows(csv, want.episodes, 90.0);
  ASSERT_EQ(episodes.size(), static_cast<std::size_t>(want.episodes)) << csv;
  for (const EpisodeRecord& episode : episodes) {
    SCOPED_TRACE(agent + " seed " + std::to_string(episode.scene_seed));
    EXPECT_EQ(episode.agent, agent);
    EXPECT_TRUE(episode.completed()) << episode.message;
    EXPECT_TRUE(episode.message.empty());
    EXPECT_LE(episode.steps, episode.max_steps);
    ASSERT_EQ(episode.path.size(), static_cast<std::size_t>(episode.steps) + 1);
    EXPECT_NEAR(episode.path.front().azimuth_rad, want.start_azimuth_rad, 1e-9);
    // Success means no occlusion left (threshold 0 px); otherwise the step limit ended it.
    if (episode.success()) {
      EXPECT_EQ(episode.final_occlusion_px, 0);
    } else {
      EXPECT_GT(episode.final_occlusion_px, 0);
      EXPECT_EQ(episode.steps, episode.max_steps);
    }
    testing_support::expectSameAsInProcess(episode, want.start_azimuth_rad);
  }
}

TEST(AgentNodes, RandomAgentRunsEveryEpisodeAsInProcess) {
  checkAgent("random");
}

// The test-only agent, registered only in test_agent_node's own registry, runs through ROS like
// any other: the registry is the one place an agent is added.
TEST(AgentNodes, TestOnlyAgentRunsThroughRosAsInProcess) {
  checkAgent("test_circling");
}

TEST(AgentNodes, GradientAgentRunsEveryEpisodeAsInProcess) {
  checkAgent("gradient");
  // The gradient agent should solve most of these scenes within 30 steps (4/4 in process).
  std::string csv;
  ros::NodeHandle("~").getParam("gradient_csv", csv);
  int successes = 0;
  for (const EpisodeRecord& episode : testing_support::readAgentCsv(csv))
    successes += episode.success();
  EXPECT_GE(successes, 3);
}

// ParameterError naming `name` when the parameters of `node` are read.
void expectParameterError(const ros::NodeHandle& node, const std::string& name) {
  try {
    readAgentNodeOptions(node, testing_support::testRegistry());
    ADD_FAILURE() << "accepted a bad " << name;
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
  }
}

TEST(AgentNodes, ParametersAreValidatedWithTheirNames) {
  ros::NodeHandle node("/agent_parameter_test");
  const AgentRegistry& registry = testing_support::testRegistry();
  expectParameterError(node, "agent");  // not set
  node.setParam("agent", std::string("ppo"));
  expectParameterError(node, "agent");  // not registered
  node.setParam("agent", std::string("gradient"));
  node.setParam("seed", 5);
  node.setParam("episodes", 3);
  AgentNodeOptions options = readAgentNodeOptions(node, registry);
  EXPECT_EQ(options.seeds, (std::vector<std::uint64_t>{5, 6, 7}));
  EXPECT_EQ(options.agent, "gradient");
  EXPECT_FALSE(options.reset.start_azimuth_rad.has_value());

  std::string scene_set;
  ASSERT_TRUE(ros::NodeHandle("~").getParam("scene_set_file", scene_set));
  node.setParam("scene_set", scene_set);
  options = readAgentNodeOptions(node, registry);
  EXPECT_EQ(options.scene_set_name, "test_embedded");
  EXPECT_EQ(options.seeds.size(), 50u);
  EXPECT_EQ(options.seeds.front(), 1000000u);
  EXPECT_TRUE(options.reset.start_azimuth_rad.has_value());
  node.setParam("seeds", std::vector<int>{9, 8});  // a list wins over the scene set
  EXPECT_EQ(readAgentNodeOptions(node, registry).seeds, (std::vector<std::uint64_t>{9, 8}));

  node.setParam("max_steps", 0);
  expectParameterError(node, "max_steps");
  node.setParam("max_steps", 10);
  node.setParam("seeds", std::string("1, 2"));
  expectParameterError(node, "seeds");
  node.setParam("seeds", std::vector<int>{1, -2});
  expectParameterError(node, "seeds");
  node.deleteParam("seeds");
  node.setParam("scene_set", std::string("/nonexistent/set.yaml"));
  expectParameterError(node, "scene_set");
  node.deleteParam("scene_set");
  node.setParam("step_rate", -1.0);
  expectParameterError(node, "step_rate");
  node.setParam("step_rate", 0.0);
  node.setParam("episodes", 0);
  expectParameterError(node, "episodes");
  EXPECT_THROW(readAgentNodeOptions(ros::NodeHandle("/agent_parameter_test_empty"), registry),
               ParameterError);

  node.setParam("episodes", 2);
  node.setParam("max_step", 10);
  EXPECT_EQ(unknownParameters(node, agentNodeOptionTable()), std::vector<std::string>{"max_step"});
  ros::param::del("/agent_parameter_test");
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "agents_test");
  ros::NodeHandle node;  // keeps the node up while the tests read parameters
  return RUN_ALL_TESTS();
}
