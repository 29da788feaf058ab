// What occlusion_eval's modes share: its options (one mode among scenes, sweep, summarize,
// landscape, strip, networks and all), the agents they run and the plot script.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/best.hpp"

namespace occlusion_env {
namespace report {

/// occlusion_eval's options (evalOptionTable() says what each does).
struct EvalOptions {
  // The mode: exactly one of these is set.
  std::string scenes;
  std::string sweep;
  std::string summarize;
  std::string landscape;
  std::string strip;
  bool networks = false;
  bool all = false;

  std::vector<std::string> agents;  // empty: the registry's competitors
  std::optional<int> max_steps;     // none: the mode's default
  std::optional<int> limit;         // none: every scene of the set
  int threads = 2;                  // episodes at once, one simulator (GL context) and agent each
  std::string sweep_source = "embedded";
  std::optional<int> sweep_models;  // none: defaultSweepModels(sweep_source)
  std::string out = "evaluation";
  eval::BestOptions best;
  bool plots = true;
  std::string source_dir;  // "": the package's share directory (doc/INSTALL.md)
  std::string plot_script;
  std::string report;
  std::string model;
  // --scenes only: the world, the depth sensor and camera draws of every scene (env/
  // scene_setup.hpp), from the scene's seed; unset: the void and an ideal sensor, or random with
  // randomize.
  std::optional<std::string> world;
  std::optional<std::string> depth_sensor;
  bool randomize = false;
  CameraRandomization camera_ranges;  // with randomize: the ranges the camera is drawn from
  std::string through_bridge;       // --scenes: "" directly; else through the bridge, this network
  std::string bridge_second_model;  // with through_bridge: "" none; else the bridge's second_model
  // With through_bridge: the bridge's stopping rule (--bridge-* flags), its defaults the bridge's.
  CameraEnvironmentOptions bridge;

  /// Throws InvalidArgumentError unless exactly one mode is set and the options fit it; then
  /// fills source_dir and plot_script with their defaults when they are empty.
  void resolve();
  /// Sets `environment`'s world, depth sensor and camera draws as these options ask (--world,
  /// --depth-sensor, --randomize and the camera's ranges).
  void applySceneRandomization(EnvironmentOptions& environment) const;
};

/// The declared options of EvalOptions; the flags are occlusion_eval's.
const OptionTable<EvalOptions>& evalOptionTable();

/// Every agent the evaluation knows, the learned ones too; built once.
const AgentRegistry& agentRegistry();

/// Runs the plot script with `--out options.out` and `plot_args` unless plots are off; a failing
/// script is reported on stderr, not thrown.
void runPlots(const EvalOptions& options, std::vector<std::string> plot_args);

}  // namespace report
}  // namespace occlusion_env
