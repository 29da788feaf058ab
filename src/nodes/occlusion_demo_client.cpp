// occlusion_demo_client: resets a few seeded scenes through /occlusion/reset, prints each scene's
// objects and occlusion figures, then takes a few steps and prints the rewards.
// Private parameters: ~seeds (list of int, default [1, 2, 3]), ~steps (int, default 5).
#include <ros/ros.h>

#include <cstdio>
#include <vector>

#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/ros/names.hpp"

namespace {

void printFigures(const occlusion_env::CameraObservation& observation) {
  std::printf("  view: azimuth %+.3f rad, elevation %+.3f rad, %ux%u px\n", observation.azimuth,
              observation.elevation, observation.rgb.width, observation.rgb.height);
  for (std::size_t k = 0; k < observation.object_ids.size(); ++k) {
    std::printf("  object %zu: %s (%s)\n", k, observation.object_ids[k].c_str(),
                observation.object_categories[k].c_str());
  }
  const occlusion_env::OcclusionFigures& figures = observation.occlusion;
  std::printf("  occlusion L = %ld px, occluded area %ld px, union %ld px\n",
              static_cast<long>(figures.total_pixels),
              static_cast<long>(figures.occluded_area_pixels),
              static_cast<long>(figures.union_pixels));
  for (const occlusion_env::OcclusionPair& pair : figures.pairs) {
    std::printf("    pair (%d, %d): %ld px\n", pair.first, pair.second,
                static_cast<long>(pair.pixels));
  }
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "occlusion_demo_client");
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(occlusion_env::names::kNamespace);
  std::vector<int> seeds = {1, 2, 3};
  private_node.param("seeds", seeds, seeds);
  const int num_steps = private_node.param("steps", 5);

  ros::ServiceClient reset_client =
      node.serviceClient<occlusion_env::Reset>(occlusion_env::names::kResetService);
  ros::ServiceClient step_client =
      node.serviceClient<occlusion_env::Step>(occlusion_env::names::kStepService);
  if (!reset_client.waitForExistence(ros::Duration(60.0)) ||
      !step_client.waitForExistence(ros::Duration(5.0))) {
    ROS_FATAL_STREAM("no simulator: " << reset_client.getService() << " did not appear in 60 s");
    return 1;
  }

  for (const int seed : seeds) {
    occlusion_env::Reset reset;
    reset.request.seed = static_cast<std::uint64_t>(seed);
    if (!reset_client.call(reset)) {
      ROS_ERROR_STREAM("the reset service call failed (seed " << seed << ")");
      return 1;
    }
    std::printf("== scene seed %d ==\n", seed);
    if (reset.response.status.code != occlusion_env::Status::OK) {
      std::printf("  reset refused: %s\n", reset.response.status.message.c_str());
      continue;
    }
    printFigures(reset.response.observation);
    // A few steps to the left: the reward says whether the objects come apart.
    for (int t = 0; t < num_steps; ++t) {
      occlusion_env::Step step;
      step.request.action.d_azimuth = 1.0;
      if (!step_client.call(step)) {
        ROS_ERROR("the step service call failed");
        return 1;
      }
      if (step.response.status.code != occlusion_env::Status::OK) {
        std::printf("  step refused: %s\n", step.response.status.message.c_str());
        break;
      }
      std::printf("  step %d: L = %ld px, reward %+.4f%s%s\n", t + 1,
                  static_cast<long>(step.response.occlusion_pixels), step.response.reward,
                  step.response.terminated ? ", terminated" : "",
                  step.response.truncated ? ", truncated" : "");
      if (step.response.terminated || step.response.truncated) break;
    }
  }
  std::fflush(stdout);
  return 0;
}
