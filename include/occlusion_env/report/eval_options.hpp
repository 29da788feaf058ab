// What occlusion_eval's modes share: its options (one mode among scenes, sweep, summarize,
// landscape, strip, networks and all), the agents they run and the plot script.
#pragma once

#include <string>
#include <vector>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/eval/best.hpp"

namespace occlusion_env {
namespace report {

/// occlusion_eval's options (its --help says what each does).
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
  int max_steps = -1;               // -1: the mode's default
  int limit = -1;
  std::string sweep_source = "embedded";
  int sweep_models = -1;  // -1: defaultSweepModels(sweep_source)
  std::string out = "evaluation";
  eval::BestOptions best;
  bool plots = true;
  std::string source_dir;  // "": the package's share directory (doc/INSTALL.md)
  std::string plot_script;
  std::string report;
  std::string model;
};

/// Every agent the evaluation knows, the learned ones too; built once.
const AgentRegistry& agentRegistry();

/// Runs the plot script with `--out options.out` and `plot_args` unless plots are off; a failing
/// script is reported on stderr, not thrown.
void runPlots(const EvalOptions& options, std::vector<std::string> plot_args);

}  // namespace report
}  // namespace occlusion_env
