#include "occlusion_env/agents/core_agents.hpp"

namespace occlusion_env {

AgentRegistry coreAgents() {
  AgentRegistry registry;
  registry.add(randomAgentEntry());
  registry.add(gradientAgentEntry());
  return registry;
}

}  // namespace occlusion_env
