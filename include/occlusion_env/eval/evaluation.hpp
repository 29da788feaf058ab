// Runs agents, chosen by name from a registry, on the scenes of a scene set in process, one
// EpisodeRecord per (agent, scene, start azimuth).
#pragma once

#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/core/agent.hpp"
#include "occlusion_env/core/environment.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/scene_set.hpp"
#include "occlusion_env/eval/summary.hpp"

namespace occlusion_env {
namespace eval {

/// Makes an agent acting on `env` (which outlives it).
using AgentFactory = std::function<std::unique_ptr<Agent>(Environment& env)>;

/// Agents by name. New agents plug in with add(); withBuiltinAgents() has "random" and
/// "gradient" (the analytic occlusion gradient of the environment, the paper's "Env. Grad").
class AgentRegistry {
 public:
  static AgentRegistry withBuiltinAgents();

  /// Throws InvalidArgumentError for an empty name or one already registered.
  void add(const std::string& name, AgentFactory factory);
  bool contains(const std::string& name) const { return factories_.count(name) > 0; }
  std::vector<std::string> names() const;
  /// Throws InvalidArgumentError naming the known agents for an unknown name.
  std::unique_ptr<Agent> make(const std::string& name, Environment& env) const;

 private:
  std::map<std::string, AgentFactory> factories_;
};

struct EvaluationPlan {
  SceneSet scenes;
  std::vector<double> start_azimuths_rad;  // empty: the set's own start azimuth
  std::vector<std::string> agents = {"random", "gradient"};
  int max_steps = 50;              // per episode; the environment truncates there too
  EnvironmentOptions environment;  // the scene set's choices are applied on top

  int episodes() const;
};

/// Runs every agent of `plan` on every scene (and start azimuth). Each finished episode goes to
/// `csv` (one row, flushed; header first) when given and to `progress` when given. Agents are
/// reset with the scene seed, so a run is reproducible.
std::vector<EpisodeRecord> runEvaluation(const EvaluationPlan& plan, const AgentRegistry& registry,
                                         std::ostream* csv, ProgressBar* progress);

}  // namespace eval
}  // namespace occlusion_env
