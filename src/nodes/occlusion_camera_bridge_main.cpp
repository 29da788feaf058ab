// occlusion_camera_bridge: a real RGB-D camera on a robot behind the simulator's reset and step
// services (doc/CAMERA_BRIDGE.md; parameters: config/camera_bridge.yaml).
#include <ros/ros.h>
#include <tf2_ros/transform_listener.h>
#include <torch/torch.h>

#include <exception>

#include "occlusion_env/ros/camera_bridge.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"

int main(int argc, char** argv) {
  namespace names = occlusion_env::names;
  ros::init(argc, argv, names::kCameraBridgeNode);
  ros::NodeHandle private_node("~");
  ros::NodeHandle node(names::kNamespace);
  occlusion_env::warnAboutUnknownParameters(private_node, occlusion_env::cameraBridgeOptionTable());
  torch::set_num_threads(1);  // one image at a time: a second thread gains nothing at 64 x 64
  try {
    const auto options = occlusion_env::readCameraBridgeOptions(private_node);
    tf2_ros::Buffer tf;
    tf2_ros::TransformListener listener(tf);  // fills `tf` on its own thread
    occlusion_env::CameraBridge bridge(options, node, tf);
    ros::AsyncSpinner input(1);  // images and camera_info, while a service call waits for them
    input.start();
    ROS_INFO_STREAM("camera bridge ready: services "
                    << node.resolveName(names::kResetService) << ", "
                    << node.resolveName(names::kStepService) << "; goals on "
                    << node.resolveName(names::kCameraGoalTopic) << " in " << options.sphere_frame
                    << "; occlusion "
                    << (options.model_path.empty() ? "unavailable (no ~model)"
                                                   : "estimated by " + options.model_path));
    bridge.spinServices();
  } catch (const std::exception& error) {
    ROS_FATAL_STREAM("camera bridge cannot start: " << error.what());
    return 1;
  }
  return 0;
}
