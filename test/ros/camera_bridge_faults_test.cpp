// The camera bridge against a scripted camera and robot (test/ros/camera_bridge_faults.test):
// this process publishes 8 x 6 RGB-D frames with tf and moves its "robot" to each goal at once,
// unless a test tells it to stop doing either or to send frames a bridge must not trust (blind or
// implausible depth, unsupported encodings, a camera_info that does not fit the images, a frame
// id without tf). Two bridges listen: /occlusion (no model) and /estimated (the shipped model).
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/transform_broadcaster.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <string>

#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/geometry/camera.hpp"

namespace occlusion_env {
namespace {

constexpr int kWidth = 8, kHeight = 6;  // not square: the bridge crops the central 6 x 6
constexpr char kOpticalFrame[] = "test_camera_optical";

// What the scripted camera's depth shows.
enum class DepthScene {
  kNormal,      // depthAt(u)
  kAllNaN,      // 32FC1 NaN everywhere (lens cap, too close)
  kAllZero,     // 16UC1 zero everywhere: no reading
  kMillimetres  // 32FC1 holding millimetres: 1500 "m" where 1.5 m is meant
};

// What the scripted camera's camera_info says.
enum class InfoFault { kNone, kWrongSize, kZeroK, kNaNFocalLength, kPrincipalPointOutside };

// The scripted camera and robot.
struct Rig {
  std::atomic<bool> camera_on{true};
  std::atomic<bool> robot_follows{true};
  std::atomic<bool> millimetre_depth{true};
  std::atomic<DepthScene> depth_scene{DepthScene::kNormal};
  std::atomic<InfoFault> info_fault{InfoFault::kNone};
  std::mutex mutex;
  std::string depth_encoding_override;  // not empty: depth with this encoding (mono8, 8UC3)
  std::string colour_encoding_override;
  std::string image_frame_id = "test_camera_optical";  // tf is sent for kOpticalFrame only
  std::string image_frame_id_after_goal;  // not empty: the images take this id at the next goal
  ros::Time last_goal_received;
  Eigen::Isometry3d world_from_optical =
      SphericalCamera(4.0, 1.3962634016).worldFromOptical({0.0, 0.0});
};
Rig rig;

// Restores the rig's healthy camera at the end of a test, however it ends.
struct HealthyCameraAfterwards {
  ~HealthyCameraAfterwards() {
    rig.depth_scene = DepthScene::kNormal;
    rig.info_fault = InfoFault::kNone;
    rig.millimetre_depth = true;
    std::lock_guard<std::mutex> lock(rig.mutex);
    rig.depth_encoding_override.clear();
    rig.colour_encoding_override.clear();
    rig.image_frame_id = kOpticalFrame;
    rig.image_frame_id_after_goal.clear();
  }
};

// Depth of pixel (u, v): 1.5 m, but no reading in column 1 and 2.25 m in column 5.
float depthAt(int u) {
  return u == 1 ? 0.0f : (u == 5 ? 2.25f : 1.5f);
}

sensor_msgs::Image colourImage(const std_msgs::Header& header, const std::string& encoding) {
  sensor_msgs::Image colour;
  colour.header = header;
  colour.width = kWidth;
  colour.height = kHeight;
  colour.encoding = encoding.empty() ? sensor_msgs::image_encodings::BGR8 : encoding;
  colour.step = kWidth * 3;
  colour.data.resize(colour.step * kHeight);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      std::uint8_t* pixel = &colour.data[v * colour.step + u * 3];
      pixel[0] = 10;                            // blue
      pixel[1] = 20;                            // green
      pixel[2] = static_cast<std::uint8_t>(u);  // red: the column
    }
  }
  return colour;
}

// One depth pixel [m] (NaN = no reading) in the rig's current scene.
float sceneDepth(int u, bool millimetre_depth) {
  switch (rig.depth_scene.load()) {
    case DepthScene::kAllNaN:
      return NAN;
    case DepthScene::kAllZero:
      return 0.0f;
    case DepthScene::kMillimetres:
      return depthAt(u) * 1000.0f;
    case DepthScene::kNormal:
      break;
  }
  return u == 1 && !millimetre_depth ? NAN : depthAt(u);
}

sensor_msgs::Image depthImage(const std_msgs::Header& header, const std::string& encoding) {
  namespace enc = sensor_msgs::image_encodings;
  const bool millimetre_depth = rig.depth_scene == DepthScene::kAllZero ||
                                (rig.millimetre_depth && rig.depth_scene == DepthScene::kNormal);
  sensor_msgs::Image depth_image;
  depth_image.header = header;
  depth_image.width = kWidth;
  depth_image.height = kHeight;
  depth_image.encoding = millimetre_depth ? enc::TYPE_16UC1 : enc::TYPE_32FC1;
  depth_image.step = kWidth * (millimetre_depth ? 2 : 4);
  depth_image.data.resize(depth_image.step * kHeight);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      std::uint8_t* out = &depth_image.data[v * depth_image.step];
      const float m = sceneDepth(u, millimetre_depth);
      if (millimetre_depth) {
        const std::uint16_t mm = static_cast<std::uint16_t>(std::lround(m * 1000.0f));
        std::memcpy(out + u * 2, &mm, 2);
      } else {
        std::memcpy(out + u * 4, &m, 4);
      }
    }
  }
  if (!encoding.empty()) {  // the same bytes under another name, sized for it
    depth_image.encoding = encoding;
    depth_image.step = kWidth * enc::numChannels(encoding) * enc::bitDepth(encoding) / 8;
    depth_image.data.resize(depth_image.step * kHeight);
  }
  return depth_image;
}

sensor_msgs::CameraInfo cameraInfo(const std_msgs::Header& header) {
  sensor_msgs::CameraInfo camera_info;
  camera_info.header = header;
  camera_info.width = kWidth;
  camera_info.height = kHeight;
  camera_info.K = {5.0, 0.0, 3.5, 0.0, 5.0, 2.5, 0.0, 0.0, 1.0};
  camera_info.P = {5.0, 0.0, 3.5, 0.0, 0.0, 5.0, 2.5, 0.0, 0.0, 0.0, 1.0, 0.0};
  switch (rig.info_fault.load()) {
    case InfoFault::kWrongSize:  // calibrated at another resolution
      camera_info.width = 16;
      camera_info.height = 12;
      break;
    case InfoFault::kZeroK:
      camera_info.K.fill(0.0);
      break;
    case InfoFault::kNaNFocalLength:
      camera_info.K[0] = NAN;
      break;
    case InfoFault::kPrincipalPointOutside:
      camera_info.K[2] = 100.0;
      break;
    case InfoFault::kNone:
      break;
  }
  return camera_info;
}

void publishFrame(ros::Publisher& rgb, ros::Publisher& depth, ros::Publisher& info,
                  tf2_ros::TransformBroadcaster& tf) {
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  std::string colour_encoding, depth_encoding;
  {
    std::lock_guard<std::mutex> lock(rig.mutex);
    header.frame_id = rig.image_frame_id;
    colour_encoding = rig.colour_encoding_override;
    depth_encoding = rig.depth_encoding_override;
    geometry_msgs::TransformStamped transform = tf2::eigenToTransform(rig.world_from_optical);
    transform.header.stamp = header.stamp;
    transform.header.frame_id = "world";
    transform.child_frame_id = kOpticalFrame;
    tf.sendTransform(transform);  // the robot's tf goes on when the camera stops
  }
  if (!rig.camera_on) return;
  rgb.publish(colourImage(header, colour_encoding));
  depth.publish(depthImage(header, depth_encoding));
  info.publish(cameraInfo(header));
}

void onGoal(const geometry_msgs::PoseStamped::ConstPtr& goal) {
  if (!rig.robot_follows) return;
  EXPECT_EQ(goal->header.frame_id, "world");
  std::lock_guard<std::mutex> lock(rig.mutex);
  rig.last_goal_received = ros::Time::now();
  if (!rig.image_frame_id_after_goal.empty()) {
    rig.image_frame_id = rig.image_frame_id_after_goal;
    rig.image_frame_id_after_goal.clear();
  }
  tf2::fromMsg(goal->pose, rig.world_from_optical);
}

// `bridge`: the namespace of the bridge asked ("/occlusion": no model; "/estimated/occlusion":
// the shipped model).
Reset::Response reset(const std::string& bridge = "/occlusion") {
  Reset call;
  EXPECT_TRUE(ros::service::call(bridge + "/reset", call));
  return call.response;
}

Step::Response step(double d_azimuth, double d_elevation,
                    const std::string& bridge = "/occlusion") {
  Step call;
  call.request.action.d_azimuth = d_azimuth;
  call.request.action.d_elevation = d_elevation;
  EXPECT_TRUE(ros::service::call(bridge + "/step", call));
  return call.response;
}

bool mentions(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

float depthPixel(const CameraObservation& observation, int u, int v) {
  float value;
  std::memcpy(&value, &observation.depth.data[v * observation.depth.step + u * 4], 4);
  return value;
}

TEST(CameraBridgeFaults, StepBeforeResetIsRefused) {
  ASSERT_TRUE(ros::service::waitForService("/occlusion/step", ros::Duration(20.0)));
  EXPECT_EQ(step(1.0, 0.0).status.code, Status::INVALID_STATE);
}

void expectConvertedFrame(const CameraObservation& observation) {
  // The central 6 x 6 of the 8 x 6 frame: columns 1..6; as rgb8, metres and NaN.
  EXPECT_EQ(observation.rgb.width, 6u);
  EXPECT_EQ(observation.rgb.height, 6u);
  EXPECT_EQ(observation.rgb.encoding, "rgb8");
  EXPECT_EQ(observation.rgb.data[0], 1);  // red of column 1
  EXPECT_EQ(observation.rgb.data[2], 10);
  EXPECT_EQ(observation.depth.encoding, "32FC1");
  EXPECT_TRUE(std::isnan(depthPixel(observation, 0, 0)));  // column 1: no reading
  EXPECT_FLOAT_EQ(depthPixel(observation, 1, 3), 1.5f);
  EXPECT_FLOAT_EQ(depthPixel(observation, 4, 5), 2.25f);  // column 5
  EXPECT_DOUBLE_EQ(observation.camera_info.K[2], 2.5);    // principal point moved with the crop
  EXPECT_EQ(observation.camera_info.width, 6u);
  // Without a model nothing of the occlusion is known.
  EXPECT_EQ(observation.occlusion_source, CameraObservation::UNAVAILABLE);
  EXPECT_EQ(observation.occlusion.total_pixels, -1);
  EXPECT_EQ(observation.occlusion_mask.width, 0u);
  EXPECT_EQ(observation.instance_mask.width, 0u);
}

TEST(CameraBridgeFaults, MillimetreDepthIsConvertedAndStepsMoveTheCamera) {
  rig.millimetre_depth = true;
  const Reset::Response start = reset();
  ASSERT_EQ(start.status.code, Status::OK) << start.status.message;
  expectConvertedFrame(start.observation);
  EXPECT_EQ(start.observation.step_index, 0);
  EXPECT_NEAR(start.observation.azimuth, 0.0, 1e-9);

  const Step::Response first = step(3.0, 4.0);
  ASSERT_EQ(first.status.code, Status::OK) << first.status.message;
  EXPECT_EQ(first.observation.step_index, 1);
  EXPECT_NEAR(first.observation.azimuth, 0.05 * 0.6, 1e-9);
  EXPECT_NEAR(first.observation.elevation, 0.05 * 0.8, 1e-9);
  EXPECT_GT(first.observation.header.stamp, start.observation.header.stamp);
  EXPECT_FALSE(first.terminated);  // unknown occlusion never ends an episode ...
  EXPECT_FALSE(first.truncated);
  EXPECT_EQ(first.reward, 0.0);
  step(1.0, 0.0);
  EXPECT_TRUE(step(1.0, 0.0).truncated);  // ... the step limit (3) does
  EXPECT_EQ(step(1.0, 0.0).status.code, Status::INVALID_STATE);
}

TEST(CameraBridgeFaults, MetreDepthIsPassedOnWithNaNForNoReading) {
  rig.millimetre_depth = false;
  const Reset::Response start = reset();
  ASSERT_EQ(start.status.code, Status::OK) << start.status.message;
  expectConvertedFrame(start.observation);
  rig.millimetre_depth = true;
}

TEST(CameraBridgeFaults, RobotThatNeverArrivesIsAnErrorAndTheEpisodeGoesOn) {
  ASSERT_EQ(reset().status.code, Status::OK);
  const Step::Response moved = step(1.0, 0.0);
  ASSERT_EQ(moved.status.code, Status::OK);
  rig.robot_follows = false;
  const ros::WallTime asked = ros::WallTime::now();
  const Step::Response stuck = step(1.0, 0.0);
  const double waited = (ros::WallTime::now() - asked).toSec();
  EXPECT_EQ(stuck.status.code, Status::UNAVAILABLE);
  EXPECT_NE(stuck.status.message.find("did not reach the goal"), std::string::npos)
      << stuck.status.message;
  EXPECT_GE(waited, 0.9);  // ~arrival_timeout 1 s
  EXPECT_LT(waited, 5.0);
  // The robot comes back: the next step counts on from the last good one, from where the
  // camera really is.
  rig.robot_follows = true;
  const Step::Response next = step(1.0, 0.0);
  ASSERT_EQ(next.status.code, Status::OK) << next.status.message;
  EXPECT_EQ(next.observation.step_index, moved.observation.step_index + 1);
  EXPECT_NEAR(next.observation.azimuth, moved.observation.azimuth + 0.05, 1e-9);
}

TEST(CameraBridgeFaults, CameraThatStopsPublishingIsAnErrorAndTheNodeStaysUp) {
  ASSERT_EQ(reset().status.code, Status::OK);
  rig.camera_on = false;
  ros::WallDuration(0.2).sleep();
  const Step::Response lost = step(0.0, 1.0);
  EXPECT_EQ(lost.status.code, Status::UNAVAILABLE);
  EXPECT_NE(lost.status.message.find("no synchronised RGB-D frame"), std::string::npos)
      << lost.status.message;
  const Reset::Response no_reset = reset();
  EXPECT_EQ(no_reset.status.code, Status::UNAVAILABLE);
  rig.camera_on = true;
  EXPECT_TRUE(ros::service::exists("/occlusion/step", false));
  const Reset::Response again = reset();
  ASSERT_EQ(again.status.code, Status::OK) << again.status.message;
  EXPECT_EQ(step(0.0, 1.0).status.code, Status::OK);
}

TEST(CameraBridgeFaults, NonFiniteActionIsRefused) {
  ASSERT_EQ(reset().status.code, Status::OK);
  EXPECT_EQ(step(NAN, 0.0).status.code, Status::INVALID_ARGUMENT);
  EXPECT_EQ(step(0.0, 1.0).observation.step_index, 1);
}

// --- Frames a bridge must not trust -------------------------------------------------------------

// Sets the rig's depth to `scene` and waits until the bridge has frames of it.
void showDepth(DepthScene scene) {
  rig.depth_scene = scene;
  ros::WallDuration(0.2).sleep();
}

TEST(CameraBridgeFaults, BlindDepthIsUnavailableNeverAView) {
  HealthyCameraAfterwards restore;
  for (const DepthScene blind : {DepthScene::kAllNaN, DepthScene::kAllZero}) {
    showDepth(blind);
    const Reset::Response start = reset();
    EXPECT_EQ(start.status.code, Status::UNAVAILABLE) << start.status.message;
    EXPECT_TRUE(mentions(start.status.message, "no valid depth")) << start.status.message;
  }
  // Within an episode: the step is refused and the episode goes on from the last good view.
  showDepth(DepthScene::kNormal);
  ASSERT_EQ(reset().status.code, Status::OK);
  const Step::Response good = step(1.0, 0.0);
  ASSERT_EQ(good.status.code, Status::OK) << good.status.message;
  showDepth(DepthScene::kAllNaN);
  const Step::Response blind = step(1.0, 0.0);
  EXPECT_EQ(blind.status.code, Status::UNAVAILABLE) << blind.status.message;
  EXPECT_FALSE(blind.terminated);
  showDepth(DepthScene::kNormal);
  const Step::Response next = step(1.0, 0.0);
  ASSERT_EQ(next.status.code, Status::OK) << next.status.message;
  EXPECT_EQ(next.observation.step_index, good.observation.step_index + 1);
}

TEST(CameraBridgeFaults, DepthFarOutsideTheWorkingRangeIsUnavailable) {
  HealthyCameraAfterwards restore;
  showDepth(DepthScene::kMillimetres);  // 1500 "m" on a sphere of 4 m
  const Reset::Response start = reset();
  EXPECT_EQ(start.status.code, Status::UNAVAILABLE) << start.status.message;
  EXPECT_TRUE(mentions(start.status.message, "working range")) << start.status.message;
}

TEST(CameraBridgeFaults, CameraInfoThatDoesNotFitTheImagesIsInvalidInput) {
  HealthyCameraAfterwards restore;
  const std::pair<InfoFault, std::string> faults[] = {
      {InfoFault::kWrongSize, "16 x 12"},
      {InfoFault::kZeroK, "focal length"},
      {InfoFault::kNaNFocalLength, "focal length"},
      {InfoFault::kPrincipalPointOutside, "principal point"}};
  for (const auto& [fault, named] : faults) {
    rig.info_fault = fault;
    ros::WallDuration(0.2).sleep();
    const Reset::Response start = reset();
    EXPECT_EQ(start.status.code, Status::INVALID_ARGUMENT) << named << ": " << start.status.message;
    EXPECT_TRUE(mentions(start.status.message, "camera_info")) << start.status.message;
    EXPECT_TRUE(mentions(start.status.message, named)) << start.status.message;
  }
  rig.info_fault = InfoFault::kNone;
  ros::WallDuration(0.2).sleep();
  EXPECT_EQ(reset().status.code, Status::OK);
}

TEST(CameraBridgeFaults, UnsupportedEncodingsAreInvalidInputNamingTheSupportedOnes) {
  HealthyCameraAfterwards restore;
  for (const std::string encoding : {"mono8", "8UC3"}) {
    {
      std::lock_guard<std::mutex> lock(rig.mutex);
      rig.depth_encoding_override = encoding;
    }
    ros::WallDuration(0.2).sleep();
    const Reset::Response start = reset();
    EXPECT_EQ(start.status.code, Status::INVALID_ARGUMENT) << start.status.message;
    EXPECT_TRUE(mentions(start.status.message, "depth image encoding '" + encoding + "'"))
        << start.status.message;
    EXPECT_TRUE(mentions(start.status.message, "16UC1")) << start.status.message;
    EXPECT_TRUE(mentions(start.status.message, "32FC1")) << start.status.message;
  }
  {
    std::lock_guard<std::mutex> lock(rig.mutex);
    rig.depth_encoding_override.clear();
    rig.colour_encoding_override = "rgba8";
  }
  ros::WallDuration(0.2).sleep();
  const Reset::Response start = reset();
  EXPECT_EQ(start.status.code, Status::INVALID_ARGUMENT) << start.status.message;
  EXPECT_TRUE(mentions(start.status.message, "rgba8")) << start.status.message;
  EXPECT_TRUE(mentions(start.status.message, "rgb8")) << start.status.message;
}

// A step whose answer names `frame_id` as having no tf, at once.
void expectFrameWithoutTfNamedAtOnce(const std::string& frame_id) {
  const ros::WallTime asked = ros::WallTime::now();
  const Step::Response moved = step(1.0, 0.0);
  const double waited = (ros::WallTime::now() - asked).toSec();
  EXPECT_EQ(moved.status.code, Status::UNAVAILABLE) << moved.status.message;
  EXPECT_TRUE(mentions(moved.status.message, frame_id)) << moved.status.message;
  EXPECT_TRUE(mentions(moved.status.message, "no transform")) << moved.status.message;
  EXPECT_FALSE(mentions(moved.status.message, "did not reach the goal")) << moved.status.message;
  EXPECT_LT(waited, 0.9);  // at once, not after ~arrival_timeout (1 s)
}

TEST(CameraBridgeFaults, FrameIdWithoutTfIsNamedAtOnce) {
  HealthyCameraAfterwards restore;
  // A driver restarted with other frame names while the robot moves: named, not blamed on the
  // robot after the arrival timeout.
  ASSERT_EQ(reset().status.code, Status::OK);
  {
    std::lock_guard<std::mutex> lock(rig.mutex);
    rig.image_frame_id_after_goal = "camera_depth_optical_frame";
  }
  expectFrameWithoutTfNamedAtOnce("camera_depth_optical_frame");
  // Between steps, and at a reset.
  ros::WallDuration(0.2).sleep();
  expectFrameWithoutTfNamedAtOnce("camera_depth_optical_frame");
  const Reset::Response again = reset();
  EXPECT_EQ(again.status.code, Status::UNAVAILABLE) << again.status.message;
  EXPECT_TRUE(mentions(again.status.message, "camera_depth_optical_frame")) << again.status.message;
}

// --- The bridge with the shipped model (/estimated): every view counts as clear there
// (occlusion_threshold 10^9 px), confirm_views 2, settle_time 0.2 s ---------------------------

constexpr char kEstimated[] = "/estimated/occlusion";

TEST(CameraBridgeEstimated, TheResetViewDoesNotConfirm) {
  HealthyCameraAfterwards restore;
  ASSERT_TRUE(ros::service::waitForService(std::string(kEstimated) + "/step", ros::Duration(30)));
  const Reset::Response start = reset(kEstimated);
  ASSERT_EQ(start.status.code, Status::OK) << start.status.message;
  EXPECT_EQ(start.observation.occlusion_source, CameraObservation::ESTIMATED);
  const Step::Response first = step(1.0, 0.0, kEstimated);
  ASSERT_EQ(first.status.code, Status::OK) << first.status.message;
  EXPECT_FALSE(first.terminated) << "the reset view counted as a confirming view";
  const Step::Response second = step(1.0, 0.0, kEstimated);
  ASSERT_EQ(second.status.code, Status::OK) << second.status.message;
  EXPECT_TRUE(second.terminated);  // two clear views after the reset
}

TEST(CameraBridgeEstimated, BlindCameraNeverReportsSuccess) {
  HealthyCameraAfterwards restore;
  ASSERT_EQ(reset(kEstimated).status.code, Status::OK);
  ASSERT_EQ(step(1.0, 0.0, kEstimated).status.code, Status::OK);
  showDepth(DepthScene::kAllNaN);
  for (int i = 0; i < 3; ++i) {
    const Step::Response blind = step(1.0, 0.0, kEstimated);
    EXPECT_EQ(blind.status.code, Status::UNAVAILABLE) << blind.status.message;
    EXPECT_FALSE(blind.terminated);
    EXPECT_NE(blind.observation.occlusion_source, CameraObservation::ESTIMATED);
  }
}

TEST(CameraBridgeEstimated, TheFrameIsTakenSettleTimeAfterArrival) {
  ASSERT_EQ(reset(kEstimated).status.code, Status::OK);
  const Step::Response moved = step(0.0, 1.0, kEstimated);
  ASSERT_EQ(moved.status.code, Status::OK) << moved.status.message;
  ros::Time goal_received;
  {
    std::lock_guard<std::mutex> lock(rig.mutex);
    goal_received = rig.last_goal_received;
  }
  // The rig's robot is there as the goal arrives: the frame is at least settle_time later.
  EXPECT_GE((moved.observation.header.stamp - goal_received).toSec(), 0.2 - 0.005);
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "camera_bridge_faults_test");
  ros::NodeHandle node("occlusion");
  ros::Publisher rgb = node.advertise<sensor_msgs::Image>("rgb/image_raw", 5);
  ros::Publisher depth = node.advertise<sensor_msgs::Image>("depth/image_raw", 5);
  ros::Publisher info = node.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 5);
  ros::Subscriber goals = node.subscribe("camera_goal", 10, &occlusion_env::onGoal);
  tf2_ros::TransformBroadcaster tf;
  const ros::Timer camera = node.createTimer(ros::Duration(0.02), [&](const ros::TimerEvent&) {
    occlusion_env::publishFrame(rgb, depth, info, tf);
  });
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
