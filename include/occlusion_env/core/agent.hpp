// Agents that choose camera moves, and an in-process episode runner.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/core/environment.hpp"
#include "occlusion_env/core/occlusion_gradient.hpp"
#include "occlusion_env/core/random.hpp"

namespace occlusion_env {

class Agent {
 public:
  virtual ~Agent() = default;
  /// The next move, given what the camera sees now.
  virtual Action act(const Observation& observation, const StepInfo& info) = 0;
  /// Starts a new episode; `seed` fixes the agent's own random draws.
  virtual void reset(std::uint64_t seed) = 0;
  virtual std::string name() const = 0;
};

/// Moves in a uniformly random direction: a unit action at an angle ~ U[0, 2 pi) in the
/// (azimuth, elevation) plane, drawn from the agent's own seeded RandomSource.
class RandomAgent : public Agent {
 public:
  explicit RandomAgent(std::uint64_t seed = 0);
  Action act(const Observation& observation, const StepInfo& info) override;
  void reset(std::uint64_t seed) override;
  std::string name() const override { return "random"; }

 private:
  RandomSource random_;
};

/// Where a GradientAgent gets dL_s/d(azimuth, elevation) for the current view: in process from an
/// OcclusionGradient on the Environment, or from elsewhere (e.g. a ROS service client).
using OcclusionGradientSource = std::function<GradientResult()>;

/// A source that runs `gradient` on `env`'s current view; both must outlive the source.
OcclusionGradientSource gradientSourceFor(Environment& env, OcclusionGradient& gradient);

/// Steps along the negative occlusion gradient (a unit action: the environment sets the length).
/// On an invalid (zero or undefined) gradient it moves in a random direction, as the paper's
/// gradient method re-ran from a randomly perturbed pose on a NaN gradient.
class GradientAgent : public Agent {
 public:
  /// Throws InvalidArgumentError for an empty source.
  explicit GradientAgent(OcclusionGradientSource source, std::uint64_t seed = 0);
  Action act(const Observation& observation, const StepInfo& info) override;
  void reset(std::uint64_t seed) override;
  std::string name() const override { return "gradient"; }

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

struct EpisodeResult {
  int steps = 0;                            // steps taken
  bool success = false;                     // occlusion reached the success threshold (terminated)
  std::int64_t final_occlusion_pixels = 0;  // L (Eq. 9) of the last view [px]
  std::vector<SphericalPose> path;          // camera angles: the start pose, then one per step
  double wall_time_s = 0.0;                 // reset and steps, agent included
};

/// Resets `env` with `seed` and `reset_options`, resets `agent` with the same seed, and steps
/// until success, the environment's truncation or `max_steps` steps, whichever comes first.
/// Throws InvalidArgumentError for max_steps < 0; errors of reset() and step() pass through.
EpisodeResult runEpisode(Environment& env, Agent& agent, std::uint64_t seed,
                         const ResetOptions& reset_options, int max_steps);

}  // namespace occlusion_env
