#include "occlusion_env/ros/agent_node_options.hpp"

#include <cmath>
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

}  // namespace

AgentNodeOptions readAgentNodeOptions(const ros::NodeHandle& private_node,
                                      const AgentRegistry& registry) {
  const ParameterReader reader(private_node);
  AgentNodeOptions options;
  reader.read("agent", options.agent);
  try {
    registry.at(options.agent);  // its message names the registered agents
  } catch (const InvalidArgumentError& error) {
    throw ParameterError(reader.prefix("agent") + (options.agent.empty() ? " is not set: " : ": ") +
                         error.what());
  }
  reader.read("model", options.model_path);
  reader.read("max_steps", options.max_steps);
  reader.read("csv", options.csv_path);
  options.csv_path = underRosHome(options.csv_path);
  reader.read("service_timeout", options.service_timeout_s);
  reader.read("step_rate", options.step_rate_hz);
  std::string preset;
  reader.read("preset", preset);
  if (!preset.empty()) options.reset.preset = preset;
  reader.read("categories", options.reset.categories);
  if (private_node.hasParam("start_azimuth")) {
    double azimuth = 0.0;
    reader.read("start_azimuth", azimuth);
    options.reset.start_azimuth_rad = azimuth;
  }
  if (private_node.hasParam("start_elevation")) {
    double elevation = 0.0;
    reader.read("start_elevation", elevation);
    options.reset.start_elevation_rad = elevation;
  }

  std::string scene_set_path;
  reader.read("scene_set", scene_set_path);
  reader.read("seeds", options.seeds);
  if (options.seeds.empty() && !scene_set_path.empty()) {
    SceneSet set;
    try {
      set = loadSceneSet(scene_set_path);
    } catch (const std::exception& error) {
      throw ParameterError(reader.prefix("scene_set") + ": " + error.what());
    }
    options.seeds = set.seeds;
    options.scene_set_name = set.name;
    options.reset = resetOptionsFor(set);
    ROS_INFO_STREAM("scene set " << set.name << " (" << set.seeds.size()
                                 << " seeds): run the simulator with catalog_source " << set.source
                                 << " and num_objects " << set.num_objects << " to get its scenes");
  }
  if (options.seeds.empty()) {
    std::int64_t first_seed = 0;
    int episodes = 10;
    reader.read("seed", first_seed);
    reader.read("episodes", episodes);
    if (first_seed < 0) throw ParameterError(reader.prefix("seed") + " must be >= 0");
    if (episodes < 1 || episodes > kMaxEpisodes) {
      throw ParameterError(reader.prefix("episodes") + " must be in [1, " +
                           std::to_string(kMaxEpisodes) + "]");
    }
    for (int i = 0; i < episodes; ++i) options.seeds.push_back(first_seed + i);
  }

  if (options.max_steps < 1) throw ParameterError(reader.prefix("max_steps") + " must be >= 1");
  if (options.service_timeout_s < 0.0) {
    throw ParameterError(reader.prefix("service_timeout") + " must be >= 0 (0 waits forever)");
  }
  if (options.step_rate_hz < 0.0) {
    throw ParameterError(reader.prefix("step_rate") + " must be >= 0 (0: no limit)");
  }
  return options;
}

const std::vector<std::string>& agentNodeParameterNames() {
  static const std::vector<std::string> kNames = {
      "agent",      "model",     "seeds",           "scene_set",       "seed",
      "episodes",   "max_steps", "start_azimuth",   "start_elevation", "preset",
      "categories", "csv",       "service_timeout", "step_rate"};
  return kNames;
}

}  // namespace occlusion_env
