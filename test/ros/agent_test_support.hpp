// Shared by the agent rostests: reading an agent node's episode CSV (the core's format) and
// replaying its episodes on an in-process Environment built from the simulator's own parameters.
#pragma once

#include <gtest/gtest.h>
#include <ros/ros.h>

#include <memory>
#include <string>
#include <vector>

#include "agents/test_agent.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/agents/episode.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {
namespace testing_support {

// The agents the test nodes can run: every agent (occlusion_agent) and the test-only one
// (test_agent_node).
inline const AgentRegistry& testRegistry() {
  static const AgentRegistry registry = [] {
    AgentRegistry agents = learning::learningAgents();
    agents.add(circlingAgentEntry());
    return agents;
  }();
  return registry;
}

// The rows written so far (none while the file does not exist or is being written).
inline std::vector<EpisodeRecord> readAgentCsv(const std::string& path) {
  try {
    return readEpisodeCsv(path);
  } catch (const std::exception&) {
    return {};
  }
}

// Waits up to `seconds` (wall time) until `path` holds `rows` rows; returns what it holds then.
inline std::vector<EpisodeRecord> waitForRows(const std::string& path, std::size_t rows,
                                              double seconds) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  std::vector<EpisodeRecord> episodes = readAgentCsv(path);
  while (episodes.size() < rows && ros::WallTime::now() < deadline) {
    ros::WallDuration(0.1).sleep();
    episodes = readAgentCsv(path);
  }
  return episodes;
}

// The simulator's options, read from its private namespace: the test's ~simulator parameter, by
// default /occlusion_sim.
inline const SimulatorOptions& simulatorOptions() {
  static const SimulatorOptions options = [] {
    std::string simulator = std::string("/") + names::kSimulatorNode;
    ros::NodeHandle("~").getParam("simulator", simulator);
    return readSimulatorOptions(ros::NodeHandle(simulator));
  }();
  return options;
}

// Runs the episode's agent in process on the simulator's options and checks that `episode` (run
// through ROS) took exactly the same path to exactly the same end.
inline void expectSameAsInProcess(const EpisodeRecord& episode, double start_azimuth_rad) {
  static Environment environment(simulatorOptions().environment);
  const std::unique_ptr<Agent> agent = testRegistry().make(episode.agent, {environment, ""});
  EpisodeRequest request;
  request.agent = episode.agent;
  request.scene_set = episode.scene_set;
  request.seed = episode.scene_seed;
  request.reset.start_azimuth_rad = start_azimuth_rad;
  EpisodeRunOptions options;
  options.max_steps = episode.max_steps;
  const EpisodeRecord local = runEpisode(environment, *agent, request, options);
  SCOPED_TRACE(episode.agent + " seed " + std::to_string(episode.scene_seed));
  EXPECT_EQ(episode.steps, local.steps);
  EXPECT_EQ(episode.end, local.end);
  EXPECT_EQ(episode.final_occlusion_px, local.final_occlusion_px);
  ASSERT_EQ(episode.path.size(), local.path.size());
  for (std::size_t t = 0; t < local.path.size(); ++t) {
    EXPECT_EQ(episode.path[t].azimuth_rad, local.path[t].azimuth_rad) << "pose " << t;
    EXPECT_EQ(episode.path[t].elevation_rad, local.path[t].elevation_rad) << "pose " << t;
  }
}

}  // namespace testing_support
}  // namespace occlusion_env
