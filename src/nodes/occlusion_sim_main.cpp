// occlusion_sim: the simulated active-perception camera as a ROS node (doc/USER_GUIDE.md), or,
// with ~mode camera, a stand-in for a real camera on a robot (doc/CAMERA_BRIDGE.md).
#include <ros/ros.h>

#include <exception>

#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"
#include "occlusion_env/ros/simulator_node.hpp"
#include "occlusion_env/ros/stand_in_camera.hpp"

int main(int argc, char** argv) {
  namespace names = occlusion_env::names;
  ros::init(argc, argv, names::kSimulatorNode);
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(names::kNamespace);
  occlusion_env::warnAboutUnknownParameters(private_node, occlusion_env::simulatorOptionTable());
  try {
    // Built on this thread, which then spins alone: the GL context stays on one thread and
    // service calls are served one at a time, in order.
    const auto options = occlusion_env::readSimulatorOptions(private_node);
    if (options.cameraMode()) {
      occlusion_env::StandInCamera camera(options, node, private_node);
      ROS_INFO_STREAM("occlusion_sim ready as a stand-in camera: images under "
                      << node.getNamespace() << ", goals on "
                      << node.resolveName(names::kCameraGoalTopic) << ", scenes by "
                      << node.resolveName(names::kArrangeSceneService));
      ros::spin();
      return 0;
    }
    occlusion_env::SimulatorNode simulator(options, node, private_node);
    ROS_INFO_STREAM("occlusion_sim ready: services "
                    << node.resolveName(names::kResetService) << ", "
                    << node.resolveName(names::kStepService)
                    << (options.offer_gradient ? ", " + node.resolveName(names::kGradientService)
                                               : std::string(" (no gradient service)")));
    ros::spin();
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("occlusion_sim cannot start: " << error.what());
    return 1;
  }
  return 0;
}
