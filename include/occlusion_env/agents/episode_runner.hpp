// The one episode loop: reset, then act and step until the episode ends. The evaluation, the
// command-line tools and the agent node all run their episodes through it, on any
// EnvironmentInterface.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "occlusion_env/agents/agent.hpp"
#include "occlusion_env/agents/episode.hpp"
#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

/// One episode to run.
struct EpisodeRequest {
  std::string agent;      // the record's agent name
  std::string scene_set;  // the record's scene-set name
  std::uint64_t seed = 0;
  ResetOptions reset;
};

struct EpisodeRunOptions {
  int max_steps = 50;         // steps at most (the environment may end the episode earlier)
  double step_rate_hz = 0.0;  // steps per second at most (to watch in rviz); 0 = no limit
  /// Asked before every step; returning false stops the episode (EpisodeEnd::kStopped).
  std::function<bool()> keep_running;
  /// Called with every result: the reset's, then each step's (e.g. to save frames).
  std::function<void(const StepResult&)> on_result;
};

/// Resets `environment` with the request's seed and overrides, resets `agent` with the same seed,
/// then steps until success, truncation, `max_steps` steps or a stop. Never throws for what goes
/// wrong in the episode: a refused or failed request, a lost environment or an agent that cannot
/// act end the record with the matching EpisodeEnd and a message. Throws InvalidArgumentError for
/// max_steps < 0 or a negative rate.
EpisodeRecord runEpisode(EnvironmentInterface& environment, Agent& agent,
                         const EpisodeRequest& request, const EpisodeRunOptions& options);

}  // namespace occlusion_env
