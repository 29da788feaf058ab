// The camera bridge end to end (test/ros/camera_bridge.test): the predicted_escape agent node
// reaches unoccluded views through the bridge where it does so against the simulator directly,
// and the bridge's estimate agrees with the stand-in camera's truth where the episodes end.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cmath>
#include <map>
#include <mutex>
#include <string>

#include "agent_test_support.hpp"
#include "occlusion_env/GroundTruthView.h"

namespace occlusion_env {
namespace {

std::mutex truth_mutex;
std::map<std::uint64_t, GroundTruthView> last_view_of_scene;  // the latest view of each seed

void onGroundTruth(const GroundTruthView::ConstPtr& view) {
  std::lock_guard<std::mutex> lock(truth_mutex);
  last_view_of_scene[view->scene_seed] = *view;
}

TEST(CameraBridge, LearnedAgentReachesUnoccludedViewsThroughTheBridge) {
  ros::NodeHandle private_node("~");
  std::string direct_csv, bridge_csv;
  int episodes = 0;
  ASSERT_TRUE(private_node.getParam("direct_csv", direct_csv));
  ASSERT_TRUE(private_node.getParam("bridge_csv", bridge_csv));
  ASSERT_TRUE(private_node.getParam("episodes", episodes));
  const auto direct = testing_support::waitForRows(direct_csv, episodes, 200.0);
  const auto bridge = testing_support::waitForRows(bridge_csv, episodes, 200.0);
  ASSERT_EQ(direct.size(), static_cast<std::size_t>(episodes)) << direct_csv;
  ASSERT_EQ(bridge.size(), static_cast<std::size_t>(episodes)) << bridge_csv;

  int direct_successes = 0, bridge_reached = 0, bridge_reached_where_direct = 0, agreements = 0;
  std::lock_guard<std::mutex> lock(truth_mutex);
  for (int i = 0; i < episodes; ++i) {
    const EpisodeRecord& d = direct[i];
    const EpisodeRecord& b = bridge[i];
    SCOPED_TRACE("seed " + std::to_string(b.scene_seed));
    ASSERT_EQ(d.scene_seed, b.scene_seed);
    EXPECT_TRUE(b.completed()) << b.message;
    const auto truth = last_view_of_scene.find(b.scene_seed);
    ASSERT_NE(truth, last_view_of_scene.end()) << "no ground truth seen for this scene";
    // The truth's last view is where the bridge's episode ended (its measured pose).
    ASSERT_FALSE(b.path.empty());
    EXPECT_NEAR(truth->second.azimuth, b.path.back().azimuth_rad, 1e-6);
    EXPECT_NEAR(truth->second.elevation, b.path.back().elevation_rad, 1e-6);
    const bool truly_clear = truth->second.unoccluded;
    direct_successes += d.success();
    bridge_reached += truly_clear;
    bridge_reached_where_direct += d.success() && truly_clear;
    agreements += b.success() == truly_clear;
    const std::string outcome = std::string("direct ") + (d.success() ? "clear" : "occluded") +
                                " after " + std::to_string(d.steps) + " steps; bridge says " +
                                (b.success() ? "clear" : "occluded") + " after " +
                                std::to_string(b.steps) + " steps, truth " +
                                std::to_string(truth->second.occlusion.total_pixels) + " px";
    RecordProperty("seed_" + std::to_string(b.scene_seed), outcome);
    std::printf("seed %llu: %s\n", static_cast<unsigned long long>(b.scene_seed), outcome.c_str());
  }
  std::printf(
      "through the bridge: truly unoccluded at the end in %d of %d scenes (%d of the %d the "
      "agent clears directly); the bridge's verdict agrees with the truth in %d of %d\n",
      bridge_reached, episodes, bridge_reached_where_direct, direct_successes, agreements,
      episodes);
  // In the test's XML report (test_results/occlusion_env/rosunit-camera_bridge_test.xml).
  RecordProperty("direct_successes", direct_successes);
  RecordProperty("bridge_truly_unoccluded", bridge_reached);
  RecordProperty("bridge_truly_unoccluded_where_direct_succeeds", bridge_reached_where_direct);
  RecordProperty("bridge_verdict_agrees_with_truth", agreements);
  RecordProperty("episodes", episodes);
  EXPECT_GE(bridge_reached_where_direct * 10, direct_successes * 8);
  EXPECT_GE(agreements * 10, episodes * 8);
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "camera_bridge_test");
  ros::NodeHandle node;
  const ros::Subscriber truth =
      node.subscribe("/bridge/occlusion/ground_truth/view", 1000, &occlusion_env::onGroundTruth);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
