// What an agent node does, read from its private parameters in one place.
#pragma once

#include <ros/node_handle.h>

#include <cstdint>
#include <string>
#include <vector>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

struct AgentNodeOptions {
  std::string agent;                 // a registry name (~agent)
  std::string model_path;            // ~model: "" = the agent's shipped model, if it needs one
  std::vector<std::uint64_t> seeds;  // one episode per scene seed, in this order
  std::string scene_set_path;        // ~scene_set: a scene-set YAML file when ~seeds is empty
  std::int64_t first_seed = 0;       // ~seed: without seeds and scene set, seeds seed, seed + 1..
  int episodes = 10;                 // ~episodes: ... this many of them
  int max_steps = 50;                // steps per episode at most (the simulator may end it earlier)
  ResetOptions reset;                // preset, categories and start pose of every reset
  std::string scene_set_name = "ros";  // the records' scene_set
  std::string csv_path;                // "" = no CSV; a relative ~csv is under ROS_HOME
  double service_timeout_s = 60.0;     // wait for the simulator's services [s]; 0 = forever
  double step_rate_hz = 0.0;           // steps per second at most (to watch in rviz); 0 = no limit
};

/// The agent node's parameters (names relative to its private namespace).
const OptionTable<AgentNodeOptions>& agentNodeOptionTable();

/// Reads the node's options from `private_node`. ~agent must name an agent of `registry`. The
/// seeds come from ~seeds (a list), else from ~scene_set (a scene-set YAML file, which also fixes
/// preset, categories and start pose), else from ~seed and ~episodes (seeds seed, seed + 1, ...).
/// Throws ParameterError naming the parameter on a missing, wrong-typed or bad value.
AgentNodeOptions readAgentNodeOptions(const ros::NodeHandle& private_node,
                                      const AgentRegistry& registry);

}  // namespace occlusion_env
