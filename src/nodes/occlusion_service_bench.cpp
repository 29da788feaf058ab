// occlusion_service_bench: what the ROS service adds to a step. Waits for the simulator's reset
// and step services (~timeout, default 60 s), times `steps` steps through them (the
// EnvironmentClient every agent node uses: persistent connections) and the same steps on an
// in-process Environment built from the simulator's own parameters, then prints both medians and
// the difference. Exits 1, saying why, when it cannot measure. Private parameters:
// serviceBenchOptionTable() (ros/service_probe_options.hpp; doc/PARAMETERS.md).
#include <ros/ros.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "occlusion_env/common/statistics.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/ros/environment_client.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"
#include "occlusion_env/ros/service_probe_options.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using occlusion_env::median;
using occlusion_env::percentile;

struct StepTiming {
  double milliseconds = 0.0;
  bool episode_over = false;
};

// The i-th action of the fixed sequence both sides run: mostly sideways, with a slow vertical wave.
occlusion_env::Action actionAt(int i) {
  return {1.0, 0.5 * std::sin(0.1 * i)};
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

int run(ros::NodeHandle& private_node, ros::NodeHandle& node) {
  occlusion_env::warnAboutUnknownParameters(private_node, occlusion_env::serviceBenchOptionTable());
  occlusion_env::ServiceBenchOptions bench;
  occlusion_env::readParameters(private_node, occlusion_env::serviceBenchOptionTable(), bench);
  const int steps = bench.steps;
  const int seed = bench.seed;

  // Every service it uses must be up before the first call: the simulator advertises them one
  // after the other, after its start-up reset.
  occlusion_env::EnvironmentClient client(node, {bench.timeout_s, /*reset_attempts=*/1});
  client.connect();
  const occlusion_env::SimulatorOptions options =
      occlusion_env::readSimulatorOptions(ros::NodeHandle(bench.simulator));

  // In-process: the same options, seed and action sequence.
  occlusion_env::Environment environment(options.environment);
  const auto timed_steps = [&](occlusion_env::EnvironmentInterface& target) {
    return timeSteps(
        steps, [&] { target.reset(seed); },
        [&](int i) {
          const Clock::time_point start = Clock::now();
          const occlusion_env::StepResult result = target.step(actionAt(i));
          const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
          return StepTiming{ms, result.terminated || result.truncated};
        });
  };
  const std::vector<double> local = timed_steps(environment);
  const std::vector<double> remote = timed_steps(client);

  const double local_median = median(local);
  const double remote_median = median(remote);
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

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "occlusion_service_bench");
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(occlusion_env::names::kNamespace);
  try {
    return run(private_node, node);
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("occlusion_service_bench: " << error.what());
    return 1;
  }
}
