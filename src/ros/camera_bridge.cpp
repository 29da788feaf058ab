#include "occlusion_env/ros/camera_bridge.hpp"

#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/statistics.hpp"
#include "occlusion_env/learning/occlusion_estimator.hpp"
#include "occlusion_env/ros/msg_conversion.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"
#include "occlusion_env/ros/status.hpp"

namespace occlusion_env {
namespace {

constexpr std::size_t kTimingWindow = 20;  // steps per timing line in the log
constexpr double kTfWait_s = 0.1;          // how long tf may lag behind a frame

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string milliseconds(double seconds) {
  std::ostringstream text;
  text.precision(3);
  text << seconds * 1000.0 << " ms";
  return text.str();
}

// `text` without trailing blanks.
std::string trimmed(std::string text) {
  text.erase(text.find_last_not_of(" \n") + 1);
  return text;
}

std::string percent(double fraction) {
  std::ostringstream text;
  text.precision(3);
  text << fraction * 100.0 << " %";
  return text.str();
}

// InvalidArgumentError unless the bridge converts these encodings.
void checkEncodings(const sensor_msgs::Image& rgb, const sensor_msgs::Image& depth) {
  namespace enc = sensor_msgs::image_encodings;
  if (rgb.encoding != enc::RGB8 && rgb.encoding != enc::BGR8) {
    throw InvalidArgumentError("colour image encoding " + occlusion_env::quoted(rgb.encoding) +
                               " is not supported: give rgb8 or bgr8");
  }
  if (depth.encoding != enc::TYPE_16UC1 && depth.encoding != enc::MONO16 &&
      depth.encoding != enc::TYPE_32FC1) {
    throw InvalidArgumentError("depth image encoding " + occlusion_env::quoted(depth.encoding) +
                               " is not supported: give 16UC1 (or mono16) in millimetres or 32FC1 "
                               "in metres (REP 118), registered to the colour image");
  }
  if (depth.is_bigendian) {
    throw InvalidArgumentError("big-endian depth images are not supported: give little-endian");
  }
}

// InvalidArgumentError naming what does not fit unless `info` (from `topic`) describes the
// width x height images it came with: their size, finite positive focal lengths and the
// principal point inside.
void checkCameraInfo(const sensor_msgs::CameraInfo& info, int width, int height,
                     const std::string& topic) {
  const double fx = info.K[0], fy = info.K[4], cx = info.K[2], cy = info.K[5];
  std::ostringstream problem;
  if (info.width != static_cast<std::uint32_t>(width) ||
      info.height != static_cast<std::uint32_t>(height)) {
    problem << "describes " << info.width << " x " << info.height << " images, the images are "
            << width << " x " << height << " (a calibration of another resolution?)";
  } else if (!(std::isfinite(fx) && fx > 0.0 && std::isfinite(fy) && fy > 0.0)) {
    problem << "has the focal lengths fx " << fx << ", fy " << fy
            << " px in K: both must be finite and positive (an uncalibrated camera?)";
  } else if (!(cx >= 0.0 && cx <= width && cy >= 0.0 && cy <= height)) {
    problem << "puts the principal point at (" << cx << ", " << cy << ") px, outside the " << width
            << " x " << height << " image";
  } else {
    return;
  }
  throw InvalidArgumentError("camera_info on " + topic + " " + problem.str() +
                             ": give the colour camera's camera_info, calibrated at the images' "
                             "resolution");
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Options
// ---------------------------------------------------------------------------------------------

const OptionTable<CameraBridgeOptions>& cameraBridgeOptionTable() {
  using Options = CameraBridgeOptions;
  static const auto table = [] {
    OptionTable<Options> made;
    // The viewing sphere's and the camera's frames.
    made.add("sphere_frame", &Options::sphere_frame,
             OptionSpec("frame at the sphere's centre (the objects' middle), z up: azimuth "
                        "about its z from its x, elevation above its xy plane; not empty"))
        .add("optical_frame", &Options::optical_frame,
             OptionSpec("the camera's optical frame (z forward); \"\" = the images' frame_id"));
    // What the core decides: the sphere, the steps, the views it uses, the stopping rule.
    made.include(cameraEnvironmentOptionTable(),
                 [](Options& options) -> CameraEnvironmentOptions& { return options.environment; });
    // When the robot has arrived and which frame is the view's.
    made.add("arrival_tolerance", &Options::arrival_tolerance_steps,
             OptionSpec("the camera has arrived when tf shows it within this fraction of a step "
                        "of the goal: arrival_tolerance * radius * step_size in position, "
                        "arrival_tolerance * step_size in orientation")
                 .unit("steps")
                 .above(0)
                 .atMost(0.5))
        .add("arrival_timeout", &Options::arrival_timeout_s,
             OptionSpec("a move that takes longer fails (status UNAVAILABLE)").unit("s").above(0))
        .add("frame_timeout", &Options::frame_timeout_s,
             OptionSpec("no frame this long after arrival + settle_time fails (UNAVAILABLE)")
                 .unit("s")
                 .above(0))
        .add("settle_time", &Options::settle_time_s,
             OptionSpec("wait after arrival: frames stamped less than this after it are not "
                        "used (motion blur, a robot that rings after it stops)")
                 .unit("s")
                 .atLeast(0))
        .add("sync_slop", &Options::sync_slop_s,
             OptionSpec("RGB, depth and camera_info stamped within this are one frame")
                 .unit("s")
                 .atLeast(0))
        .add("tf_poll_period", &Options::tf_poll_period_s,
             OptionSpec("how often tf is read while the robot moves").unit("s").above(0).atMost(1));
    // Episodes: the scene service and the network whose map is the estimate.
    made.add("scene_service", &Options::scene_service,
             OptionSpec("\"\": none; else an occlusion_env/Reset service that arranges the "
                        "scene at every reset"))
        .add("model", &Options::model_path,
             OptionSpec("\"\": occlusion is UNAVAILABLE and only max_steps ends an episode; "
                        "else a multi-task network (.pt with its .json) whose occlusion map is "
                        "the ESTIMATED occlusion"))
        .add("second_model", &Options::second_model_path,
             OptionSpec("\"\": none; else a second network whose map (at "
                        "second_occlusion_probability) joins model's: a pixel is occluded where "
                        "either says so, so a view is clear only where both see none"));
    return made;
  }();
  return table;
}

void CameraBridgeOptions::validate() const {
  try {
    cameraBridgeOptionTable().check(*this);
  } catch (const InvalidArgumentError& error) {
    throw ParameterError(std::string("camera bridge: ") + error.what());
  }
  if (sphere_frame.empty()) throw ParameterError("camera bridge: sphere_frame must not be empty");
  if (!second_model_path.empty() && model_path.empty()) {
    throw ParameterError("camera bridge: second_model needs a model: it joins that one's estimate");
  }
}

ArrivalTolerance arrivalTolerance(const CameraBridgeOptions& options) {
  const CameraEnvironmentOptions& sphere = options.environment;
  return {options.arrival_tolerance_steps * sphere.radius_m * sphere.step_size_rad,
          options.arrival_tolerance_steps * sphere.step_size_rad};
}

CameraBridgeOptions readCameraBridgeOptions(const ros::NodeHandle& private_node) {
  CameraBridgeOptions options;
  readParameters(private_node, cameraBridgeOptionTable(), options);
  try {
    options.validate();
  } catch (const ParameterError& error) {
    throw ParameterError(std::string(error.what()) + " (parameters in " +
                         private_node.getNamespace() + ")");
  }
  return options;
}

// ---------------------------------------------------------------------------------------------
// The bridge
// ---------------------------------------------------------------------------------------------

namespace {

// The network of ~model, ParameterError when it cannot be loaded; nullptr without one.
std::unique_ptr<ViewOcclusionEstimator> estimatorFor(const CameraBridgeOptions& options) {
  if (options.model_path.empty()) return nullptr;
  const auto load = [](const std::string& parameter, const std::string& path) {
    try {
      return std::make_shared<learning::LoadedModel>(learning::loadModel(path));
    } catch (const std::exception& error) {
      throw ParameterError("parameter ~" + parameter + ": " + std::string(error.what()));
    }
  };
  std::shared_ptr<learning::LoadedModel> model = load("model", options.model_path);
  std::shared_ptr<learning::LoadedModel> second;
  if (!options.second_model_path.empty()) second = load("second_model", options.second_model_path);
  try {
    return learning::makeBridgeEstimator(std::move(model), options.environment, std::move(second));
  } catch (const std::exception& error) {
    throw ParameterError("parameter ~model: " + std::string(error.what()));
  }
}

}  // namespace

CameraBridge::CameraBridge(const CameraBridgeOptions& options, ros::NodeHandle node,
                           tf2_ros::Buffer& tf)
    : options_((options.validate(), options)),
      node_(std::move(node)),
      tf_(tf),
      sphere_(options.environment.sphere()),
      estimator_(estimatorFor(options)),
      environment_(options.environment, *this, estimator_.get()),
      rgb_subscriber_(node_, names::kRgbImageTopic, 5),
      depth_subscriber_(node_, names::kDepthImageTopic, 5),
      info_subscriber_(node_, names::kRgbCameraInfoTopic, 5),
      synchronizer_(Sync(10), rgb_subscriber_, depth_subscriber_, info_subscriber_) {
  synchronizer_.setMaxIntervalDuration(ros::Duration(options_.sync_slop_s));
  synchronizer_.registerCallback(&CameraBridge::onFrame, this);

  ros::NodeHandle service_node(node_);
  service_node.setCallbackQueue(&service_queue_);
  // Latched: a robot driver that connects late, or whose connection is still being made when a
  // step publishes, still gets the goal the bridge is waiting for.
  goal_publisher_ =
      node_.advertise<geometry_msgs::PoseStamped>(names::kCameraGoalTopic, 1, /*latch=*/true);
  if (!options_.scene_service.empty()) {
    scene_client_ = node_.serviceClient<Reset>(options_.scene_service);
  }
  services_ = std::make_unique<EnvironmentServices>(
      service_node, environment_,
      [this](const StepResult& result, CameraObservation& observation) {
        fillObservation(result, observation);
      },
      [this](const StepResult& /*result*/, double answer_s) {
        // Apart from waiting for the robot and the camera: the bridge's own work.
        noteStepTiming(answer_s - robot_s_ - frame_s_, robot_s_, frame_s_);
      });
}

CameraBridge::~CameraBridge() = default;

void CameraBridge::spinServices() {
  while (node_.ok()) service_queue_.callAvailable(ros::WallDuration(0.1));
}

void CameraBridge::onFrame(const sensor_msgs::ImageConstPtr& rgb,
                           const sensor_msgs::ImageConstPtr& depth,
                           const sensor_msgs::CameraInfoConstPtr& info) {
  {
    std::lock_guard<std::mutex> lock(frame_mutex_);
    latest_frame_ = {rgb, depth, info};
  }
  frame_arrived_.notify_all();
}

CameraBridge::Frame CameraBridge::waitForFrame(const ros::Time& after) {
  // Until `after` (arrival + settle_time, in the future while the robot settles), then at most
  // frame_timeout.
  const double wait_s =
      options_.frame_timeout_s + std::max(0.0, (after - ros::Time::now()).toSec());
  std::unique_lock<std::mutex> lock(frame_mutex_);
  const auto is_new = [&] { return latest_frame_.rgb && latest_frame_.rgb->header.stamp >= after; };
  const bool arrived = frame_arrived_.wait_for(lock, std::chrono::duration<double>(wait_s), is_new);
  if (!arrived) {
    std::ostringstream message;
    message << "no synchronised RGB-D frame (" << rgb_subscriber_.getTopic() << ", "
            << depth_subscriber_.getTopic() << ", " << info_subscriber_.getTopic()
            << ") stamped after " << after << " within " << options_.frame_timeout_s << " s; ";
    if (latest_frame_.rgb) {
      message << "the last one is " << (ros::Time::now() - latest_frame_.rgb->header.stamp).toSec()
              << " s old: is the camera still publishing?";
    } else {
      message << "none has come yet: check the topics and that their stamps agree within "
              << options_.sync_slop_s << " s (~sync_slop)";
    }
    throw EnvironmentUnavailableError(message.str());
  }
  return latest_frame_;
}

std::string CameraBridge::opticalFrame() {
  if (!options_.optical_frame.empty()) return options_.optical_frame;
  std::lock_guard<std::mutex> lock(frame_mutex_);
  if (!latest_frame_.rgb) {
    throw EnvironmentUnavailableError("no camera frame yet: the optical frame is not known");
  }
  return latest_frame_.rgb->header.frame_id;
}

Eigen::Isometry3d CameraBridge::lookUpPose(const std::string& optical_frame, const ros::Time& stamp,
                                           ros::Time* transform_stamp, double wait_s) {
  geometry_msgs::TransformStamped transform;
  try {
    transform =
        tf_.lookupTransform(options_.sphere_frame, optical_frame, stamp, ros::Duration(wait_s));
  } catch (const tf2::TransformException& error) {
    const bool known = tf_._frameExists(optical_frame);
    throw EnvironmentUnavailableError(
        "no transform from the sphere frame " + occlusion_env::quoted(options_.sphere_frame) +
        " to the camera's optical frame " + occlusion_env::quoted(optical_frame) +
        (options_.optical_frame.empty() ? " (the images' frame_id)" : " (~optical_frame)") +
        (known ? "" : ", a frame tf has not heard of") + ": " + trimmed(error.what()) +
        "; publish tf for it (the robot's description, a static transform) or set ~optical_frame");
  }
  if (transform_stamp != nullptr) *transform_stamp = transform.header.stamp;
  return tf2::transformToEigen(transform);
}

Eigen::Isometry3d CameraBridge::poseAt(const Frame& frame) {
  const std::string optical_frame =
      options_.optical_frame.empty() ? frame.rgb->header.frame_id : options_.optical_frame;
  const ros::Time& stamp = frame.rgb->header.stamp;
  try {
    return lookUpPose(optical_frame, stamp, nullptr, kTfWait_s);
  } catch (const EnvironmentUnavailableError&) {
    return lookUpPose(optical_frame, ros::Time(0));  // tf has not caught up: the latest
  }
}

ros::Time CameraBridge::sendGoalAndWait(const SphericalPose& goal) {
  const Eigen::Isometry3d sphere_from_goal = sphere_.worldFromOptical(goal);
  geometry_msgs::PoseStamped message;
  message.header.stamp = ros::Time::now();
  message.header.frame_id = options_.sphere_frame;
  message.pose = toPose(sphere_from_goal);
  goal_publisher_.publish(message);

  const ArrivalTolerance tolerance = arrivalTolerance(options_);
  const ros::WallTime deadline =
      ros::WallTime::now() + ros::WallDuration(options_.arrival_timeout_s);
  ros::WallTime lookups_fail_since;  // zero while tf answers
  double distance_m = -1.0, angle_rad = -1.0;
  while (ros::ok()) {
    try {
      ros::Time stamp;
      const Eigen::Isometry3d pose = lookUpPose(opticalFrame(), ros::Time(0), &stamp);
      lookups_fail_since = ros::WallTime();
      distance_m = (pose.translation() - sphere_from_goal.translation()).norm();
      angle_rad = Eigen::AngleAxisd(sphere_from_goal.linear().transpose() * pose.linear()).angle();
      // A transform stamped before the goal shows where the camera was, not where it is.
      if (distance_m <= tolerance.position_m && angle_rad <= tolerance.angle_rad &&
          (stamp >= message.header.stamp || stamp.isZero())) {
        return stamp.isZero() ? ros::Time::now() : stamp;
      }
    } catch (const EnvironmentUnavailableError&) {
      // The latest transform fails only for a frame tf does not know or cannot connect to the
      // sphere frame: no wait makes it come, so say so at once (after tf's usual lag).
      if (lookups_fail_since.isZero()) lookups_fail_since = ros::WallTime::now();
      if ((ros::WallTime::now() - lookups_fail_since).toSec() > kTfWait_s) throw;
    }
    if (ros::WallTime::now() > deadline) break;
    ros::WallDuration(options_.tf_poll_period_s).sleep();
  }
  std::ostringstream text;
  text << "the camera did not reach the goal (azimuth " << goal.azimuth_rad << " rad, elevation "
       << goal.elevation_rad << " rad) within " << options_.arrival_timeout_s << " s: ";
  if (distance_m >= 0.0) {
    text << "tf last showed it " << distance_m << " m and " << angle_rad << " rad away";
  } else {
    text << "tf has not shown the camera yet";
  }
  text << " (tolerances " << tolerance.position_m << " m, " << tolerance.angle_rad
       << " rad: ~arrival_tolerance " << options_.arrival_tolerance_steps
       << " of a step); is the robot taking goals on " << goal_publisher_.getTopic() << "?";
  throw EnvironmentUnavailableError(text.str());
}

// ---------------------------------------------------------------------------------------------
// The rig: what the core (env/camera_environment.hpp) asks of the robot and the camera
// ---------------------------------------------------------------------------------------------

void CameraBridge::arrangeScene(std::uint64_t seed, const ResetOptions& overrides) {
  ros::Time start = ros::Time::now();
  if (scene_client_) {
    // The scene's node may still be starting (loading its objects).
    if (!scene_client_.waitForExistence(ros::Duration(options_.arrival_timeout_s))) {
      throw EnvironmentUnavailableError("the scene service " + scene_client_.getService() +
                                        " did not appear within " +
                                        std::to_string(options_.arrival_timeout_s) + " s");
    }
    Reset scene;
    scene.request = toResetRequest(seed, overrides);
    if (!scene_client_.call(scene)) {
      throw EnvironmentUnavailableError("the scene service " + scene_client_.getService() +
                                        " could not be called");
    }
    throwForStatus(scene.response.status, "the scene service refused");
    start = ros::Time::now();  // frames from before the scene was arranged do not count
  }
  view_since_ = start;
}

Eigen::Isometry3d CameraBridge::cameraPose() {
  // After an arrangement (which may have moved the camera): at a frame from after it.
  if (!view_since_.isZero()) return poseAt(waitForFrame(view_since_));
  return lookUpPose(opticalFrame(), ros::Time(0), nullptr, kTfWait_s);
}

const CameraFrame& CameraBridge::moveTo(const SphericalPose& goal) {
  auto waited = std::chrono::steady_clock::now();
  const ros::Time arrived = sendGoalAndWait(goal);
  robot_s_ = secondsSince(waited);
  view_since_ = ros::Time();
  waited = std::chrono::steady_clock::now();
  const Frame frame = waitForFrame(arrived + ros::Duration(options_.settle_time_s));
  frame_s_ = secondsSince(waited);
  return takeFrame(frame);
}

const CameraFrame& CameraBridge::currentFrame() {
  const Frame frame = waitForFrame(view_since_ + ros::Duration(options_.settle_time_s));
  view_since_ = ros::Time();
  return takeFrame(frame);
}

std::string CameraBridge::describe() const {
  return "a camera on " + rgb_subscriber_.getTopic() + ", moved by a robot on " +
         goal_publisher_.getTopic();
}

const CameraFrame& CameraBridge::takeFrame(const Frame& frame) {
  namespace enc = sensor_msgs::image_encodings;
  const sensor_msgs::Image& rgb_message = *frame.rgb;
  checkEncodings(rgb_message, *frame.depth);
  if (rgb_message.width == 0 || rgb_message.height == 0) {
    throw InvalidArgumentError("the colour image is empty");
  }
  cv::Mat rgb;
  try {
    toMetricDepth(*frame.depth, depth_m_);
    rgb = imageView(rgb_message, rgb_message.encoding, CV_8UC3);
  } catch (const std::invalid_argument& error) {  // data shorter than width, height and step say
    throw InvalidArgumentError(std::string("camera image: ") + error.what());
  }
  if (depth_m_.cols != rgb.cols || depth_m_.rows != rgb.rows) {
    throw InvalidArgumentError("depth is " + std::to_string(depth_m_.cols) + " x " +
                               std::to_string(depth_m_.rows) + ", colour " +
                               std::to_string(rgb.cols) + " x " + std::to_string(rgb.rows) +
                               ": give depth registered to the colour image (e.g. "
                               "realsense2_camera's aligned_depth_to_color)");
  }
  checkCameraInfo(*frame.info, rgb.cols, rgb.rows, info_subscriber_.getTopic());
  // rgb8 is used where it lies (the response's copy is the only one); bgr8 is converted once.
  if (rgb_message.encoding == enc::BGR8) {
    cv::cvtColor(rgb, bgr_to_rgb_, cv::COLOR_BGR2RGB);
    rgb = bgr_to_rgb_;
  }
  camera_frame_.rgb = rgb;
  camera_frame_.depth = depth_m_;
  camera_frame_.intrinsics = intrinsicsOf(*frame.info);
  camera_frame_.sphere_from_optical = poseAt(frame);
  taken_frame_ = frame;
  return camera_frame_;
}

// ---------------------------------------------------------------------------------------------
// The services
// ---------------------------------------------------------------------------------------------

void CameraBridge::fillObservation(const StepResult& result, CameraObservation& observation) {
  const std_msgs::Header& header = taken_frame_.rgb->header;
  observation.header = header;
  fillImage(result.observation->rgb, header, observation.rgb);
  fillImage(result.observation->depth, header, observation.depth);
  observation.camera_info = *taken_frame_.info;
  observation.camera_info.header = header;
  if (options_.environment.square_crop) {
    // The crop moves the principal point; the projection keeps its focal lengths.
    const cv::Rect& crop = environment_.cropRegion();
    observation.camera_info.width = crop.width;
    observation.camera_info.height = crop.height;
    observation.camera_info.K[2] -= crop.x;
    observation.camera_info.K[5] -= crop.y;
    observation.camera_info.P[2] -= crop.x;
    observation.camera_info.P[6] -= crop.y;
    observation.camera_info.roi = sensor_msgs::RegionOfInterest();
  }

  observation.camera_pose.header.stamp = header.stamp;
  observation.camera_pose.header.frame_id = options_.sphere_frame;
  observation.camera_pose.pose = toPose(result.info.world_from_optical);
  observation.azimuth = result.info.pose.azimuth_rad;
  observation.elevation = result.info.pose.elevation_rad;
  observation.step_index = result.info.step_index;
  observation.instance_mask = sensor_msgs::Image();
  observation.object_ids.clear();
  observation.object_categories.clear();
  observation.occlusion = toOcclusionFigures(result.info.occlusion);
  if (result.info.occlusion_source == OcclusionSource::kEstimated) {
    observation.occlusion_source = CameraObservation::ESTIMATED;
    fillImage(result.observation->occlusion_mask, header, observation.occlusion_mask);
  } else {
    observation.occlusion_source = CameraObservation::UNAVAILABLE;
    observation.occlusion_mask = sensor_msgs::Image();
  }
}

void CameraBridge::noteStepTiming(double overhead_s, double robot_s, double frame_s) {
  overhead_times_s_.push_back(overhead_s);
  robot_times_s_.push_back(robot_s);
  frame_times_s_.push_back(frame_s);
  valid_depth_fractions_.push_back(environment_.validDepthFraction());
  if (overhead_times_s_.size() < kTimingWindow) return;
  ROS_INFO_STREAM(
      "camera bridge, median of the last "
      << kTimingWindow << " steps: own work " << milliseconds(median(overhead_times_s_))
      << " (goal, pose, conversion" << (estimator_ ? ", estimate" : "")
      << "); waiting for the robot " << milliseconds(median(robot_times_s_))
      << ", for the frame after arrival " << milliseconds(median(frame_times_s_))
      << "; depth in the working range on " << percent(median(valid_depth_fractions_))
      << " of the view (lowest "
      << percent(*std::min_element(valid_depth_fractions_.begin(), valid_depth_fractions_.end()))
      << ", ~min_valid_depth_fraction " << percent(options_.environment.min_valid_depth_fraction)
      << ")");
  valid_depth_fractions_.clear();
  overhead_times_s_.clear();
  robot_times_s_.clear();
  frame_times_s_.clear();
}

}  // namespace occlusion_env
