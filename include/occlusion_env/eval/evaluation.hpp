// Runs agents, chosen by name from the agent registry, on the scenes of a scene set in process,
// one EpisodeRecord per (agent, scene, start azimuth).
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/agents/episode.hpp"
#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/eval/progress.hpp"

namespace occlusion_env {
namespace eval {

struct EvaluationPlan {
  SceneSet scenes;
  std::vector<double> start_azimuths_rad;  // empty: the set's own start azimuth
  std::vector<std::string> agents;         // empty: the registry's competitors
  int max_steps = 50;                      // per episode; the environment truncates there too
  EnvironmentOptions environment;          // the scene set's choices are applied on top
  std::string model_path;  // for agents that need a model; "" = each one's shipped model
  /// Set: the agents run through the camera bridge's logic in front of the simulator
  /// (env/simulated_camera_rig.hpp: BridgedSimulator), an estimator made by this (one per worker
  /// thread) estimating the occlusion; the records then hold the bridge's verdict and estimate.
  std::function<std::unique_ptr<ViewOcclusionEstimator>()> bridge_estimators;
  CameraEnvironmentOptions bridge;  // its rule; sphere, step and limits are the simulator's
  /// Worker threads, each with its own simulator, estimator and agent, running episodes at once.
  /// The records, CSV and progress come in the same order and are the same as with one.
  int threads = 1;

  int episodes(const AgentRegistry& registry) const;
};

/// Runs every agent of `plan` on every scene (and start azimuth). Each finished episode goes to
/// `csv` (one row, flushed; header first) when given and to `progress` when given, in the order
/// agent, scene, start azimuth whatever plan.threads is. Agents are reset with the scene seed, so a
/// run is reproducible. Throws InvalidArgumentError for an unknown agent or threads < 1, and the
/// episode's message when one is cut short (an in-process environment refused a
/// reset or step, or an agent failed). Through the bridge, `true_final_occlusion_px` (when given)
/// gets the simulator's L where each episode ended [px], in the records' order.
std::vector<EpisodeRecord> runEvaluation(
    const EvaluationPlan& plan, const AgentRegistry& registry, std::ostream* csv,
    ProgressBar* progress, std::vector<std::int64_t>* true_final_occlusion_px = nullptr);

}  // namespace eval
}  // namespace occlusion_env
