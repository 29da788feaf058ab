#include "occlusion_env/agents/gradient_agent.hpp"

#include <utility>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

GradientAgent::GradientAgent(OcclusionGradientSource source, std::uint64_t seed)
    : source_(std::move(source)), fallback_(seed) {
  if (!source_) throw InvalidArgumentError("a gradient agent needs a gradient source");
}

void GradientAgent::reset(std::uint64_t seed) {
  fallback_.reset(seed);
  last_gradient_ = {};
  random_moves_ = 0;
}

Action GradientAgent::act(const RigObservation& observation) {
  last_gradient_ = source_();
  const Eigen::Vector2d& gradient = last_gradient_.gradient;
  if (!last_gradient_.valid || !gradient.allFinite() || gradient.norm() == 0.0) {
    ++random_moves_;
    return fallback_.act(observation);
  }
  const Eigen::Vector2d direction = -gradient.normalized();
  return {direction.x(), direction.y()};
}

}  // namespace occlusion_env

namespace occlusion_env {

AgentEntry gradientAgentEntry() {
  AgentEntry entry;
  entry.name = "gradient";
  entry.summary =
      "a unit move along the negative analytic gradient of the smooth occlusion loss L_s "
      "(doc/GRADIENT.md), a random one when the gradient is invalid; needs the simulator";
  entry.needs.occlusion_gradient = true;
  entry.paper_label = "Env. Grad";
  entry.make = [](const AgentCapabilities& capabilities) {
    return std::make_unique<GradientAgent>(capabilities.occlusion_gradient);
  };
  return entry;
}

}  // namespace occlusion_env
