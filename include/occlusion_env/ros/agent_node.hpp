// Runs any agent of a registry as a ROS node on the simulator's services (or anything that offers
// them: the camera bridge of a real camera), through the EnvironmentClient and the core's episode
// runner. When the simulator goes away mid-episode the episode is reported as cut short, the node
// waits for the services to come back and carries on with the next seed.
#pragma once

#include <ros/ros.h>

#include <memory>
#include <vector>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/ros/agent_node_options.hpp"
#include "occlusion_env/ros/environment_client.hpp"
#include "occlusion_env/ros/episode_reporter.hpp"

namespace occlusion_env {

class AgentNode {
 public:
  /// `node` resolves the simulator's services (occlusion/reset, ...); `private_node` advertises
  /// ~episodes. Throws ParameterError for an unwritable CSV path.
  AgentNode(const AgentNodeOptions& options, const AgentRegistry& registry, ros::NodeHandle node,
            ros::NodeHandle private_node);

  /// Connects, makes the agent, runs one episode per seed. Returns the episodes that ran to an
  /// outcome of the agent. Throws EnvironmentUnavailableError when the services are not there
  /// within the timeout, and InvalidStateError when the agent needs what the environment does not
  /// offer (the gradient of a real camera).
  int run();

  const std::vector<EpisodeRecord>& records() const { return reporter_.records(); }

 private:
  AgentNodeOptions options_;
  const AgentRegistry& registry_;
  ros::NodeHandle private_node_;
  EnvironmentClient environment_;
  EpisodeReporter reporter_;
};

/// The whole main() of an agent node: ros::init as `agent_node` (the launch file names it
/// `<agent>_agent`), options from the private parameters, run, exit code (0 when every requested
/// episode was attempted, 1 on a fatal error). `registry` is the agents the node can run.
int runAgentNodeMain(int argc, char** argv, const AgentRegistry& registry);

}  // namespace occlusion_env
