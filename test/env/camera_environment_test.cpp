// The camera bridge's logic without ROS (env/camera_environment.hpp): in front of the in-process
// simulator (env/simulated_camera_rig.hpp) with an estimator that knows the truth it plays the
// simulator's own episodes; views without depth are refused and leave the episode as it was;
// without an estimator only max_steps ends an episode.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/simulated_camera_rig.hpp"

namespace occlusion_env {
namespace {

// An "estimate" that is the simulator's own count of the view the rig just rendered.
class TrueOcclusion : public ViewOcclusionEstimator {
 public:
  explicit TrueOcclusion(const Environment& environment) : environment_(environment) {}
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat& /*depth*/, const CameraIntrinsics&,
                        cv::Mat& mask) override {
    mask = environment_.observation().occlusion_mask;
    EXPECT_EQ(mask.size(), rgb.size());
    return environment_.info().occlusion.total_pixels;
  }

 private:
  const Environment& environment_;
};

EnvironmentOptions simulatorOptions() {
  EnvironmentOptions options;
  options.width = options.height = 64;
  options.reward.normalization = RewardNormalization::kIntersection;  // the bridge's Z
  return options;
}

TEST(CameraEnvironment, OnTheSimulatorWithTheTruthItPlaysTheSimulatorsEpisodes) {
  Environment direct(simulatorOptions());
  Environment stand_in(simulatorOptions());
  SimulatedCameraRig rig(stand_in);
  TrueOcclusion truth(stand_in);
  CameraEnvironmentOptions options;
  options.confirm_views = 1;  // the simulator's rule
  CameraEnvironment bridge(options, rig, &truth);
  for (const std::uint64_t seed : {0, 2, 4}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    StepResult expected = direct.reset(seed);
    StepResult got = bridge.reset(seed);
    EXPECT_EQ(got.info.occlusion.total_pixels, expected.info.occlusion.total_pixels);
    EXPECT_EQ(got.info.occlusion_source, OcclusionSource::kEstimated);
    EXPECT_TRUE(got.info.world_from_optical.isApprox(expected.info.world_from_optical, 1e-12));
    EXPECT_EQ(bridge.intrinsics().fx, stand_in.intrinsics().fx);
    EXPECT_EQ(got.info.intrinsics.fx, expected.info.intrinsics.fx);  // what agents are told
    EXPECT_EQ(got.info.intrinsics.cx, expected.info.intrinsics.cx);
    int steps = 0;
    while (!expected.terminated && !expected.truncated) {
      const Action action{1.0, 0.3};
      expected = direct.step(action);
      got = bridge.step(action);
      ++steps;
      SCOPED_TRACE("step " + std::to_string(steps));
      EXPECT_NEAR(got.info.pose.azimuth_rad, expected.info.pose.azimuth_rad, 1e-9);
      EXPECT_NEAR(got.info.pose.elevation_rad, expected.info.pose.elevation_rad, 1e-9);
      EXPECT_EQ(got.info.occlusion.total_pixels, expected.info.occlusion.total_pixels);
      EXPECT_DOUBLE_EQ(got.reward, expected.reward);
      EXPECT_EQ(got.terminated, expected.terminated);
      EXPECT_EQ(got.truncated, expected.truncated);
      EXPECT_EQ(got.info.step_index, expected.info.step_index);
      EXPECT_EQ(got.info.last_action.d_elevation_rad, 0.3);
      EXPECT_EQ(expected.info.last_action.d_elevation_rad, 0.3);
      ASSERT_LT(steps, 60);
    }
    EXPECT_TRUE(expected.terminated) << "a scene the test should see cleared";
  }
  // Masks and true occlusion: the simulator has them, a camera does not.
  EXPECT_TRUE(direct.hasPrivilegedObservation());
  EXPECT_EQ(direct.privilegedObservation().occlusion.total_pixels,
            direct.info().occlusion.total_pixels);
  EXPECT_FALSE(bridge.hasPrivilegedObservation());
  EXPECT_THROW(bridge.privilegedObservation(), InvalidStateError);
}

// The bridge in front of a simulator that draws its camera per scene: the field of view may be
// drawn (the bridge reads each frame's intrinsics), the radius only as one value, its sphere.
TEST(CameraEnvironment, InFrontOfADrawnCameraItKeepsOneSphere) {
  EnvironmentOptions drawn = simulatorOptions();
  drawn.width = drawn.height = 128;  // enough pixels at 86 deg for a start view with occlusion
  drawn.camera_randomization.enabled = true;
  drawn.camera_randomization.radius_range_m = {1.0, 1.0};
  drawn.camera_randomization.field_of_view_range_rad = {1.5, 1.5};
  drawn.camera_randomization.resolution_scale_range = {1.0, 1.0};
  drawn.camera_randomization.focal_length_jitter = 0.0;
  Environment simulator(drawn);
  BridgedSimulator bridged(simulator, CameraEnvironmentOptions{}, nullptr);
  EXPECT_DOUBLE_EQ(bridged.bridge().options().radius_m, 1.0);
  const StepResult start = bridged.bridge().reset(3);
  EXPECT_NEAR(start.info.world_from_optical.translation().norm(), 1.0, 1e-9);
  EXPECT_EQ(start.info.intrinsics.fx, simulator.intrinsics().fx) << "the drawn camera's";
  EXPECT_NEAR(start.info.intrinsics.fx, 0.5 * 128 / std::tan(0.75), 1e-9) << "1.5 rad wide";
  EXPECT_DOUBLE_EQ(BridgedSimulator::sphereRadius(drawn), 1.0) << "the estimate's radius too";
  EXPECT_DOUBLE_EQ(BridgedSimulator::sphereRadius(simulatorOptions()), 4.0);
  drawn.camera_randomization.radius_range_m = {0.5, 1.5};
  EXPECT_THROW(BridgedSimulator::sphereRadius(drawn), InvalidArgumentError);
  Environment ranged(drawn);
  EXPECT_THROW(BridgedSimulator(ranged, CameraEnvironmentOptions{}, nullptr), InvalidArgumentError);
}

TEST(CameraEnvironment, WithoutAnEstimatorOnlyMaxStepsEndsAnEpisode) {
  Environment stand_in(simulatorOptions());
  SimulatedCameraRig rig(stand_in);
  CameraEnvironmentOptions options;
  options.max_steps = 30;
  options.min_valid_depth_fraction = 0.005;  // 64 px of the void: the objects fill little
  CameraEnvironment bridge(options, rig, nullptr);
  StepResult result = bridge.reset(2);
  EXPECT_EQ(result.info.occlusion_source, OcclusionSource::kUnavailable);
  EXPECT_EQ(result.info.occlusion.total_pixels, kUnknownOcclusion);
  EXPECT_TRUE(result.observation->occlusion_mask.empty());
  for (int step = 1; step <= 30; ++step) {
    result = bridge.step({1.0, 0.0});  // seed 2 turning left is truly clear after 4 steps
    EXPECT_EQ(result.reward, 0.0);
    EXPECT_FALSE(result.terminated);
    EXPECT_EQ(result.truncated, step == 30);
  }
  EXPECT_THROW(bridge.step({1.0, 0.0}), InvalidStateError);
}

// A rig that gives one fixed frame, which a test can spoil.
class FixedCamera : public CameraRig {
 public:
  FixedCamera() {
    frame_.rgb = cv::Mat(60, 80, CV_8UC3, cv::Scalar(10, 20, 30));
    frame_.depth = cv::Mat(60, 80, CV_32FC1, cv::Scalar(4.0f));
    frame_.intrinsics = CameraIntrinsics::fromFieldOfView(80, 60, 1.0);
    frame_.sphere_from_optical = SphericalCamera(4.0, 1.3).worldFromOptical({0.1, 0.2});
  }
  void arrangeScene(std::uint64_t, const ResetOptions&) override {}
  Eigen::Isometry3d cameraPose() override { return frame_.sphere_from_optical; }
  const CameraFrame& moveTo(const SphericalPose& goal) override {
    frame_.sphere_from_optical = SphericalCamera(4.0, 1.3).worldFromOptical(goal);
    return frame_;
  }
  const CameraFrame& currentFrame() override { return frame_; }
  std::string describe() const override { return "a fixed camera"; }
  CameraFrame frame_;
};

class CountingEstimator : public ViewOcclusionEstimator {
 public:
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat&, const CameraIntrinsics&,
                        cv::Mat& mask) override {
    mask = cv::Mat::zeros(rgb.size(), CV_8UC1);
    return 0;
  }
};

TEST(CameraEnvironment, CropsToTheCentralSquareAndRefusesBlindViews) {
  FixedCamera camera;
  CountingEstimator estimator;
  CameraEnvironment bridge(CameraEnvironmentOptions(), camera, &estimator);
  const StepResult first = bridge.reset(0);
  EXPECT_EQ(first.observation->rgb.size(), cv::Size(60, 60));
  EXPECT_EQ(bridge.cropRegion(), cv::Rect(10, 0, 60, 60));
  EXPECT_DOUBLE_EQ(bridge.intrinsics().cx, camera.frame_.intrinsics.cx - 10.0);
  EXPECT_EQ(bridge.intrinsics().width, 60);
  EXPECT_NEAR(first.info.pose.azimuth_rad, 0.1, 1e-9);
  EXPECT_NEAR(first.info.pose.elevation_rad, 0.2, 1e-9);

  // All depth lost (a covered lens): UNAVAILABLE (an unusable view, which an episode runner
  // counts as a failure), never an estimate, the episode as it was.
  camera.frame_.depth.setTo(std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(bridge.step({1.0, 0.0}), UnusableViewError);
  EXPECT_EQ(bridge.episodeRule().stepIndex(), 0);
  EXPECT_EQ(bridge.episodeRule().clearViewsInARow(), 0);
  camera.frame_.depth.setTo(4000.0f);  // millimetres sent as metres: out of the working range
  EXPECT_THROW(bridge.step({1.0, 0.0}), EnvironmentUnavailableError);
  camera.frame_.depth.setTo(4.0f);
  const StepResult next = bridge.step({1.0, 0.0});
  EXPECT_EQ(next.info.step_index, 1);
  EXPECT_FALSE(next.terminated);  // one clear view of the five that confirm
  // Steps start from where the camera is: the refused steps had moved it twice already.
  EXPECT_NEAR(next.info.pose.azimuth_rad, 0.25, 1e-9);

  // A request it would refuse arranges no scene and moves nothing.
  ResetOptions bad;
  bad.start_elevation_rad = 2.0;
  EXPECT_THROW(bridge.reset(0, bad), InvalidArgumentError);
  EXPECT_EQ(bridge.episodeRule().stepIndex(), 1);
}

TEST(CameraEnvironment, GoalsStayWithinTheRigsElevations) {
  FixedCamera camera;
  CountingEstimator estimator;
  CameraEnvironmentOptions options;
  options.lowest_elevation_rad = 0.15;  // e.g. the arm cannot reach below the table top
  CameraEnvironment bridge(options, camera, &estimator);
  bridge.reset(0);  // the fixed camera is at elevation 0.2
  StepResult result = bridge.step({0.0, -1.0});
  EXPECT_NEAR(result.info.pose.elevation_rad, 0.15, 1e-9);
  result = bridge.step({0.0, -1.0});
  EXPECT_NEAR(result.info.pose.elevation_rad, 0.15, 1e-9);
  ResetOptions below;
  below.start_elevation_rad = 0.1;
  EXPECT_THROW(bridge.reset(0, below), InvalidArgumentError);
  // Never below -elevation_limit, whatever lowest_elevation says.
  options.lowest_elevation_rad = -1.4;
  options.elevation_limit_rad = 1.0;
  EXPECT_DOUBLE_EQ(options.sphere().lowestElevation(), -1.0);
  EXPECT_DOUBLE_EQ(options.sphere().highestElevation(), 1.0);
}

TEST(CameraEnvironment, RefusesOptionsOutsideTheirRangesByName) {
  FixedCamera camera;
  const auto refused = [&camera](auto change, const std::string& name) {
    CameraEnvironmentOptions options;
    change(options);
    try {
      CameraEnvironment bridge(options, camera, nullptr);
      ADD_FAILURE() << name << " accepted";
    } catch (const InvalidArgumentError& error) {
      EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
    }
  };
  refused([](CameraEnvironmentOptions& o) { o.step_size_rad = 0.0; }, "step_size");
  refused([](CameraEnvironmentOptions& o) { o.radius_m = -1.0; }, "radius");
  refused([](CameraEnvironmentOptions& o) { o.elevation_limit_rad = 1.6; }, "elevation_limit");
  refused([](CameraEnvironmentOptions& o) { o.min_valid_depth_fraction = 0.0; },
          "min_valid_depth_fraction");
  refused([](CameraEnvironmentOptions& o) { o.working_range_factor = 0.9; },
          "working_range_factor");
  refused([](CameraEnvironmentOptions& o) { o.confirm_views = 0; }, "confirm_views");
  refused([](CameraEnvironmentOptions& o) { o.occlusion_probability = 1.0; },
          "occlusion_probability");
  refused([](CameraEnvironmentOptions& o) { o.max_steps = 0; }, "max_steps");
  refused([](CameraEnvironmentOptions& o) { o.lowest_elevation_rad = -1.6; }, "lowest_elevation");
  refused([](CameraEnvironmentOptions& o) { o.lowest_elevation_rad = 1.5; }, "lowest_elevation");
  EXPECT_NO_THROW(CameraEnvironment(CameraEnvironmentOptions(), camera, nullptr));
}

// An estimate that marks a fixed rectangle of the view (empty: nothing).
class RectangleEstimate : public ViewOcclusionEstimator {
 public:
  explicit RectangleEstimate(cv::Rect occluded) : occluded_(occluded) {}
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat&, const CameraIntrinsics&,
                        cv::Mat& mask) override {
    mask.create(rgb.size(), CV_8UC1);
    mask.setTo(0);
    mask(occluded_).setTo(255);
    return occluded_.area();
  }

 private:
  cv::Rect occluded_;
};

// A second opinion: a view is clear only where neither estimate sees occlusion; the mask and the
// count are the union of both (overlapping rectangles counted once).
TEST(EstimateUnion, IsClearOnlyWhereBothEstimatesAre) {
  const cv::Mat rgb(32, 32, CV_8UC3, cv::Scalar::all(0)), depth(32, 32, CV_32FC1, 4.0f);
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(32, 32, 1.0);
  cv::Mat mask;
  EstimateUnion both_clear(std::make_unique<RectangleEstimate>(cv::Rect()),
                           std::make_unique<RectangleEstimate>(cv::Rect()));
  EXPECT_EQ(both_clear.estimate(rgb, depth, intrinsics, mask), 0);
  EXPECT_EQ(cv::countNonZero(mask), 0);
  EstimateUnion second_sees(std::make_unique<RectangleEstimate>(cv::Rect()),
                            std::make_unique<RectangleEstimate>(cv::Rect(4, 4, 2, 3)));
  EXPECT_EQ(second_sees.estimate(rgb, depth, intrinsics, mask), 6);
  EXPECT_EQ(mask.at<std::uint8_t>(5, 4), 255);
  EstimateUnion overlapping(std::make_unique<RectangleEstimate>(cv::Rect(0, 0, 4, 4)),
                            std::make_unique<RectangleEstimate>(cv::Rect(2, 2, 4, 4)));
  EXPECT_EQ(overlapping.estimate(rgb, depth, intrinsics, mask), 16 + 16 - 4);
  EXPECT_EQ(cv::countNonZero(mask), 28);
  EXPECT_THROW(EstimateUnion(std::make_unique<RectangleEstimate>(cv::Rect()), nullptr),
               InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
