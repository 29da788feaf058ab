// The occlusion_sim node: the environment behind reset/step/gradient services, image topics, tf,
// markers and a `move` topic for teleoperation.
#pragma once

#include <image_transport/camera_publisher.h>
#include <image_transport/image_transport.h>
#include <image_transport/publisher.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <memory>

#include "occlusion_env/CameraMove.h"
#include "occlusion_env/GetOcclusionGradient.h"
#include "occlusion_env/Reset.h"
#include "occlusion_env/Status.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"
#include "occlusion_env/ros/environment_services.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {

class SimulatorNode {
 public:
  /// Creates the environment (and its OSMesa GL context) on the calling thread, which must be the
  /// one that spins `node`'s callback queue; a single-threaded spinner then serves reset and step
  /// in order. Throws ParameterError when an object id or category parameter names nothing in the
  /// catalogue, and the core's errors when the environment cannot be built.
  SimulatorNode(const SimulatorOptions& options, ros::NodeHandle node,
                ros::NodeHandle private_node);

  /// The service handlers, public so that tests and benchmarks can call them in-process (reset
  /// and step are the shared server's, ros/environment_services.hpp).
  bool reset(Reset::Request& request, Reset::Response& response);
  bool step(Step::Request& request, Step::Response& response);
  bool getOcclusionGradient(GetOcclusionGradient::Request& request,
                            GetOcclusionGradient::Response& response);

 private:
  /// Applies one step; on success `result` holds its outcome. The state is unchanged on error.
  Status applyStep(const CameraMove& move, StepResult& result);
  void onMove(const CameraMove::ConstPtr& move);
  void onTfTimer(const ros::TimerEvent& event);

  /// The observation of the environment's current view, stamped as a new view and published
  /// (with the scene's markers after a reset).
  void answerView(const StepResult& result, CameraObservation& observation);
  /// Stamps a new view (now, in the optical frame): every message of it carries this header.
  const std_msgs::Header& stampNewView();
  /// Publishes images, camera infos and the camera transform of the current view; the scene
  /// markers too when `scene_changed`. Image messages are built only for topics with subscribers.
  void publishView(bool scene_changed);
  geometry_msgs::TransformStamped cameraTransform(const ros::Time& stamp) const;
  void broadcastCameraTransform(const ros::Time& stamp);
  void validateObjectParameters();
  /// Publishers of one image topic and its camera_info that send the current view to each new
  /// subscriber.
  image_transport::CameraPublisher advertiseView(const std::string& topic,
                                                 const cv::Mat Observation::*image);

  SimulatorOptions options_;
  ros::NodeHandle node_;
  ros::NodeHandle private_node_;
  Environment environment_;
  std::unique_ptr<OcclusionGradient> analytic_gradient_;
  std::unique_ptr<OcclusionGradient> finite_difference_gradient_;

  std_msgs::Header view_header_;  // of the current view; stamp zero before the first reset
  image_transport::ImageTransport image_transport_;
  image_transport::CameraPublisher rgb_publisher_;
  image_transport::CameraPublisher depth_publisher_;
  image_transport::CameraPublisher occlusion_mask_publisher_;
  image_transport::CameraPublisher instance_mask_publisher_;
  ros::Publisher scene_markers_publisher_;
  ros::Publisher step_outcome_publisher_;
  ros::Subscriber move_subscriber_;
  std::unique_ptr<EnvironmentServices> services_;  // reset and step
  ros::ServiceServer gradient_service_;
  ros::Publisher tf_publisher_;  // /tf, with the current view's transform for each new listener
  tf2_ros::StaticTransformBroadcaster static_transform_broadcaster_;
  ros::Timer tf_timer_;
};

}  // namespace occlusion_env
