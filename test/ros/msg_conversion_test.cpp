// The ROS layer's conversions and shipped configuration, without a ROS master: depth in both of
// REP 118's encodings, observations with the masks a real camera cannot give, and the camera
// bridge's and stand-in camera's documented defaults.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <cstring>
#include <string>

#include "common/yaml_defaults.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/ros/camera_bridge.hpp"
#include "occlusion_env/ros/msg_conversion.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {
namespace {

TEST(DepthConversionTest, MillimetresRoundTripWithZeroForNoReading) {
  cv::Mat metres(2, 3, CV_32FC1);
  metres.at<float>(0, 0) = 1.2344f;  // rounds to 1234 mm
  metres.at<float>(0, 1) = NAN;      // nothing hit
  metres.at<float>(0, 2) = 70.0f;    // beyond 16 bits of millimetres
  metres.at<float>(1, 0) = 0.0f;
  metres.at<float>(1, 1) = 0.0004f;  // rounds to 0: no reading
  metres.at<float>(1, 2) = 4.0f;
  cv::Mat millimetres;
  toMillimetreDepth(metres, millimetres);
  ASSERT_EQ(millimetres.type(), CV_16UC1);
  EXPECT_EQ(millimetres.at<std::uint16_t>(0, 0), 1234);
  EXPECT_EQ(millimetres.at<std::uint16_t>(0, 1), 0);
  EXPECT_EQ(millimetres.at<std::uint16_t>(0, 2), 0);
  EXPECT_EQ(millimetres.at<std::uint16_t>(1, 0), 0);
  EXPECT_EQ(millimetres.at<std::uint16_t>(1, 1), 0);
  EXPECT_EQ(millimetres.at<std::uint16_t>(1, 2), 4000);

  sensor_msgs::Image image;
  fillImage(millimetres, std_msgs::Header(), image);
  EXPECT_EQ(image.encoding, sensor_msgs::image_encodings::TYPE_16UC1);
  cv::Mat back;
  toMetricDepth(image, back);
  ASSERT_EQ(back.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(back.at<float>(0, 0), 1.234f);
  EXPECT_TRUE(std::isnan(back.at<float>(0, 1)));
  EXPECT_TRUE(std::isnan(back.at<float>(1, 0)));
  EXPECT_FLOAT_EQ(back.at<float>(1, 2), 4.0f);
}

TEST(DepthConversionTest, MetresKeepTheirValuesAndEveryNoReadingBecomesNaN) {
  cv::Mat metres(1, 5, CV_32FC1);
  metres.at<float>(0, 0) = 2.5f;
  metres.at<float>(0, 1) = NAN;
  metres.at<float>(0, 2) = INFINITY;   // REP 118: too far
  metres.at<float>(0, 3) = -INFINITY;  // too close
  metres.at<float>(0, 4) = 0.0f;       // what some drivers send
  sensor_msgs::Image image;
  fillImage(metres, std_msgs::Header(), image);
  cv::Mat back;
  toMetricDepth(image, back);
  EXPECT_EQ(back.at<float>(0, 0), 2.5f);
  for (int u = 1; u < 5; ++u) EXPECT_TRUE(std::isnan(back.at<float>(0, u))) << u;
}

TEST(DepthConversionTest, OtherEncodingsAndShortDataAreRefused) {
  sensor_msgs::Image image;
  fillImage(cv::Mat(2, 2, CV_8UC1, cv::Scalar(1)), std_msgs::Header(), image);
  cv::Mat out;
  EXPECT_THROW(toMetricDepth(image, out), std::invalid_argument);
  fillImage(cv::Mat(2, 2, CV_32FC1, cv::Scalar(1.0f)), std_msgs::Header(), image);
  image.data.resize(4);
  EXPECT_THROW(toMetricDepth(image, out), std::invalid_argument);
  fillImage(cv::Mat(2, 2, CV_32FC1, cv::Scalar(1.0f)), std_msgs::Header(), image);
  image.is_bigendian = 1;
  EXPECT_THROW(toMetricDepth(image, out), std::invalid_argument);
}

TEST(ObservationViewTest, MasksACameraCannotGiveStayEmpty) {
  CameraObservation message;
  fillImage(cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3)), message.header, message.rgb);
  fillImage(cv::Mat(4, 4, CV_32FC1, cv::Scalar(2.0f)), message.header, message.depth);
  message.occlusion_source = CameraObservation::UNAVAILABLE;
  message.occlusion.total_pixels = -1;
  message.camera_pose.pose.orientation.w = 1.0;
  Observation observation;
  StepInfo info;
  viewObservation(message, observation, info);
  EXPECT_EQ(observation.rgb.cols, 4);
  EXPECT_TRUE(observation.instance.empty());
  EXPECT_TRUE(observation.occlusion_mask.empty());
  EXPECT_EQ(info.occlusion.total_pixels, -1);
  EXPECT_EQ(info.occlusion_source, OcclusionSource::kUnavailable);
  message.occlusion_source = CameraObservation::ESTIMATED;
  viewObservation(message, observation, info);
  EXPECT_EQ(info.occlusion_source, OcclusionSource::kEstimated);
  message.occlusion_source = CameraObservation::GROUND_TRUTH;
  viewObservation(message, observation, info);
  EXPECT_EQ(info.occlusion_source, OcclusionSource::kGroundTruth);
  // A mask with pixels must still have its encoding.
  fillImage(cv::Mat(4, 4, CV_32FC1), message.header, message.occlusion_mask);
  EXPECT_THROW(viewObservation(message, observation, info), std::invalid_argument);
}

// With the camera drawn per scene, the messages carry the drawn intrinsics (the renderer's) and
// the scene markers the scaled scene.
TEST(RandomizedCameraTest, CameraInfoAndMarkersFollowTheDrawnCamera) {
  EnvironmentOptions options;
  options.width = options.height = 96;
  options.camera_randomization.enabled = true;
  Environment environment(options);
  environment.reset(4);
  const CameraIntrinsics& k = environment.sceneSetup().intrinsics;
  const CameraIntrinsics nominal = CameraIntrinsics::fromFieldOfView(
      k.width, k.height, environment.sceneSetup().field_of_view_rad);
  ASSERT_NE(k.fx, nominal.fx);  // jittered
  ASSERT_NE(k.cx, nominal.cx);
  std_msgs::Header header;
  header.frame_id = "camera_optical";
  CameraObservation message;
  fillObservation(environment, header, "world", message);
  const sensor_msgs::CameraInfo& info = message.camera_info;
  EXPECT_EQ(info.width, static_cast<std::uint32_t>(k.width));
  EXPECT_EQ(info.height, static_cast<std::uint32_t>(k.height));
  EXPECT_EQ(info.K[0], k.fx);
  EXPECT_EQ(info.K[2], k.cx);
  EXPECT_EQ(info.K[4], k.fy);
  EXPECT_EQ(info.K[5], k.cy);
  EXPECT_EQ(info.P[0], k.fx);
  EXPECT_EQ(info.P[6], k.cy);
  EXPECT_EQ(message.rgb.width, info.width);
  Observation observation;  // what a client of the simulator's services reads back
  StepInfo view_info;
  viewObservation(message, observation, view_info);
  EXPECT_EQ(view_info.intrinsics.width, k.width);
  EXPECT_EQ(view_info.intrinsics.fx, k.fx);
  EXPECT_EQ(view_info.intrinsics.fy, k.fy);
  EXPECT_EQ(view_info.intrinsics.cx, k.cx);
  EXPECT_EQ(view_info.intrinsics.cy, k.cy);

  const visualization_msgs::MarkerArray markers = toSceneMarkers(environment.scene(), header);
  const double scale = environment.scene().scale;
  ASSERT_LT(scale, 1.0);
  const SceneObject& second = environment.scene().objects.at(1);
  EXPECT_DOUBLE_EQ(markers.markers.at(2).pose.position.x, scale * second.position_m.x());
  EXPECT_DOUBLE_EQ(markers.markers.at(2).scale.x, scale);
}

TEST(ShippedRosConfigTest, CameraBridgeYamlStatesEveryOptionWithItsDefault) {
  testing_support::expectYamlStatesDefaults(
      std::string(OCCLUSION_ENV_SOURCE_DIR) + "/config/camera_bridge.yaml",
      cameraBridgeOptionTable().toJson(CameraBridgeOptions()), /*only_these=*/true);
}

TEST(ShippedRosConfigTest, SimYamlStatesEverySimulatorOptionWithItsDefault) {
  testing_support::expectYamlStatesDefaults(
      std::string(OCCLUSION_ENV_SOURCE_DIR) + "/config/sim.yaml",
      simulatorOptionTable().toJson(SimulatorOptions()), /*only_these=*/true);
}

TEST(CameraBridgeOptionsTest, BadValuesAreRefusedByName) {
  const auto refused = [](auto change, const std::string& name) {
    CameraBridgeOptions options;
    change(options);
    try {
      options.validate();
      ADD_FAILURE() << name << " accepted";
    } catch (const ParameterError& error) {
      EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
    }
  };
  CameraBridgeOptions().validate();
  refused([](CameraBridgeOptions& o) { o.environment.radius_m = 0.0; }, "radius");
  refused([](CameraBridgeOptions& o) { o.environment.elevation_limit_rad = 2.0; },
          "elevation_limit");
  refused([](CameraBridgeOptions& o) { o.arrival_timeout_s = 0.0; }, "arrival_timeout");
  refused([](CameraBridgeOptions& o) { o.frame_timeout_s = -1.0; }, "frame_timeout");
  refused([](CameraBridgeOptions& o) { o.environment.occlusion_probability = 1.0; },
          "occlusion_probability");
  refused([](CameraBridgeOptions& o) { o.environment.confirm_views = 0; }, "confirm_views");
  refused([](CameraBridgeOptions& o) { o.sphere_frame.clear(); }, "sphere_frame");
}

}  // namespace
}  // namespace occlusion_env
