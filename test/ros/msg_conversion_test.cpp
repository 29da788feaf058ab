// The ROS layer's conversions and shipped configuration, without a ROS master: depth in both of
// REP 118's encodings, observations with the masks a real camera cannot give, and the camera
// bridge's and stand-in camera's documented defaults.
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstring>
#include <string>

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

TEST(ShippedRosConfigTest, CameraBridgeYamlStatesTheDefaults) {
  const YAML::Node yaml =
      YAML::LoadFile(std::string(OCCLUSION_ENV_SOURCE_DIR) + "/config/camera_bridge.yaml");
  const CameraBridgeOptions defaults;
  EXPECT_EQ(yaml["sphere_frame"].as<std::string>(), defaults.sphere_frame);
  EXPECT_EQ(yaml["optical_frame"].as<std::string>(), defaults.optical_frame);
  EXPECT_DOUBLE_EQ(yaml["radius"].as<double>(), defaults.radius_m);
  EXPECT_NEAR(yaml["elevation_limit"].as<double>(), defaults.elevation_limit_rad, 1e-9);
  EXPECT_DOUBLE_EQ(yaml["step_size"].as<double>(), defaults.step_size_rad);
  EXPECT_EQ(yaml["normalize_action"].as<bool>(), defaults.normalize_action);
  EXPECT_EQ(yaml["max_steps"].as<int>(), defaults.max_steps);
  EXPECT_DOUBLE_EQ(yaml["position_tolerance"].as<double>(), defaults.position_tolerance_m);
  EXPECT_DOUBLE_EQ(yaml["angle_tolerance"].as<double>(), defaults.angle_tolerance_rad);
  EXPECT_DOUBLE_EQ(yaml["arrival_timeout"].as<double>(), defaults.arrival_timeout_s);
  EXPECT_DOUBLE_EQ(yaml["frame_timeout"].as<double>(), defaults.frame_timeout_s);
  EXPECT_DOUBLE_EQ(yaml["settle_time"].as<double>(), defaults.settle_time_s);
  EXPECT_DOUBLE_EQ(yaml["sync_slop"].as<double>(), defaults.sync_slop_s);
  EXPECT_DOUBLE_EQ(yaml["tf_poll_period"].as<double>(), defaults.tf_poll_period_s);
  EXPECT_EQ(yaml["square_crop"].as<bool>(), defaults.square_crop);
  EXPECT_EQ(yaml["scene_service"].as<std::string>(), defaults.scene_service);
  EXPECT_EQ(yaml["model"].as<std::string>(), defaults.model_path);
  EXPECT_DOUBLE_EQ(yaml["occlusion_probability"].as<double>(), defaults.occlusion_probability);
  EXPECT_EQ(yaml["occlusion_threshold"].as<std::int64_t>(), defaults.occlusion_threshold_px);
  EXPECT_EQ(yaml["confirm_views"].as<int>(), defaults.confirm_views);
  EXPECT_DOUBLE_EQ(yaml["success_bonus"].as<double>(), defaults.success_bonus);
  EXPECT_DOUBLE_EQ(yaml["step_penalty"].as<double>(), defaults.step_penalty);
  // Every key is a parameter the bridge reads, and every parameter is documented.
  EXPECT_EQ(yaml.size(), cameraBridgeParameterNames().size());
  for (const std::string& name : cameraBridgeParameterNames()) EXPECT_TRUE(yaml[name]) << name;
}

TEST(ShippedRosConfigTest, SimYamlStatesTheStandInCameraDefaults) {
  const YAML::Node yaml =
      YAML::LoadFile(std::string(OCCLUSION_ENV_SOURCE_DIR) + "/config/sim.yaml");
  const SimulatorOptions defaults;
  EXPECT_EQ(yaml["mode"].as<std::string>(), defaults.mode);
  EXPECT_DOUBLE_EQ(yaml["camera_rate"].as<double>(), defaults.camera_rate_hz);
  EXPECT_DOUBLE_EQ(yaml["motion_time"].as<double>(), defaults.motion_time_s);
  EXPECT_EQ(yaml["depth_encoding"].as<std::string>(), defaults.depth_encoding);
  EXPECT_DOUBLE_EQ(yaml["tf_rate"].as<double>(), defaults.tf_rate_hz);
  EXPECT_EQ(yaml["offer_gradient"].as<bool>(), defaults.offer_gradient);
  EXPECT_EQ(yaml.size(), simulatorParameterNames().size());
  for (const std::string& name : simulatorParameterNames()) EXPECT_TRUE(yaml[name]) << name;
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
  refused([](CameraBridgeOptions& o) { o.radius_m = 0.0; }, "radius");
  refused([](CameraBridgeOptions& o) { o.elevation_limit_rad = 2.0; }, "elevation_limit");
  refused([](CameraBridgeOptions& o) { o.arrival_timeout_s = 0.0; }, "arrival_timeout");
  refused([](CameraBridgeOptions& o) { o.frame_timeout_s = -1.0; }, "frame_timeout");
  refused([](CameraBridgeOptions& o) { o.occlusion_probability = 1.0; }, "occlusion_probability");
  refused([](CameraBridgeOptions& o) { o.confirm_views = 0; }, "confirm_views");
  refused([](CameraBridgeOptions& o) { o.sphere_frame.clear(); }, "sphere_frame");
}

}  // namespace
}  // namespace occlusion_env
