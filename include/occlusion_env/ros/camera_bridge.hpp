// The camera bridge: a real RGB-D camera on a robot behind the simulator's reset and step
// services, so that every agent runs on it unchanged (doc/CAMERA_BRIDGE.md).
//
// In: synchronised RGB, depth (32FC1 [m] or 16UC1 [mm]) and camera_info; tf from the sphere's
// frame to the camera's optical frame. Out: a geometry_msgs/PoseStamped goal for the optical
// frame on camera_goal, for the robot. A step turns the action into the next pose on the viewing
// sphere (doc/CONVENTIONS.md), publishes it, waits until tf shows the camera there and for the
// first frame stamped settle_time after that, and answers with that frame. Occlusion cannot be
// measured on a real camera: with a network model the bridge estimates it
// (CameraObservation::ESTIMATED) and ends an episode when the estimate has fallen to
// ~occlusion_threshold on confirm_views views after the reset's; without one the figures are
// UNAVAILABLE and only the step limit ends an episode. A timeout, a frame id without tf and a view
// without enough plausible depth answer UNAVAILABLE; images or camera_info the bridge cannot use
// answer INVALID_ARGUMENT. Either leaves the episode as it was, so the next step starts from
// wherever the camera really is.
#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>

#include <opencv2/core.hpp>

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/ros/environment_services.hpp"

namespace occlusion_env {

/// Every option of the bridge, with the defaults config/camera_bridge.yaml documents.
struct CameraBridgeOptions {
  // The viewing sphere's and the camera's frames, in the simulator's convention
  // (doc/CONVENTIONS.md).
  std::string sphere_frame = "world";  // origin = the sphere's centre, z up, azimuth from +x
  std::string optical_frame;           // the camera's optical frame; "" = the images' frame_id

  // What the bridge decides apart from ROS: the sphere, the steps, which views it uses, the
  // stopping rule and the reward (the core's options, by the same parameter names).
  CameraEnvironmentOptions environment;

  // Arrival and frames.
  double arrival_tolerance_steps = 0.1;  // the camera is there within this fraction of a step
  double arrival_timeout_s = 10.0;       // how long a move may take
  double frame_timeout_s = 2.0;          // how long after arrival + settle_time a frame may take
  double settle_time_s = 0.0;            // frames stamped before arrival + this are not used
  double sync_slop_s = 0.02;             // RGB, depth and camera_info within this count as one
  double tf_poll_period_s = 0.002;       // how often tf is looked at while the robot moves

  // Episodes and what is estimated.
  std::string scene_service;      // "": none; else a Reset service called at each reset
  std::string model_path;         // "": no estimate; else a multi-task network model
  std::string second_model_path;  // "": none; else a second network: its estimate joins model's

  /// Throws ParameterError naming the first bad option (the table's ranges, and a sphere_frame).
  void validate() const;
};

/// The bridge's parameters (names relative to its private namespace; config/camera_bridge.yaml).
const OptionTable<CameraBridgeOptions>& cameraBridgeOptionTable();

/// How close tf must show the camera to its goal: arrival_tolerance of one step, which moves the
/// camera radius * step_size [m] along the sphere and turns its view by step_size [rad].
struct ArrivalTolerance {
  double position_m = 0.0;
  double angle_rad = 0.0;
};
ArrivalTolerance arrivalTolerance(const CameraBridgeOptions& options);

/// Reads every option from the node's private namespace; absent parameters keep their defaults.
CameraBridgeOptions readCameraBridgeOptions(const ros::NodeHandle& private_node);

/// The ROS side of the bridge: tf and the camera's topics are the rig of a CameraEnvironment
/// (env/camera_environment.hpp), which decides everything else; its reset and step are served as
/// the simulator's services.
class CameraBridge : private CameraRig {
 public:
  /// `node` resolves the topics and services (occlusion/...); `tf` must be filled by a listener
  /// on its own thread. Loads the model (ParameterError when it cannot). Subscriptions are served
  /// by the global callback queue, which must be spun by another thread (an AsyncSpinner); the
  /// services by spinServices().
  CameraBridge(const CameraBridgeOptions& options, ros::NodeHandle node, tf2_ros::Buffer& tf);
  ~CameraBridge() override;

  /// Serves reset and step (the simulator's server, ros/environment_services.hpp), one at a time,
  /// until ROS shuts down.
  void spinServices();

 private:
  using Sync =
      message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image,
                                                      sensor_msgs::CameraInfo>;
  struct Frame {
    sensor_msgs::ImageConstPtr rgb, depth;
    sensor_msgs::CameraInfoConstPtr info;
  };

  // CameraRig: the scene service, tf and the synchronised frames.
  void arrangeScene(std::uint64_t seed, const ResetOptions& overrides) override;
  Eigen::Isometry3d cameraPose() override;
  const CameraFrame& moveTo(const SphericalPose& goal) override;
  const CameraFrame& currentFrame() override;
  std::string describe() const override;

  void onFrame(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth,
               const sensor_msgs::CameraInfoConstPtr& info);
  /// The first frame stamped at or after `after`, waiting until `after` and then up to
  /// frame_timeout; EnvironmentUnavailableError after that.
  Frame waitForFrame(const ros::Time& after);
  /// ~optical_frame, else the latest images' frame_id.
  std::string opticalFrame();
  /// `optical_frame` in the sphere's frame at `stamp` (zero: the latest), waiting up to `wait_s`
  /// for tf; EnvironmentUnavailableError naming both frames when tf cannot say.
  Eigen::Isometry3d lookUpPose(const std::string& optical_frame, const ros::Time& stamp,
                               ros::Time* transform_stamp = nullptr, double wait_s = 0.0);
  /// The optical frame of `frame` at its stamp, waiting briefly for tf to catch up; the latest
  /// pose when it does not.
  Eigen::Isometry3d poseAt(const Frame& frame);
  /// Publishes the goal and waits until tf shows the camera there; returns the stamp of the
  /// transform that did. EnvironmentUnavailableError after the timeout, or at once when tf
  /// cannot place the optical frame at all.
  ros::Time sendGoalAndWait(const SphericalPose& goal);
  /// `frame` as the core takes it (checked, depth in metres, rgb8) with its pose; keeps `frame`
  /// for the answer. InvalidArgumentError for encodings, sizes or a camera_info the bridge cannot
  /// use.
  const CameraFrame& takeFrame(const Frame& frame);
  /// The answer's observation: the core's view of the last frame, with that frame's header.
  void fillObservation(const StepResult& result, CameraObservation& observation);
  void noteStepTiming(double overhead_s, double robot_s, double frame_s);

  CameraBridgeOptions options_;
  ros::NodeHandle node_;
  tf2_ros::Buffer& tf_;
  SphericalCamera sphere_;
  std::unique_ptr<ViewOcclusionEstimator> estimator_;
  CameraEnvironment environment_;  // the decision logic; this object is its rig

  // Input, on the global queue's thread.
  message_filters::Subscriber<sensor_msgs::Image> rgb_subscriber_;
  message_filters::Subscriber<sensor_msgs::Image> depth_subscriber_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_subscriber_;
  message_filters::Synchronizer<Sync> synchronizer_;
  std::mutex frame_mutex_;
  std::condition_variable frame_arrived_;
  Frame latest_frame_;

  // Services, on their own queue (spinServices()).
  ros::CallbackQueue service_queue_;
  ros::Publisher goal_publisher_;
  std::unique_ptr<EnvironmentServices> services_;  // reset and step, on service_queue_
  ros::ServiceClient scene_client_;

  // The rig's state: frames from before view_since_ (the arrangement; zero after a move or a
  // view) do not show the camera where it is.
  ros::Time view_since_;
  Frame taken_frame_;         // the last frame given to the core, for the answer's header
  CameraFrame camera_frame_;  // its conversion
  cv::Mat bgr_to_rgb_, depth_m_;
  double robot_s_ = 0.0, frame_s_ = 0.0;  // the last move's waits

  // Timing and valid depth of the last steps, summarised in the log every kTimingWindow steps.
  std::vector<double> overhead_times_s_, robot_times_s_, frame_times_s_, valid_depth_fractions_;
};

}  // namespace occlusion_env
