// The simulator standing in for a real RGB-D camera on a robot (occlusion_sim with ~mode camera):
// it publishes only what a real camera and robot give (RGB, depth, camera_info, tf), streamed at
// ~camera_rate, and moves its camera to each pose received on camera_goal after ~motion_time, as
// a robot would. What no real camera has, the scene's truth, goes only to ground_truth/: a
// service that arranges a scene from a seed (the lab technician) and the view's occlusion. The
// camera bridge (ros/camera_bridge.hpp) then serves reset/step on top of it, and tests check the
// bridge against the truth.
#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <image_transport/camera_publisher.h>
#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <optional>

#include "occlusion_env/Reset.h"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {

class StandInCamera {
 public:
  /// Creates the environment (and its GL context) on the calling thread, which must spin
  /// `node`'s callback queue alone. With options.start_seed >= 0 the scene of that seed is
  /// arranged at once; until a scene is arranged the camera publishes nothing.
  StandInCamera(const SimulatorOptions& options, ros::NodeHandle node,
                ros::NodeHandle private_node);

  /// ground_truth/arrange_scene: draws the scene of `request.seed` (the Reset fields as in the
  /// simulator) and puts the camera at its start pose at once; a move under way is dropped. The
  /// response carries the status only: the truth is on ground_truth/view.
  bool arrangeScene(Reset::Request& request, Reset::Response& response);

 private:
  void onGoal(const geometry_msgs::PoseStamped::ConstPtr& goal);
  /// One camera frame: arrives at a pending goal when its time has come, then publishes RGB,
  /// depth, their camera_info and the camera's tf, all with one stamp (now).
  void onFrame(const ros::TimerEvent& event);
  /// Re-encodes what frames send of the new view (depth in millimetres, if so configured).
  void onViewChanged();
  void publishGroundTruth(const ros::Time& stamp);

  SimulatorOptions options_;
  ros::NodeHandle node_;
  Environment environment_;
  bool has_scene_ = false;
  std::uint64_t scene_seed_ = 0;
  std::uint32_t view_index_ = 0;
  std::optional<SphericalPose> goal_;  // where the robot is going
  ros::Time goal_arrival_;             // when it gets there

  image_transport::ImageTransport image_transport_;
  image_transport::CameraPublisher rgb_publisher_;
  image_transport::CameraPublisher depth_publisher_;
  ros::Publisher tf_publisher_;
  ros::Publisher ground_truth_publisher_;
  ros::Subscriber goal_subscriber_;
  ros::ServiceServer arrange_service_;
  tf2_ros::StaticTransformBroadcaster static_transform_broadcaster_;
  ros::Timer frame_timer_;
  cv::Mat depth_millimetres_;  // CV_16UC1 of the current view, for ~depth_encoding 16UC1
};

}  // namespace occlusion_env
