#include "occlusion_env/ros/agent_node_options.hpp"

#include <cstdlib>
#include <filesystem>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxEpisodes = 1'000'000;

// Relative to ROS_HOME, as ROS puts its own files, whatever the working directory.
std::string underRosHome(const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  const char* ros_home = std::getenv("ROS_HOME");
  const char* home = std::getenv("HOME");
  const fs::path base = ros_home != nullptr && *ros_home != '\0'
                            ? fs::path(ros_home)
                            : fs::path(home != nullptr ? home : ".") / ".ros";
  return (base / path).string();
}

// The seeds, preset, categories and start pose of ~scene_set, unless ~seeds lists the seeds.
void applySceneSet(const ros::NodeHandle& private_node, AgentNodeOptions& options) {
  if (!options.seeds.empty() || options.scene_set_path.empty()) return;
  SceneSet set;
  try {
    set = loadSceneSet(options.scene_set_path);
  } catch (const std::exception& error) {
    throw ParameterError("parameter " + private_node.resolveName("scene_set") + ": " +
                         error.what());
  }
  options.seeds = set.seeds;
  options.scene_set_name = set.name;
  options.reset = resetOptionsFor(set);
  ROS_INFO_STREAM("scene set " << set.name << " (" << set.seeds.size()
                               << " seeds): run the simulator with catalog_source " << set.source
                               << " and num_objects " << set.num_objects << " to get its scenes");
}

}  // namespace

const OptionTable<AgentNodeOptions>& agentNodeOptionTable() {
  using Options = AgentNodeOptions;
  using Reset = ResetOptions;
  const auto reset = [](auto member) {
    return [member](Options & o) -> auto& {
      return o.reset.*member;
    };
  };
  static const auto table =
      OptionTable<Options>()
          .add("agent", &Options::agent,
               OptionSpec("the agent, a registry name (occlusion_agents lists them); required"))
          .add("model", &Options::model_path,
               OptionSpec("the agent's model file; \"\" = its shipped model, if it needs one"))
          .add("seeds", &Options::seeds,
               OptionSpec("one episode per scene seed, in this order; [] = from scene_set or "
                          "seed and episodes"))
          .add("scene_set", &Options::scene_set_path,
               OptionSpec("a scene-set YAML file (config/scenes/): its seeds, preset, "
                          "categories and start pose; used when seeds is empty"))
          .add("seed", &Options::first_seed,
               OptionSpec("without seeds and scene_set: the first seed (seed, seed + 1, ...)")
                   .atLeast(0))
          .add("episodes", &Options::episodes,
               OptionSpec("without seeds and scene_set: this many episodes").range(1, kMaxEpisodes))
          .add(
              "max_steps", &Options::max_steps,
              OptionSpec("steps per episode at most (the simulator may end it earlier)").atLeast(1))
          .add("start_azimuth", reset(&Reset::start_azimuth_rad),
               OptionSpec("start azimuth of every episode; unset = the scene's own").unit("rad"))
          .add("start_elevation", reset(&Reset::start_elevation_rad),
               OptionSpec("start elevation of every episode; unset = the scene's own").unit("rad"))
          .addChoice(
              "preset", [](const Options& o) { return o.reset.preset.value_or(""); },
              [](Options& o, const std::string& preset) {
                o.reset.preset = preset.empty() ? std::nullopt : std::optional(preset);
              },
              OptionSpec("difficulty preset of every reset; \"\" = the simulator's own"))
          .add("categories", reset(&Reset::categories),
               OptionSpec("object categories of every reset; [] = the simulator's own"))
          .add("csv", &Options::csv_path,
               OptionSpec("one CSV row per episode; \"\" = none; relative = under ROS_HOME"))
          .add("service_timeout", &Options::service_timeout_s,
               OptionSpec("wait this long for the simulator's services; 0 = forever")
                   .unit("s")
                   .atLeast(0))
          .add("step_rate", &Options::step_rate_hz,
               OptionSpec("steps per second at most (to watch in rviz); 0 = no limit")
                   .unit("Hz")
                   .atLeast(0));
  return table;
}

AgentNodeOptions readAgentNodeOptions(const ros::NodeHandle& private_node,
                                      const AgentRegistry& registry) {
  AgentNodeOptions options;
  readParameters(private_node, agentNodeOptionTable(), options);
  try {
    registry.at(options.agent);  // its message names the registered agents
  } catch (const InvalidArgumentError& error) {
    throw ParameterError("parameter " + private_node.resolveName("agent") +
                         (options.agent.empty() ? " is not set: " : ": ") + error.what());
  }
  options.csv_path = underRosHome(options.csv_path);
  applySceneSet(private_node, options);
  if (options.seeds.empty()) {
    for (int i = 0; i < options.episodes; ++i) options.seeds.push_back(options.first_seed + i);
  }
  return options;
}

}  // namespace occlusion_env
