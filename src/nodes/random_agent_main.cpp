// random_agent: the random agent as a ROS node against the simulator's services
// (occlusion_env/ros/agent_node.hpp; parameters: launch/agent.launch).
#include "occlusion_env/ros/agent_node.hpp"

int main(int argc, char** argv) {
  return occlusion_env::runAgentNodeMain(argc, argv, "random");
}
