#include "occlusion_env/agents/core_agents.hpp"

#include "occlusion_env/agents/depth_geometry_agent.hpp"
#include "occlusion_env/agents/oracle.hpp"

namespace occlusion_env {

AgentRegistry coreAgents() {
  AgentRegistry registry;
  registry.add(randomAgentEntry());
  registry.add(gradientAgentEntry());
  registry.add(depthGeometryAgentEntry());
  registry.add(oracleAgentEntry());
  return registry;
}

}  // namespace occlusion_env
