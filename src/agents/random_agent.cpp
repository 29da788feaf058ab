#include "occlusion_env/agents/random_agent.hpp"

#include <cmath>
#include <memory>

#include "occlusion_env/agents/core_agents.hpp"

namespace occlusion_env {

RandomAgent::RandomAgent(std::uint64_t seed) : random_(seed) {}

void RandomAgent::reset(std::uint64_t seed) {
  random_ = RandomSource(seed);
}

Action RandomAgent::act(const RigObservation&) {
  const double angle = random_.uniform(0.0, 2.0 * M_PI);
  return {std::cos(angle), std::sin(angle)};
}

}  // namespace occlusion_env

namespace occlusion_env {

AgentEntry randomAgentEntry() {
  AgentEntry entry;
  entry.name = "random";
  entry.summary = "a unit move in a uniformly random direction of the (azimuth, elevation) plane";
  entry.paper_label = "Random";
  entry.make = [](const AgentCapabilities&) { return std::make_unique<RandomAgent>(); };
  return entry;
}

}  // namespace occlusion_env
