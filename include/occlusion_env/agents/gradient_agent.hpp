// The gradient agent (the paper's Env. Grad): descends the simulator's occlusion gradient.
#pragma once

#include <functional>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/agents/random_agent.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"

namespace occlusion_env {

/// Steps along the negative occlusion gradient (a unit action: the environment sets the length).
/// The gradient comes from `source` (OcclusionGradientSource, agents/agent_registry.hpp): from the
/// registry, EnvironmentInterface::occlusionGradient(), which the in-process simulator computes and
/// the ROS client asks the simulator's get_occlusion_gradient service for. It reads nothing else
/// that a camera cannot give: the gradient is its only privileged input.
/// On an invalid (zero or undefined) gradient it moves in a random direction, as the paper's
/// gradient method re-ran from a randomly perturbed pose on a NaN gradient.
class GradientAgent : public Agent {
 public:
  /// Throws InvalidArgumentError for an empty source.
  explicit GradientAgent(OcclusionGradientSource source, std::uint64_t seed = 0);
  void reset(std::uint64_t seed) override;
  Action act(const RigObservation& observation) override;

  /// Moves made at random since reset() because the gradient was invalid.
  int randomMoves() const { return random_moves_; }
  /// The gradient behind the last act().
  const GradientResult& lastGradient() const { return last_gradient_; }

 private:
  OcclusionGradientSource source_;
  RandomAgent fallback_;
  GradientResult last_gradient_;
  int random_moves_ = 0;
};

}  // namespace occlusion_env
