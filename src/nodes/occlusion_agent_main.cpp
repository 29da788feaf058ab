// occlusion_agent: any agent of the registry as a ROS node on the simulator's services, chosen by
// ~agent (occlusion_env/ros/agent_node.hpp; parameters: launch/agent.launch, doc/USER_GUIDE.md).
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/ros/agent_node.hpp"

int main(int argc, char** argv) {
  return occlusion_env::runAgentNodeMain(argc, argv, occlusion_env::learning::learningAgents());
}
