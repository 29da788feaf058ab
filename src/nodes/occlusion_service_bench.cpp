// occlusion_service_bench: what the ROS service adds to a step. Times `steps` steps through the
// running simulator's step service (persistent connection) and the same steps on an in-process
// Environment built from the simulator's own parameters, then prints both medians and the
// difference. Private parameters: ~steps (default 500), ~seed (default 1), ~simulator (the
// simulator node's name, default /occlusion_sim, whose parameters give the options).
#include <ros/ros.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/core/environment.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct StepTiming {
  double milliseconds = 0.0;
  bool episode_over = false;
};

// The i-th action of the fixed sequence both sides run: mostly sideways, with a slow vertical wave.
occlusion_env::Action actionAt(int i) {
  return {1.0, 0.5 * std::sin(0.1 * i)};
}

double percentile(std::vector<double> values, double fraction) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(fraction * (values.size() - 1))];
}

// Runs `steps` timed steps; `reset` starts a new episode (untimed) whenever one ends.
std::vector<double> timeSteps(int steps, const std::function<void()>& reset,
                              const std::function<StepTiming(int)>& step) {
  std::vector<double> milliseconds;
  milliseconds.reserve(steps);
  reset();
  for (int i = 0; i < steps; ++i) {
    const StepTiming timing = step(i);
    milliseconds.push_back(timing.milliseconds);
    if (timing.episode_over) reset();
  }
  return milliseconds;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "occlusion_service_bench");
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(occlusion_env::names::kNamespace);
  const int steps = private_node.param("steps", 500);
  const int seed = private_node.param("seed", 1);
  const std::string simulator = private_node.param<std::string>(
      "simulator", std::string("/") + occlusion_env::names::kSimulatorNode);

  ros::ServiceClient reset_client =
      node.serviceClient<occlusion_env::Reset>(occlusion_env::names::kResetService, true);
  ros::ServiceClient step_client =
      node.serviceClient<occlusion_env::Step>(occlusion_env::names::kStepService, true);
  if (!reset_client.waitForExistence(ros::Duration(60.0))) {
    ROS_FATAL_STREAM("no simulator: " << reset_client.getService() << " did not appear in 60 s");
    return 1;
  }
  const occlusion_env::SimulatorOptions options =
      occlusion_env::readSimulatorOptions(ros::NodeHandle(simulator));

  // In-process: the same options, seed and action sequence.
  occlusion_env::Environment environment(options.environment);
  const std::vector<double> local = timeSteps(
      steps, [&] { environment.reset(seed); },
      [&](int i) {
        const Clock::time_point start = Clock::now();
        const occlusion_env::StepResult result = environment.step(actionAt(i));
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        return StepTiming{ms, result.terminated || result.truncated};
      });

  // Over the service.
  bool failed = false;
  const std::vector<double> remote = timeSteps(
      steps,
      [&] {
        occlusion_env::Reset reset;
        reset.request.seed = seed;
        failed |= !reset_client.call(reset) || reset.response.status.code != 0;
      },
      [&](int i) {
        occlusion_env::Step step;
        const occlusion_env::Action action = actionAt(i);
        step.request.action.d_azimuth = action.d_azimuth_rad;
        step.request.action.d_elevation = action.d_elevation_rad;
        const Clock::time_point start = Clock::now();
        failed |= !step_client.call(step) || step.response.status.code != 0;
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        return StepTiming{ms, step.response.terminated || step.response.truncated};
      });
  if (failed) {
    ROS_FATAL("a reset or step over the service failed");
    return 1;
  }

  const double local_median = percentile(local, 0.5);
  const double remote_median = percentile(remote, 0.5);
  std::printf("%d steps at %dx%d, seed %d\n", steps, options.environment.width,
              options.environment.height, seed);
  std::printf("in-process step:    median %.3f ms, p90 %.3f ms\n", local_median,
              percentile(local, 0.9));
  std::printf("service round trip: median %.3f ms, p90 %.3f ms\n", remote_median,
              percentile(remote, 0.9));
  std::printf("ROS overhead:       median %.3f ms per step (goal <= 1.5 ms)\n",
              remote_median - local_median);
  std::fflush(stdout);
  return 0;
}
