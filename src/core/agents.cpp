#include "occlusion_env/core/agent.hpp"

#include <chrono>
#include <cmath>
#include <utility>

#include "occlusion_env/core/errors.hpp"

namespace occlusion_env {

RandomAgent::RandomAgent(std::uint64_t seed) : random_(seed) {}

Action RandomAgent::act(const Observation&, const StepInfo&) {
  const double angle = random_.uniform(0.0, 2.0 * M_PI);
  return {std::cos(angle), std::sin(angle)};
}

void RandomAgent::reset(std::uint64_t seed) {
  random_ = RandomSource(seed);
}

OcclusionGradientSource gradientSourceFor(Environment& env, OcclusionGradient& gradient) {
  return [&env, &gradient]() { return gradient.compute(env); };
}

GradientAgent::GradientAgent(OcclusionGradientSource source, std::uint64_t seed)
    : source_(std::move(source)), fallback_(seed) {
  if (!source_) throw InvalidArgumentError("a gradient agent needs a gradient source");
}

Action GradientAgent::act(const Observation& observation, const StepInfo& info) {
  last_gradient_ = source_();
  const Eigen::Vector2d& gradient = last_gradient_.gradient;
  if (!last_gradient_.valid || !gradient.allFinite() || gradient.norm() == 0.0) {
    ++random_moves_;
    return fallback_.act(observation, info);
  }
  const Eigen::Vector2d direction = -gradient.normalized();
  return {direction.x(), direction.y()};
}

void GradientAgent::reset(std::uint64_t seed) {
  fallback_.reset(seed);
  last_gradient_ = {};
  random_moves_ = 0;
}

EpisodeResult runEpisode(Environment& env, Agent& agent, std::uint64_t seed,
                         const ResetOptions& reset_options, int max_steps) {
  if (max_steps < 0) throw InvalidArgumentError("max_steps must be >= 0");
  const auto start = std::chrono::steady_clock::now();
  EpisodeResult episode;
  StepResult result = env.reset(seed, reset_options);
  agent.reset(seed);
  episode.path.push_back(result.info.pose);
  bool over = false;
  while (!over && episode.steps < max_steps) {
    const Action action = agent.act(*result.observation, result.info);
    result = env.step(action);
    ++episode.steps;
    episode.path.push_back(result.info.pose);
    episode.success = result.terminated;
    over = result.terminated || result.truncated;
  }
  episode.final_occlusion_pixels = result.info.occlusion.total_pixels;
  episode.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return episode;
}

}  // namespace occlusion_env
