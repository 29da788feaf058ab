#include "occlusion_env/ros/agent_node.hpp"

#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {

AgentNode::AgentNode(const AgentNodeOptions& options, const AgentRegistry& registry,
                     ros::NodeHandle node, ros::NodeHandle private_node)
    : options_(options),
      registry_(registry),
      private_node_(std::move(private_node)),
      environment_(std::move(node), {options.service_timeout_s, /*reset_attempts=*/3}),
      reporter_(private_node_, options.csv_path) {}

int AgentNode::run() {
  environment_.connect();
  const std::unique_ptr<Agent> agent =
      registry_.make(options_.agent, {environment_, options_.model_path});
  const int total = static_cast<int>(options_.seeds.size());
  ROS_INFO_STREAM(
      options_.agent << " agent on " << environment_.describe() << ": " << total
                     << " episodes, at most " << options_.max_steps << " steps each"
                     << (options_.csv_path.empty() ? std::string() : ", CSV " + options_.csv_path));
  EpisodeRunOptions run_options;
  run_options.max_steps = options_.max_steps;
  run_options.step_rate_hz = options_.step_rate_hz;
  run_options.keep_running = [] { return ros::ok(); };
  int completed = 0;
  for (int index = 0; index < total && ros::ok(); ++index) {
    EpisodeRequest request;
    request.agent = options_.agent;
    request.scene_set = options_.scene_set_name;
    request.seed = options_.seeds[index];
    request.reset = options_.reset;
    const EpisodeRecord record = runEpisode(environment_, *agent, request, run_options);
    reporter_.report(record, index, total);
    if (record.completed()) ++completed;
    if (record.end == EpisodeEnd::kStopped) break;
    if (record.end == EpisodeEnd::kEnvironmentLost && ros::ok() && index + 1 < total) {
      ROS_WARN_STREAM("waiting for the environment to return, then going on with episode "
                      << index + 2);
      environment_.connect();
    }
  }
  reporter_.finish(options_.agent);
  return completed;
}

int runAgentNodeMain(int argc, char** argv, const AgentRegistry& registry) {
  ros::init(argc, argv, "agent_node");
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(names::kNamespace);
  warnAboutUnknownParameters(private_node, agentNodeOptionTable());
  try {
    AgentNode agent_node(readAgentNodeOptions(private_node, registry), registry, node,
                         private_node);
    agent_node.run();
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM(ros::this_node::getName() << ": " << error.what());
    return 1;
  }
  return 0;
}

}  // namespace occlusion_env
