// The simulator node's contract, checked from a client node against an in-process Environment
// built from the node's own parameters. Tests run in declaration order: the first one needs a
// node that has not been reset yet.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <mutex>

#include "occlusion_env/CameraMove.h"
#include "occlusion_env/GetOcclusionGradient.h"
#include "occlusion_env/Reset.h"
#include "occlusion_env/Step.h"
#include "occlusion_env/StepOutcome.h"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"
#include "occlusion_env/ros/names.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {
namespace {

constexpr int kSize = 128;  // the .test file's width and height [px]

ros::NodeHandle& publicNode() {
  static ros::NodeHandle node(names::kNamespace);
  return node;
}

Reset::Response callReset(Reset::Request request) {
  Reset reset;
  reset.request = std::move(request);
  EXPECT_TRUE(ros::service::call(publicNode().resolveName(names::kResetService), reset));
  return reset.response;
}

Reset::Response callReset(std::uint64_t seed) {
  Reset::Request request;
  request.seed = seed;
  return callReset(request);
}

Step::Response callStep(double d_azimuth, double d_elevation) {
  Step step;
  step.request.action.d_azimuth = d_azimuth;
  step.request.action.d_elevation = d_elevation;
  EXPECT_TRUE(ros::service::call(publicNode().resolveName(names::kStepService), step));
  return step.response;
}

GetOcclusionGradient::Response callGradient(std::uint8_t method) {
  GetOcclusionGradient gradient;
  gradient.request.method = method;
  EXPECT_TRUE(ros::service::call(publicNode().resolveName(names::kGradientService), gradient));
  return gradient.response;
}

// The options the node runs with, read from its private namespace.
const SimulatorOptions& nodeOptions() {
  static const SimulatorOptions options =
      readSimulatorOptions(ros::NodeHandle(std::string("/") + names::kSimulatorNode));
  return options;
}

// The in-process reference, built on the test thread (its GL context stays there).
Environment& localEnvironment() {
  static Environment environment(nodeOptions().environment);
  return environment;
}

bool sameBytes(const sensor_msgs::Image& image, const cv::Mat& mat) {
  const std::size_t bytes = mat.total() * mat.elemSize();
  return mat.isContinuous() && image.data.size() == bytes &&
         std::memcmp(image.data.data(), mat.data, bytes) == 0;
}

void expectImage(const sensor_msgs::Image& image, const std::string& encoding,
                 int bytes_per_pixel) {
  EXPECT_EQ(image.encoding, encoding);
  EXPECT_EQ(image.width, static_cast<std::uint32_t>(kSize));
  EXPECT_EQ(image.height, static_cast<std::uint32_t>(kSize));
  EXPECT_EQ(image.step, static_cast<std::uint32_t>(kSize * bytes_per_pixel));
  EXPECT_EQ(image.data.size(), static_cast<std::size_t>(kSize * kSize * bytes_per_pixel));
  EXPECT_EQ(image.header.frame_id, names::kOpticalFrame);
}

// The response's observation equals the local environment's current one, bit for bit.
void expectMatchesLocal(const CameraObservation& observation) {
  const Environment& local = localEnvironment();
  expectImage(observation.rgb, "rgb8", 3);
  expectImage(observation.depth, "32FC1", 4);
  expectImage(observation.occlusion_mask, "mono8", 1);
  expectImage(observation.instance_mask, "mono8", 1);
  EXPECT_TRUE(sameBytes(observation.rgb, local.observation().rgb));
  EXPECT_TRUE(sameBytes(observation.depth, local.observation().depth));
  EXPECT_TRUE(sameBytes(observation.occlusion_mask, local.observation().occlusion_mask));
  EXPECT_TRUE(sameBytes(observation.instance_mask, local.observation().instance));

  EXPECT_EQ(observation.header.frame_id, names::kOpticalFrame);
  EXPECT_EQ(observation.camera_info.header.frame_id, names::kOpticalFrame);
  EXPECT_EQ(observation.camera_info.width, static_cast<std::uint32_t>(kSize));
  EXPECT_DOUBLE_EQ(observation.camera_info.K[0], local.intrinsics().fx);
  EXPECT_DOUBLE_EQ(observation.camera_info.K[2], local.intrinsics().cx);
  EXPECT_DOUBLE_EQ(observation.camera_info.K[4], local.intrinsics().fy);
  EXPECT_DOUBLE_EQ(observation.camera_info.K[5], local.intrinsics().cy);

  const StepInfo& info = local.info();
  EXPECT_EQ(observation.camera_pose.header.frame_id, names::kWorldFrame);
  const Eigen::Vector3d position = info.world_from_optical.translation();
  EXPECT_NEAR(observation.camera_pose.pose.position.x, position.x(), 1e-9);
  EXPECT_NEAR(observation.camera_pose.pose.position.y, position.y(), 1e-9);
  EXPECT_NEAR(observation.camera_pose.pose.position.z, position.z(), 1e-9);
  EXPECT_DOUBLE_EQ(observation.azimuth, info.pose.azimuth_rad);
  EXPECT_DOUBLE_EQ(observation.elevation, info.pose.elevation_rad);
  EXPECT_EQ(observation.step_index, info.step_index);

  EXPECT_EQ(observation.occlusion.total_pixels, info.occlusion.total_pixels);
  EXPECT_EQ(observation.occlusion.occluded_area_pixels, info.occlusion.occluded_area_pixels);
  EXPECT_EQ(observation.occlusion.union_pixels, info.occlusion.union_pixels);
  ASSERT_EQ(observation.occlusion.pairs.size(), info.occlusion.pairs.size());
  for (std::size_t p = 0; p < info.occlusion.pairs.size(); ++p) {
    EXPECT_EQ(observation.occlusion.pairs[p].first, info.occlusion.pairs[p].first);
    EXPECT_EQ(observation.occlusion.pairs[p].second, info.occlusion.pairs[p].second);
    EXPECT_EQ(observation.occlusion.pairs[p].pixels, info.occlusion.pairs[p].pixels);
  }
  ASSERT_EQ(observation.object_ids.size(), local.scene().objects.size());
  for (std::size_t k = 0; k < observation.object_ids.size(); ++k) {
    EXPECT_EQ(observation.object_ids[k], local.scene().objects[k].model->info.id);
    EXPECT_EQ(observation.object_categories[k], local.scene().objects[k].model->info.category);
  }
}

// Waits up to `seconds` for `done`, spinning in the background meanwhile.
template <typename Predicate>
bool waitFor(Predicate done, double seconds) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(seconds);
  while (!done()) {
    if (ros::WallTime::now() > deadline) return false;
    ros::WallDuration(0.01).sleep();
  }
  return true;
}

TEST(SimulatorNode, StepBeforeAnyResetIsRefused) {
  const Step::Response response = callStep(1.0, 0.0);
  EXPECT_EQ(response.status.code, Status::INVALID_STATE);
  EXPECT_NE(response.status.message.find("reset"), std::string::npos) << response.status.message;
  const GetOcclusionGradient::Response gradient =
      callGradient(GetOcclusionGradient::Request::DEFAULT);
  EXPECT_EQ(gradient.status.code, Status::INVALID_STATE);
  EXPECT_FALSE(gradient.valid);
}

TEST(SimulatorNode, ResetAndStepMatchTheInProcessEnvironment) {
  const Reset::Response reset = callReset(7);
  ASSERT_EQ(reset.status.code, Status::OK) << reset.status.message;
  EXPECT_TRUE(reset.status.message.empty());
  localEnvironment().reset(7);
  expectMatchesLocal(reset.observation);
  EXPECT_GT(reset.observation.occlusion.total_pixels, 0);  // scenes start occluded

  for (int t = 1; t <= 3; ++t) {
    const Step::Response step = callStep(1.0, 0.3);
    ASSERT_EQ(step.status.code, Status::OK) << step.status.message;
    const StepResult local = localEnvironment().step({1.0, 0.3});
    EXPECT_DOUBLE_EQ(step.reward, local.reward);
    EXPECT_EQ(step.terminated, local.terminated);
    EXPECT_EQ(step.truncated, local.truncated);
    EXPECT_EQ(step.occlusion_pixels, local.info.occlusion.total_pixels);
    EXPECT_EQ(step.occlusion_pixels, step.observation.occlusion.total_pixels);
    EXPECT_EQ(step.observation.step_index, t);
    expectMatchesLocal(step.observation);
  }
}

TEST(SimulatorNode, GradientServiceMatchesTheInProcessGradients) {
  ASSERT_EQ(callReset(7).status.code, Status::OK);
  localEnvironment().reset(7);
  const struct {
    std::uint8_t method;
    std::string name;
  } methods[] = {
      {GetOcclusionGradient::Request::DEFAULT, nodeOptions().environment.gradient_method},
      {GetOcclusionGradient::Request::ANALYTIC, "analytic"},
      {GetOcclusionGradient::Request::FINITE_DIFFERENCE, "finite_difference"}};
  for (const auto& method : methods) {
    SCOPED_TRACE(method.name);
    const GetOcclusionGradient::Response response = callGradient(method.method);
    ASSERT_EQ(response.status.code, Status::OK) << response.status.message;
    EXPECT_EQ(response.method_name, method.name);
    const GradientResult local =
        makeOcclusionGradient(method.name, nodeOptions().environment.gradient)
            ->compute(localEnvironment());
    EXPECT_EQ(response.valid, local.valid);
    EXPECT_EQ(response.reason, local.reason);
    EXPECT_DOUBLE_EQ(response.loss, local.loss);
    EXPECT_DOUBLE_EQ(response.d_azimuth, local.gradient.x());
    EXPECT_DOUBLE_EQ(response.d_elevation, local.gradient.y());
    EXPECT_TRUE(response.valid);  // seed 7 starts occluded
    EXPECT_GT(response.loss, 0.0);
  }
  // The service leaves the episode as it was.
  const Step::Response step = callStep(1.0, 0.3);
  localEnvironment().step({1.0, 0.3});
  expectMatchesLocal(step.observation);

  const GetOcclusionGradient::Response bad = callGradient(9);
  EXPECT_EQ(bad.status.code, Status::INVALID_ARGUMENT);
  EXPECT_NE(bad.status.message.find("method"), std::string::npos) << bad.status.message;
  EXPECT_FALSE(bad.valid);
  EXPECT_EQ(bad.d_azimuth, 0.0);
}

TEST(SimulatorNode, SameSeedGivesTheSameScene) {
  const Reset::Response first = callReset(11);
  const Reset::Response second = callReset(11);
  ASSERT_EQ(first.status.code, Status::OK);
  ASSERT_EQ(second.status.code, Status::OK);
  EXPECT_EQ(first.observation.rgb.data, second.observation.rgb.data);
  EXPECT_EQ(first.observation.depth.data, second.observation.depth.data);
  EXPECT_EQ(first.observation.object_ids, second.observation.object_ids);
  EXPECT_EQ(first.observation.occlusion.total_pixels, second.observation.occlusion.total_pixels);
  EXPECT_DOUBLE_EQ(first.observation.azimuth, second.observation.azimuth);
  const Reset::Response other = callReset(12);
  ASSERT_EQ(other.status.code, Status::OK);
  EXPECT_NE(first.observation.rgb.data, other.observation.rgb.data);
}

TEST(SimulatorNode, EveryTopicIsPublishedWithTheRightTypeAndSize) {
  ros::NodeHandle& node = publicNode();
  std::mutex mutex;
  std::map<std::string, sensor_msgs::Image> images;
  std::map<std::string, sensor_msgs::CameraInfo> infos;
  visualization_msgs::MarkerArray markers;
  std::atomic<bool> have_markers{false};
  std::vector<ros::Subscriber> subscribers;
  for (const char* topic : {names::kRgbImageTopic, names::kDepthImageTopic,
                            names::kOcclusionMaskTopic, names::kInstanceMaskTopic}) {
    const std::string name = topic;
    subscribers.push_back(node.subscribe<sensor_msgs::Image>(
        name, 1, [&, name](const sensor_msgs::Image::ConstPtr& image) {
          std::lock_guard<std::mutex> lock(mutex);
          images[name] = *image;
        }));
  }
  for (const char* topic :
       {names::kRgbCameraInfoTopic, names::kDepthCameraInfoTopic,
        names::kOcclusionMaskCameraInfoTopic, names::kInstanceMaskCameraInfoTopic}) {
    const std::string name = topic;
    subscribers.push_back(node.subscribe<sensor_msgs::CameraInfo>(
        name, 1, [&, name](const sensor_msgs::CameraInfo::ConstPtr& info) {
          std::lock_guard<std::mutex> lock(mutex);
          infos[name] = *info;
        }));
  }
  subscribers.push_back(node.subscribe<visualization_msgs::MarkerArray>(
      names::kSceneMarkersTopic, 1, [&](const visualization_msgs::MarkerArray::ConstPtr& array) {
        std::lock_guard<std::mutex> lock(mutex);
        markers = *array;
        have_markers = true;
      }));

  // The node builds image messages only for connected subscribers (and sends each new one the
  // current view): reset until every topic has the reset's view.
  Reset::Response reset;
  const bool received = waitFor(
      [&] {
        reset = callReset(5);
        ros::Duration(0.1).sleep();
        std::lock_guard<std::mutex> lock(mutex);
        const ros::Time stamp = reset.observation.header.stamp;
        const auto current = [&stamp](const auto& entry) {
          return entry.second.header.stamp == stamp;
        };
        return images.size() == 4 && infos.size() == 4 && have_markers &&
               std::all_of(images.begin(), images.end(), current) &&
               std::all_of(infos.begin(), infos.end(), current);
      },
      20.0);
  ASSERT_TRUE(received) << images.size() << " image topics, " << infos.size() << " infos";
  ASSERT_EQ(reset.status.code, Status::OK);

  std::lock_guard<std::mutex> lock(mutex);
  expectImage(images[names::kRgbImageTopic], "rgb8", 3);
  expectImage(images[names::kDepthImageTopic], "32FC1", 4);
  expectImage(images[names::kOcclusionMaskTopic], "mono8", 1);
  expectImage(images[names::kInstanceMaskTopic], "mono8", 1);
  EXPECT_EQ(images[names::kRgbImageTopic].data, reset.observation.rgb.data);
  for (const auto& entry : infos) {
    EXPECT_EQ(entry.second.width, static_cast<std::uint32_t>(kSize)) << entry.first;
    EXPECT_EQ(entry.second.height, static_cast<std::uint32_t>(kSize)) << entry.first;
    EXPECT_EQ(entry.second.header.frame_id, names::kOpticalFrame) << entry.first;
    EXPECT_EQ(entry.second.K, reset.observation.camera_info.K) << entry.first;
  }
  // Depth: metres where an object is hit, NaN elsewhere.
  const auto* depth = reinterpret_cast<const float*>(images[names::kDepthImageTopic].data.data());
  int hits = 0, misses = 0;
  for (int i = 0; i < kSize * kSize; ++i) {
    if (std::isnan(depth[i])) {
      ++misses;
    } else {
      ++hits;
      EXPECT_GT(depth[i], 0.0f);
    }
  }
  EXPECT_GT(hits, 0);
  EXPECT_GT(misses, 0);

  // DELETEALL, then one TRIANGLE_LIST with vertex colours per object.
  ASSERT_EQ(markers.markers.size(), reset.observation.object_ids.size() + 1);
  EXPECT_EQ(markers.markers[0].action, visualization_msgs::Marker::DELETEALL);
  for (std::size_t k = 1; k < markers.markers.size(); ++k) {
    const visualization_msgs::Marker& marker = markers.markers[k];
    EXPECT_EQ(marker.type, visualization_msgs::Marker::TRIANGLE_LIST);
    EXPECT_EQ(marker.header.frame_id, names::kWorldFrame);
    EXPECT_GT(marker.points.size(), 0u);
    EXPECT_EQ(marker.points.size() % 3, 0u);
    EXPECT_EQ(marker.colors.size(), marker.points.size());
  }
}

TEST(SimulatorNode, TfGivesTheCameraPose) {
  const Reset::Response reset = callReset(9);
  ASSERT_EQ(reset.status.code, Status::OK);
  const Step::Response step = callStep(0.0, 1.0);
  ASSERT_EQ(step.status.code, Status::OK);
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  std::string error;
  ASSERT_TRUE(buffer.canTransform(names::kWorldFrame, names::kOpticalFrame, ros::Time(0),
                                  ros::Duration(5.0), &error))
      << error;
  // The latest transform is the re-broadcast of the current pose (the step's).
  ros::Duration(0.2).sleep();
  const geometry_msgs::TransformStamped transform =
      buffer.lookupTransform(names::kWorldFrame, names::kOpticalFrame, ros::Time(0));
  const geometry_msgs::Pose& pose = step.observation.camera_pose.pose;
  EXPECT_NEAR(transform.transform.translation.x, pose.position.x, 1e-6);
  EXPECT_NEAR(transform.transform.translation.y, pose.position.y, 1e-6);
  EXPECT_NEAR(transform.transform.translation.z, pose.position.z, 1e-6);
  const double dot = transform.transform.rotation.x * pose.orientation.x +
                     transform.transform.rotation.y * pose.orientation.y +
                     transform.transform.rotation.z * pose.orientation.z +
                     transform.transform.rotation.w * pose.orientation.w;
  EXPECT_NEAR(std::abs(dot), 1.0, 1e-6);
}

TEST(SimulatorNode, MoveTopicAppliesAStepAndReportsIt) {
  ros::NodeHandle& node = publicNode();
  std::mutex mutex;
  std::vector<StepOutcome> outcomes;
  ros::Subscriber subscriber = node.subscribe<StepOutcome>(
      names::kStepOutcomeTopic, 10, [&](const StepOutcome::ConstPtr& outcome) {
        std::lock_guard<std::mutex> lock(mutex);
        outcomes.push_back(*outcome);
      });
  std::vector<sensor_msgs::Image> images;
  ros::Subscriber image_subscriber = node.subscribe<sensor_msgs::Image>(
      names::kDepthImageTopic, 10, [&](const sensor_msgs::Image::ConstPtr& image) {
        std::lock_guard<std::mutex> lock(mutex);
        images.push_back(*image);
      });
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  ros::Publisher publisher = node.advertise<CameraMove>(names::kMoveTopic, 10);
  ASSERT_TRUE(waitFor(
      [&] {
        return publisher.getNumSubscribers() > 0 && subscriber.getNumPublishers() > 0 &&
               image_subscriber.getNumPublishers() > 0;
      },
      10.0));
  ros::Duration(0.3).sleep();  // let the node's side of both connections settle
  const Reset::Response reset = callReset(4);
  ASSERT_EQ(reset.status.code, Status::OK);

  CameraMove move;
  move.d_azimuth = -1.0;
  publisher.publish(move);
  move.d_azimuth = std::numeric_limits<double>::quiet_NaN();
  publisher.publish(move);
  ASSERT_TRUE(waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return outcomes.size() >= 2;
      },
      10.0));
  std::lock_guard<std::mutex> lock(mutex);
  EXPECT_EQ(outcomes[0].status.code, Status::OK) << outcomes[0].status.message;
  EXPECT_EQ(outcomes[0].step_index, 1);
  EXPECT_LT(outcomes[0].azimuth, reset.observation.azimuth);  // moved towards -azimuth
  EXPECT_EQ(outcomes[1].status.code, Status::INVALID_ARGUMENT);
  EXPECT_FALSE(outcomes[1].status.message.empty());

  // The outcome is stamped like the view it led to: its images and its camera transform.
  const ros::Time stamp = outcomes[0].header.stamp;
  EXPECT_TRUE(std::any_of(images.begin(), images.end(), [&](const sensor_msgs::Image& image) {
    return image.header.stamp == stamp;
  })) << "no depth image with the outcome's stamp";
  std::string error;
  ASSERT_TRUE(buffer.canTransform(names::kWorldFrame, names::kOpticalFrame, stamp,
                                  ros::Duration(5.0), &error))
      << error;
  const geometry_msgs::TransformStamped transform =
      buffer.lookupTransform(names::kWorldFrame, names::kOpticalFrame, stamp);
  // The camera looks at the origin from the outcome's angles (radius 4 m).
  const double radius = nodeOptions().environment.radius_m;
  EXPECT_NEAR(transform.transform.translation.x,
              radius * std::cos(outcomes[0].elevation) * std::cos(outcomes[0].azimuth), 1e-6);
  EXPECT_NEAR(transform.transform.translation.y,
              radius * std::cos(outcomes[0].elevation) * std::sin(outcomes[0].azimuth), 1e-6);
}

TEST(SimulatorNode, BadInputsAreRefusedAndLeaveTheStateUnchanged) {
  ASSERT_EQ(callReset(3).status.code, Status::OK);
  const Step::Response first = callStep(1.0, 0.0);
  ASSERT_EQ(first.status.code, Status::OK);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const auto& action :
       {std::make_pair(nan, 0.0), std::make_pair(0.0, inf), std::make_pair(-inf, 1.0)}) {
    const Step::Response step = callStep(action.first, action.second);
    EXPECT_EQ(step.status.code, Status::INVALID_ARGUMENT);
    EXPECT_NE(step.status.message.find("finite"), std::string::npos) << step.status.message;
  }

  Reset::Request unknown_id;
  unknown_id.seed = 1;
  unknown_id.object_ids = {"no_such_object"};
  Reset::Response reset = callReset(unknown_id);
  EXPECT_EQ(reset.status.code, Status::INVALID_ARGUMENT);
  EXPECT_NE(reset.status.message.find("no_such_object"), std::string::npos) << reset.status.message;

  Reset::Request unknown_category;
  unknown_category.seed = 1;
  unknown_category.categories = {"spaceship"};
  reset = callReset(unknown_category);
  EXPECT_EQ(reset.status.code, Status::INVALID_ARGUMENT);
  EXPECT_NE(reset.status.message.find("spaceship"), std::string::npos) << reset.status.message;

  Reset::Request bad_preset;
  bad_preset.seed = 1;
  bad_preset.preset = "three_chairs";
  reset = callReset(bad_preset);
  EXPECT_EQ(reset.status.code, Status::INVALID_ARGUMENT);
  EXPECT_NE(reset.status.message.find("three_chairs"), std::string::npos) << reset.status.message;

  Reset::Request bad_elevation;
  bad_elevation.seed = 1;
  bad_elevation.set_start_elevation = true;
  bad_elevation.start_elevation = 2.0;  // beyond the 80 deg limit
  EXPECT_EQ(callReset(bad_elevation).status.code, Status::INVALID_ARGUMENT);

  // The episode went on untouched: the next step is step 2 of seed 3's episode.
  const Step::Response second = callStep(1.0, 0.0);
  ASSERT_EQ(second.status.code, Status::OK) << second.status.message;
  EXPECT_EQ(second.observation.step_index, 2);
  Environment& local = localEnvironment();
  local.reset(3);
  local.step({1.0, 0.0});
  local.step({1.0, 0.0});
  expectMatchesLocal(second.observation);
}

TEST(SimulatorNode, StepAfterTheEpisodeEndedIsRefused) {
  ASSERT_EQ(callReset(2).status.code, Status::OK);
  Step::Response step;
  int steps = 0;
  do {
    step = callStep(0.0, 1.0);
    ASSERT_EQ(step.status.code, Status::OK) << step.status.message;
    ++steps;
  } while (!step.terminated && !step.truncated && steps < 100);
  EXPECT_LE(steps, nodeOptions().environment.max_steps);
  EXPECT_EQ(callStep(0.0, 1.0).status.code, Status::INVALID_STATE);
}

TEST(SimulatorNode, ParametersAreValidatedWithTheirNames) {
  ros::NodeHandle node("/parameter_validation_test");
  node.setParam("width", std::string("wide"));
  EXPECT_THROW(
      {
        try {
          readSimulatorOptions(node);
        } catch (const ParameterError& error) {
          EXPECT_NE(std::string(error.what()).find("width"), std::string::npos) << error.what();
          throw;
        }
      },
      ParameterError);
  node.setParam("width", 5000);
  try {
    readSimulatorOptions(node);
    ADD_FAILURE() << "width 5000 was accepted";
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("width"), std::string::npos) << error.what();
  }
  node.setParam("width", 128);
  node.setParam("reward_normalization", std::string("max"));
  try {
    readSimulatorOptions(node);
    ADD_FAILURE() << "reward_normalization max was accepted";
  } catch (const ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("reward_normalization"), std::string::npos);
  }
  node.setParam("reward_normalization", std::string("none"));
  node.setParam("categories", 3);
  EXPECT_THROW(readSimulatorOptions(node), ParameterError);
  node.deleteParam("categories");
  node.setParam("widht", 64);
  const SimulatorOptions options = readSimulatorOptions(node);
  EXPECT_EQ(options.environment.width, 128);
  EXPECT_EQ(options.environment.reward.normalization, RewardNormalization::kNone);
  EXPECT_EQ(unknownParameters(node, simulatorOptionTable()), std::vector<std::string>{"widht"});
  ros::param::del("/parameter_validation_test");
}

TEST(SimulatorNode, NodeIsStillServingAfterEverything) {
  const Reset::Response reset = callReset(1);
  EXPECT_EQ(reset.status.code, Status::OK) << reset.status.message;
  EXPECT_EQ(callStep(0.5, 0.5).status.code, Status::OK);
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "simulator_node_test");
  ros::AsyncSpinner spinner(1);  // subscription callbacks; the tests run on this thread
  spinner.start();
  // The node advertises its services one after another: wait for each, not just the first.
  for (const char* service :
       {occlusion_env::names::kResetService, occlusion_env::names::kStepService,
        occlusion_env::names::kGradientService}) {
    const std::string name = std::string("/") + occlusion_env::names::kNamespace + "/" + service;
    if (!ros::service::waitForService(name, ros::Duration(30.0))) {
      ADD_FAILURE() << "the simulator's service " << name << " did not appear in 30 s";
    }
  }
  const int result = RUN_ALL_TESTS();
  ros::shutdown();
  return result;
}
