// test_agent_node: the agent node with the core's agents plus the test-only circling agent
// (test/agents/test_agent.hpp), as any package would add its own agents to its own node.
#include "agents/test_agent.hpp"
#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/ros/agent_node.hpp"

int main(int argc, char** argv) {
  occlusion_env::AgentRegistry registry = occlusion_env::coreAgents();
  registry.add(occlusion_env::testing_support::circlingAgentEntry());
  return occlusion_env::runAgentNodeMain(argc, argv, registry);
}
