// The camera bridge driven in process (env/camera_environment.hpp on env/simulated_camera_rig.hpp,
// what occlusion_agents --through-bridge runs): the learned agent, unchanged, on two held-out
// scenes through the bridge's logic with the shipped network, scored by the simulator's truth.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/simulated_camera_rig.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/occlusion_estimator.hpp"

namespace occlusion_env {
namespace {

TEST(InProcessBridge, TheLearnedAgentRunsThroughTheBridgeScoredByTheSimulatorsTruth) {
  EnvironmentOptions options;
  options.catalog.source = "sweethome3d";
  options.scene.categories = {"chair", "table"};
  Environment simulator(options);
  SimulatedCameraRig rig(simulator, /*millimetre_depth=*/true);
  const AgentRegistry registry = learning::learningAgents();
  const std::string model_path = registry.at("predicted_escape").default_model_path;
  CameraEnvironmentOptions bridge_options;  // the node's defaults (camera_bridge_options_test)
  const auto estimator = learning::makeBridgeEstimator(
      std::make_shared<learning::LoadedModel>(learning::loadModel(model_path)), bridge_options);
  CameraEnvironment bridge(bridge_options, rig, estimator.get());
  std::unique_ptr<Agent> agent = registry.make("predicted_escape", {bridge, ""});

  int truly_clear = 0;
  // test_sweethome3d's first and third scenes: over ROS (camera_bridge.test) the agent ends
  // both truly clear, after 15 and 11 steps.
  for (const std::uint64_t seed : {1001000u, 1001002u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::vector<StepInfo> views;
    EpisodeRunOptions run;
    run.on_result = [&](const StepResult& result) {
      views.push_back(result.info);
      // A camera gives images only: no instances or silhouettes; the estimate, not the truth.
      EXPECT_TRUE(result.observation->instance.empty());
      EXPECT_TRUE(result.observation->amodal_bits.empty());
      EXPECT_EQ(result.info.occlusion_source, OcclusionSource::kEstimated);
    };
    EpisodeRequest request;
    request.agent = "predicted_escape";
    request.seed = seed;
    request.reset.start_azimuth_rad = 0.0;
    const EpisodeRecord record = runEpisode(bridge, *agent, request, run);
    ASSERT_TRUE(record.completed()) << record.message;
    ASSERT_EQ(views.size(), static_cast<std::size_t>(record.steps) + 1);
    // The simulator's camera is where the bridge's episode ended: its truth scores that view.
    EXPECT_NEAR(simulator.info().pose.azimuth_rad, record.path.back().azimuth_rad, 1e-9);
    EXPECT_NEAR(simulator.info().pose.elevation_rad, record.path.back().elevation_rad, 1e-9);
    if (record.success()) {
      // The verdict: the last confirm_views step views estimated clear, never the reset view.
      ASSERT_GE(record.steps, bridge_options.confirm_views);
      for (int back = 0; back < bridge_options.confirm_views; ++back) {
        EXPECT_LE(views[views.size() - 1 - back].occlusion.total_pixels,
                  bridge_options.occlusion_threshold_px);
      }
    } else {
      EXPECT_EQ(record.steps, bridge_options.max_steps);
    }
    truly_clear += simulator.reward().solved(simulator.info().occlusion.total_pixels);
  }
  // A bridge that stopped on a wrong view (a broken crop, depth or estimate) would miss both.
  EXPECT_GE(truly_clear, 1);
}

}  // namespace
}  // namespace occlusion_env
