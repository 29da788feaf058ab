// Runs an Agent of the core as a ROS node that talks to the simulator only through its services:
// reset and step, and get_occlusion_gradient for agents that need it (which a real camera will not
// offer). Each episode is published on ~episodes (EpisodeReport) and written as a CSV row. When the
// simulator goes away mid-episode the episode is reported as cut short, the node waits for the
// services to come back and carries on with the next seed.
#pragma once

#include <ros/ros.h>

#include <cstdint>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "occlusion_env/EpisodeReport.h"
#include "occlusion_env/GetOcclusionGradient.h"
#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/core/agent.hpp"

namespace occlusion_env {

/// What an agent node does; read from its private parameters by readAgentNodeOptions().
struct AgentNodeOptions {
  std::string agent = "random";      // random | gradient
  std::vector<std::uint64_t> seeds;  // one episode per scene seed, in this order
  int max_steps = 50;                // steps per episode at most (the simulator may end it earlier)
  std::string preset;                // reset's preset ("" = the simulator's ~preset)
  std::vector<std::string> categories;  // reset's categories (empty = the simulator's)
  bool set_start_azimuth = false;       // true: every episode starts at start_azimuth_rad
  double start_azimuth_rad = 0.0;
  bool set_start_elevation = false;  // true: every episode starts at start_elevation_rad
  double start_elevation_rad = 0.0;
  std::string scene_set_name = "ros";  // the CSV's scene_set column
  std::string csv_path;                // "" = no CSV; a relative ~csv is under ROS_HOME
  double service_timeout_s = 60.0;     // wait for the simulator's services [s]; 0 = forever
  double step_rate_hz = 0.0;           // steps per second at most (to watch in rviz); 0 = no limit
};

/// Reads the node's options from `private_node`. The seeds come from ~seeds (a list), else from
/// ~scene_set (a scene-set YAML file, which also fixes preset, categories and start pose), else
/// from ~seed and ~episodes (seeds seed, seed + 1, ...). Throws ParameterError naming the
/// parameter on a wrong type or value.
AgentNodeOptions readAgentNodeOptions(const ros::NodeHandle& private_node,
                                      const std::string& agent);

/// Every parameter name readAgentNodeOptions() reads, relative to the private namespace.
const std::vector<std::string>& agentNodeParameterNames();

/// Names of the agents an agent node can run.
const std::vector<std::string>& agentNodeAgents();

/// A service call failed at the transport level: the simulator is gone (or never came).
class SimulatorUnavailableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class AgentNode {
 public:
  /// `node` resolves the simulator's services (occlusion/reset, ...); `private_node` advertises
  /// ~episodes. Throws ParameterError for an unknown agent or an unwritable CSV path.
  AgentNode(const AgentNodeOptions& options, ros::NodeHandle node, ros::NodeHandle private_node);

  /// Runs one episode per seed, logging each. Returns the episodes that ran to their end (success,
  /// truncation or max_steps); the others were cut short and reported. Throws
  /// SimulatorUnavailableError when the services are not there within the timeout, and
  /// ParameterError when the agent needs the gradient service and the simulator has none.
  int run();

  /// The episodes run so far, in order.
  const std::vector<EpisodeReport>& reports() const { return reports_; }

 private:
  EpisodeReport runEpisode(int index, std::uint64_t seed);
  /// Waits for the services and (re)creates persistent clients to them.
  void connect();
  GradientResult requestGradient();
  void writeCsvRow(const EpisodeReport& report);
  void logSummary() const;

  AgentNodeOptions options_;
  ros::NodeHandle node_;
  ros::NodeHandle private_node_;
  std::unique_ptr<Agent> agent_;
  bool needs_gradient_ = false;

  ros::ServiceClient reset_client_;
  ros::ServiceClient step_client_;
  ros::ServiceClient gradient_client_;
  ros::Publisher episodes_publisher_;
  std::ofstream csv_;

  // Reused between calls so that responses are decoded into buffers of the right capacity.
  Reset reset_call_;
  Step step_call_;
  GetOcclusionGradient gradient_call_;
  std::vector<EpisodeReport> reports_;
};

/// The whole main() of an agent executable: ros::init as `<agent>_agent`, options, run, exit code
/// (0 when every requested episode was attempted, 1 on a fatal error).
int runAgentNodeMain(int argc, char** argv, const std::string& agent);

}  // namespace occlusion_env
