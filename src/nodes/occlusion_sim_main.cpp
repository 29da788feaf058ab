// occlusion_sim: the simulated active-perception camera as a ROS node (README, "ROS interface").
#include <ros/ros.h>

#include <exception>

#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"
#include "occlusion_env/ros/simulator_node.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, occlusion_env::names::kSimulatorNode);
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(occlusion_env::names::kNamespace);
  for (const std::string& name : occlusion_env::unknownParameters(private_node)) {
    ROS_WARN_STREAM("unknown parameter " << private_node.resolveName(name) << " is ignored");
  }
  try {
    // Built on this thread, which then spins alone: the GL context stays on one thread and
    // service calls are served one at a time, in order.
    const auto options = occlusion_env::readSimulatorOptions(private_node);
    occlusion_env::SimulatorNode simulator(options, node, private_node);
    ROS_INFO_STREAM("occlusion_sim ready: services "
                    << node.resolveName(occlusion_env::names::kResetService) << ", "
                    << node.resolveName(occlusion_env::names::kStepService)
                    << (options.offer_gradient
                            ? ", " + node.resolveName(occlusion_env::names::kGradientService)
                            : std::string(" (no gradient service)")));
    ros::spin();
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("occlusion_sim cannot start: " << error.what());
    return 1;
  }
  return 0;
}
