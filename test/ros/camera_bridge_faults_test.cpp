// The camera bridge against a scripted camera and robot (test/ros/camera_bridge_faults.test):
// this process publishes 8 x 6 RGB-D frames with tf and moves its "robot" to each goal at once,
// unless a test tells it to stop doing either.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/transform_broadcaster.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>

#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/geometry/camera.hpp"

namespace occlusion_env {
namespace {

constexpr int kWidth = 8, kHeight = 6;  // not square: the bridge crops the central 6 x 6
constexpr char kOpticalFrame[] = "test_camera_optical";

// The scripted camera and robot.
struct Rig {
  std::atomic<bool> camera_on{true};
  std::atomic<bool> robot_follows{true};
  std::atomic<bool> millimetre_depth{true};
  std::mutex mutex;
  Eigen::Isometry3d world_from_optical =
      SphericalCamera(4.0, 1.3962634016).worldFromOptical({0.0, 0.0});
};
Rig rig;

// Depth of pixel (u, v): 1.5 m, but no reading in column 1 and 2.25 m in column 5.
float depthAt(int u) {
  return u == 1 ? 0.0f : (u == 5 ? 2.25f : 1.5f);
}

void publishFrame(ros::Publisher& rgb, ros::Publisher& depth, ros::Publisher& info,
                  tf2_ros::TransformBroadcaster& tf) {
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  header.frame_id = kOpticalFrame;
  {
    std::lock_guard<std::mutex> lock(rig.mutex);
    geometry_msgs::TransformStamped transform = tf2::eigenToTransform(rig.world_from_optical);
    transform.header.stamp = header.stamp;
    transform.header.frame_id = "world";
    transform.child_frame_id = kOpticalFrame;
    tf.sendTransform(transform);  // the robot's tf goes on when the camera stops
  }
  if (!rig.camera_on) return;
  sensor_msgs::Image colour;
  colour.header = header;
  colour.width = kWidth;
  colour.height = kHeight;
  colour.encoding = sensor_msgs::image_encodings::BGR8;
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
  sensor_msgs::Image depth_image;
  depth_image.header = header;
  depth_image.width = kWidth;
  depth_image.height = kHeight;
  if (rig.millimetre_depth) {
    depth_image.encoding = sensor_msgs::image_encodings::TYPE_16UC1;
    depth_image.step = kWidth * 2;
  } else {
    depth_image.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
    depth_image.step = kWidth * 4;
  }
  depth_image.data.resize(depth_image.step * kHeight);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      std::uint8_t* out = &depth_image.data[v * depth_image.step];
      if (rig.millimetre_depth) {
        const std::uint16_t mm = static_cast<std::uint16_t>(std::lround(depthAt(u) * 1000.0f));
        std::memcpy(out + u * 2, &mm, 2);
      } else {
        const float m = u == 1 ? NAN : depthAt(u);
        std::memcpy(out + u * 4, &m, 4);
      }
    }
  }
  sensor_msgs::CameraInfo camera_info;
  camera_info.header = header;
  camera_info.width = kWidth;
  camera_info.height = kHeight;
  camera_info.K = {5.0, 0.0, 3.5, 0.0, 5.0, 2.5, 0.0, 0.0, 1.0};
  camera_info.P = {5.0, 0.0, 3.5, 0.0, 0.0, 5.0, 2.5, 0.0, 0.0, 0.0, 1.0, 0.0};
  rgb.publish(colour);
  depth.publish(depth_image);
  info.publish(camera_info);
}

void onGoal(const geometry_msgs::PoseStamped::ConstPtr& goal) {
  if (!rig.robot_follows) return;
  EXPECT_EQ(goal->header.frame_id, "world");
  std::lock_guard<std::mutex> lock(rig.mutex);
  tf2::fromMsg(goal->pose, rig.world_from_optical);
}

Reset::Response reset() {
  Reset call;
  EXPECT_TRUE(ros::service::call("/occlusion/reset", call));
  return call.response;
}

Step::Response step(double d_azimuth, double d_elevation) {
  Step call;
  call.request.action.d_azimuth = d_azimuth;
  call.request.action.d_elevation = d_elevation;
  EXPECT_TRUE(ros::service::call("/occlusion/step", call));
  return call.response;
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
