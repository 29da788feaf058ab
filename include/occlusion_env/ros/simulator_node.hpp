// The occlusion_sim node: the environment behind reset/step/gradient services, image topics, tf,
// markers and a `move` topic for teleoperation.
#pragma once

#include <image_transport/camera_publisher.h>
#include <image_transport/image_transport.h>
#include <image_transport/publisher.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>

#include "occlusion_env/CameraMove.h"
#include "occlusion_env/GetOcclusionGradient.h"
#include "occlusion_env/Reset.h"
#include "occlusion_env/Status.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/core/environment.hpp"
#include "occlusion_env/core/occlusion_gradient.hpp"
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

  /// The service handlers, public so that tests and benchmarks can call them in-process.
  bool reset(Reset::Request& request, Reset::Response& response);
  bool step(Step::Request& request, Step::Response& response);
  bool getOcclusionGradient(GetOcclusionGradient::Request& request,
                            GetOcclusionGradient::Response& response);

 private:
  /// Applies one step; on success `result` holds its outcome. The state is unchanged on error.
  Status applyStep(const CameraMove& move, StepResult& result);
  void onMove(const CameraMove::ConstPtr& move);
  void onTfTimer(const ros::TimerEvent& event);

  /// Header of the current view's messages: now, in the optical frame.
  std_msgs::Header viewHeader() const;
  /// Publishes images, camera infos and the camera transform of the current view; the scene
  /// markers too when `scene_changed`. Image messages are built only for topics with subscribers.
  void publishView(const std_msgs::Header& header, bool scene_changed);
  void broadcastCameraTransform(const ros::Time& stamp);
  void validateObjectParameters();

  SimulatorOptions options_;
  ros::NodeHandle node_;
  ros::NodeHandle private_node_;
  Environment environment_;
  std::unique_ptr<OcclusionGradient> analytic_gradient_;
  std::unique_ptr<OcclusionGradient> finite_difference_gradient_;

  image_transport::ImageTransport image_transport_;
  image_transport::CameraPublisher rgb_publisher_;
  image_transport::CameraPublisher depth_publisher_;
  image_transport::Publisher occlusion_mask_publisher_;
  image_transport::Publisher instance_mask_publisher_;
  ros::Publisher scene_markers_publisher_;
  ros::Publisher step_outcome_publisher_;
  ros::Subscriber move_subscriber_;
  ros::ServiceServer reset_service_;
  ros::ServiceServer step_service_;
  ros::ServiceServer gradient_service_;
  tf2_ros::TransformBroadcaster transform_broadcaster_;
  tf2_ros::StaticTransformBroadcaster static_transform_broadcaster_;
  ros::Timer tf_timer_;
};

}  // namespace occlusion_env
