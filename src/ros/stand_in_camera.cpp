#include "occlusion_env/ros/stand_in_camera.hpp"

#include <boost/make_shared.hpp>
#include <cmath>

#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include "occlusion_env/GroundTruthView.h"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/ros/msg_conversion.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/status.hpp"

namespace occlusion_env {
namespace {

// How far a goal may lie from what the stand-in robot can reach (its sphere, looking at the
// centre) before it says so; it goes to the nearest reachable pose all the same.
constexpr double kReachTolerance_m = 0.01;
constexpr double kReachTolerance_rad = 0.01;

}  // namespace

StandInCamera::StandInCamera(const SimulatorOptions& options, ros::NodeHandle node,
                             ros::NodeHandle /*private_node*/)
    : options_(options),
      node_(std::move(node)),
      environment_(options.environment),
      image_transport_(node_) {
  rgb_publisher_ = image_transport_.advertiseCamera(names::kRgbImageTopic, 2);
  depth_publisher_ = image_transport_.advertiseCamera(names::kDepthImageTopic, 2);
  tf_publisher_ = node_.advertise<tf2_msgs::TFMessage>("/tf", 100);
  ground_truth_publisher_ =
      node_.advertise<GroundTruthView>(names::kGroundTruthViewTopic, 10, /*latch=*/true);

  static_transform_broadcaster_.sendTransform(
      bodyToOpticalTransform(ros::Time::now(), options_.camera_frame, options_.optical_frame));

  resetAtStartUp(options_.start_seed, [this](Reset::Request& request, Reset::Response& response) {
    arrangeScene(request, response);
  });

  arrange_service_ =
      node_.advertiseService(names::kArrangeSceneService, &StandInCamera::arrangeScene, this);
  goal_subscriber_ = node_.subscribe(names::kCameraGoalTopic, 10, &StandInCamera::onGoal, this);
  frame_timer_ = node_.createTimer(ros::Duration(1.0 / options_.camera_rate_hz),
                                   &StandInCamera::onFrame, this);
}

bool StandInCamera::arrangeScene(Reset::Request& request, Reset::Response& response) {
  response.status = runWithStatus([&] {
    environment_.reset(request.seed, toResetOptions(request));
    onViewChanged();
    has_scene_ = true;
    scene_seed_ = request.seed;
    view_index_ = 0;
    goal_.reset();
    publishGroundTruth(ros::Time::now());
  });
  if (response.status.code != Status::OK) {
    ROS_WARN_STREAM("arrange_scene (seed " << request.seed
                                           << ") refused: " << response.status.message);
  }
  return true;
}

void StandInCamera::onGoal(const geometry_msgs::PoseStamped::ConstPtr& goal) {
  if (goal->header.frame_id != options_.world_frame) {
    ROS_WARN_STREAM_THROTTLE(1.0, "camera goal in frame '" << goal->header.frame_id
                                                           << "' ignored: the stand-in robot "
                                                              "takes goals in "
                                                           << options_.world_frame);
    return;
  }
  Eigen::Isometry3d world_from_optical;
  tf2::fromMsg(goal->pose, world_from_optical);
  const Eigen::Vector3d position = world_from_optical.translation();
  if (!position.allFinite() || !world_from_optical.linear().allFinite()) {
    ROS_WARN_THROTTLE(1.0, "camera goal with a non-finite pose ignored");
    return;
  }
  const SphericalPose pose = environment_.camera().normalized(sphericalPoseOf(position));
  // Only poses on the sphere, looking at the centre, can be reached; say so once in a while.
  const Eigen::Isometry3d reachable = environment_.camera().worldFromOptical(pose);
  const double distance_m = (reachable.translation() - position).norm();
  const double angle_rad =
      Eigen::AngleAxisd(reachable.linear().transpose() * world_from_optical.linear()).angle();
  if (distance_m > kReachTolerance_m || angle_rad > kReachTolerance_rad) {
    ROS_WARN_STREAM_THROTTLE(1.0, "camera goal " << distance_m << " m and " << angle_rad
                                                 << " rad from the viewing sphere's nearest "
                                                    "pose: going there instead");
  }
  goal_ = pose;
  goal_arrival_ = ros::Time::now() + ros::Duration(options_.motion_time_s);
}

void StandInCamera::onFrame(const ros::TimerEvent& /*event*/) {
  if (!has_scene_) return;
  const ros::Time stamp = ros::Time::now();
  if (goal_ && stamp >= goal_arrival_) {
    try {
      environment_.viewFrom(*goal_);
      onViewChanged();
      ++view_index_;
      publishGroundTruth(stamp);
    } catch (const std::exception& error) {
      ROS_ERROR_STREAM("the stand-in camera could not render its goal pose: " << error.what());
    }
    goal_.reset();
  }

  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = options_.optical_frame;
  // The transform first, so that a listener has it when the images at its stamp arrive.
  tf2_msgs::TFMessage transforms;
  transforms.transforms.push_back(
      toTransform(environment_.camera().worldFromBody(environment_.info().pose), stamp,
                  options_.world_frame, options_.camera_frame));
  tf_publisher_.publish(transforms);

  const Observation& observation = environment_.observation();
  const auto camera_info =
      boost::make_shared<sensor_msgs::CameraInfo>(toCameraInfo(environment_.intrinsics(), header));
  if (rgb_publisher_.getNumSubscribers() > 0) {
    auto rgb = boost::make_shared<sensor_msgs::Image>();
    fillImage(observation.rgb, header, *rgb);
    rgb_publisher_.publish(rgb, camera_info);
  }
  if (depth_publisher_.getNumSubscribers() > 0) {
    auto depth = boost::make_shared<sensor_msgs::Image>();
    if (options_.depth_encoding == "16UC1") {
      fillImage(depth_millimetres_, header, *depth);
    } else {
      fillImage(observation.depth, header, *depth);
    }
    depth_publisher_.publish(depth, camera_info);
  }
}

void StandInCamera::onViewChanged() {
  // Converted once per view, not once per frame: frames repeat the view until the camera moves.
  if (options_.depth_encoding == "16UC1") {
    toMillimetreDepth(environment_.observation().depth, depth_millimetres_);
  }
}

void StandInCamera::publishGroundTruth(const ros::Time& stamp) {
  const StepInfo& info = environment_.info();
  GroundTruthView view;
  view.header.stamp = stamp;
  view.header.frame_id = options_.world_frame;
  view.scene_seed = scene_seed_;
  view.view_index = view_index_;
  view.azimuth = info.pose.azimuth_rad;
  view.elevation = info.pose.elevation_rad;
  view.occlusion = toOcclusionFigures(info.occlusion);
  view.unoccluded = environment_.reward().solved(info.occlusion.total_pixels);
  ground_truth_publisher_.publish(view);
}

}  // namespace occlusion_env
