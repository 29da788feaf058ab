// Shared by the agent rostests: reading an agent node's episode CSV and replaying its episodes on
// an in-process Environment built from the simulator's own parameters.
#pragma once

#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cstdint>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "occlusion_env/core/agent.hpp"
#include "occlusion_env/core/environment.hpp"
#include "occlusion_env/core/occlusion_gradient.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {
namespace testing_support {

// One row of an agent node's CSV (see AgentNode).
struct CsvEpisode {
  std::string agent;
  std::uint64_t seed = 0;
  int max_steps = 0;
  int steps = 0;
  bool success = false;
  std::int64_t final_occlusion_px = 0;
  bool completed = false;
  std::string message;
  std::vector<double> azimuths;
  std::vector<double> elevations;
};

inline std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream stream(text);
  while (std::getline(stream, field, separator)) fields.push_back(field);
  if (!text.empty() && text.back() == separator) fields.emplace_back();
  return fields;
}

inline std::vector<double> angles(const std::string& text) {
  std::vector<double> values;
  for (const std::string& value : split(text, ';')) values.push_back(std::stod(value));
  return values;
}

// The data rows written so far (none when the file does not exist yet).
inline std::vector<CsvEpisode> readAgentCsv(const std::string& path) {
  std::vector<CsvEpisode> episodes;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return episodes;
  EXPECT_EQ(line,
            "agent,scene_set,scene_seed,start_azimuth_rad,max_steps,steps,success,"
            "final_occlusion_px,wall_time_s,completed,message,azimuths_rad,elevations_rad");
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = split(line, ',');
    if (fields.size() != 13) {
      ADD_FAILURE() << path << ": row with " << fields.size() << " fields: " << line;
      continue;
    }
    CsvEpisode episode;
    episode.agent = fields[0];
    episode.seed = std::stoull(fields[2]);
    episode.max_steps = std::stoi(fields[4]);
    episode.steps = std::stoi(fields[5]);
    episode.success = fields[6] == "1";
    episode.final_occlusion_px = std::stoll(fields[7]);
    episode.completed = fields[9] == "1";
    episode.message = fields[10];
    episode.azimuths = angles(fields[11]);
    episode.elevations = angles(fields[12]);
    episodes.push_back(episode);
  }
  return episodes;
}

// Waits up to `seconds` (wall time) until `path` holds `rows` rows; returns what it holds then.
inline std::vector<CsvEpisode> waitForRows(const std::string& path, std::size_t rows,
                                           double seconds) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  std::vector<CsvEpisode> episodes = readAgentCsv(path);
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

// Runs `agent_name` ("random" | "gradient") in process on the simulator's options and checks
// that `episode` (run through ROS) took exactly the same path to exactly the same end.
inline void expectSameAsInProcess(const std::string& agent_name, const CsvEpisode& episode,
                                  double start_azimuth_rad) {
  static Environment environment(simulatorOptions().environment);
  static AnalyticOcclusionGradient gradient(simulatorOptions().gradient);
  std::unique_ptr<Agent> agent;
  if (agent_name == "gradient") {
    agent = std::make_unique<GradientAgent>(gradientSourceFor(environment, gradient));
  } else {
    agent = std::make_unique<RandomAgent>();
  }
  ResetOptions reset;
  reset.start_azimuth_rad = start_azimuth_rad;
  const EpisodeResult local =
      runEpisode(environment, *agent, episode.seed, reset, episode.max_steps);
  SCOPED_TRACE(agent_name + " seed " + std::to_string(episode.seed));
  EXPECT_EQ(episode.steps, local.steps);
  EXPECT_EQ(episode.success, local.success);
  EXPECT_EQ(episode.final_occlusion_px, local.final_occlusion_pixels);
  ASSERT_EQ(episode.azimuths.size(), local.path.size());
  for (std::size_t t = 0; t < local.path.size(); ++t) {
    EXPECT_NEAR(episode.azimuths[t], local.path[t].azimuth_rad, 1e-7) << "pose " << t;
    EXPECT_NEAR(episode.elevations[t], local.path[t].elevation_rad, 1e-7) << "pose " << t;
  }
}

}  // namespace testing_support
}  // namespace occlusion_env
