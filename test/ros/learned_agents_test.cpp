// The learned agents as nodes (test/ros/learned_agents.test), on simulators without a gradient
// service: each reports every episode, equal to the same agent's episode in process, and the
// simulator indeed offers no gradient.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <string>

#include "agent_test_support.hpp"

namespace occlusion_env {
namespace {

void checkAgent(const std::string& agent) {
  ros::NodeHandle private_node("~");
  std::string csv;
  int episodes = 0;
  double start_azimuth = 0.0;
  ASSERT_TRUE(private_node.getParam(agent + "_csv", csv));
  private_node.getParam("episodes", episodes);
  private_node.getParam("start_azimuth", start_azimuth);
  const std::vector<EpisodeRecord> rows = testing_support::waitForRows(csv, episodes, 90.0);
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(episodes)) << csv;
  for (const EpisodeRecord& row : rows) {
    EXPECT_EQ(row.agent, agent);
    EXPECT_TRUE(row.completed()) << row.message;
    testing_support::expectSameAsInProcess(row, start_azimuth);
  }
}

TEST(LearnedAgentNodes, NoGradientServiceIsOffered) {
  EXPECT_FALSE(ros::service::exists("/predicted_escape/occlusion/get_occlusion_gradient", false));
  EXPECT_TRUE(ros::service::exists("/predicted_escape/occlusion/step", false));
}

TEST(LearnedAgentNodes, PredictedGradientRunsAsInProcess) {
  checkAgent("predicted_gradient");
}

TEST(LearnedAgentNodes, PredictedEscapeRunsAsInProcess) {
  checkAgent("predicted_escape");
}

TEST(LearnedAgentNodes, ShippedPolicyRunsAsInProcess) {
  checkAgent("policy_un");
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "learned_agents_test");
  ros::NodeHandle node;
  return RUN_ALL_TESTS();
}
