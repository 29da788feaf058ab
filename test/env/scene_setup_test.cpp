// Per-scene draws of world, depth sensor and camera (env/scene_setup.hpp): off by default (the
// options' fixed camera), the same seed gives the same draws and bit-identical frames, draws stay
// inside their ranges, and the renderer, the camera and the scene follow the drawn setup.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/render/osmesa_renderer.hpp"

namespace occlusion_env {
namespace {

EnvironmentOptions smallOptions() {
  EnvironmentOptions options;
  options.width = options.height = 96;
  options.max_steps = 1000;
  return options;
}

EnvironmentOptions randomizedOptions() {
  EnvironmentOptions options = smallOptions();
  applySceneRandomization(options, std::nullopt, std::nullopt, true);
  return options;
}

bool sameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

TEST(SceneSetupTest, OffByDefaultTheOptionsCamera) {
  const EnvironmentOptions options = smallOptions();
  EXPECT_FALSE(options.camera_randomization.enabled);
  const SceneSetup setup = drawSceneSetup(options, 12);
  EXPECT_EQ(setup.world, "void");
  EXPECT_EQ(setup.depth_sensor, "ideal");
  EXPECT_EQ(setup.radius_m, options.radius_m);
  EXPECT_EQ(setup.field_of_view_rad, options.field_of_view_rad);
  EXPECT_EQ(setup.scene_scale, 1.0);
  const CameraIntrinsics nominal =
      CameraIntrinsics::fromFieldOfView(96, 96, options.field_of_view_rad);
  EXPECT_EQ(setup.intrinsics.fx, nominal.fx);
  EXPECT_EQ(setup.intrinsics.cx, nominal.cx);

  // Ranges set but randomisation off: the frames of the default options, bit for bit.
  EnvironmentOptions ranges_only = options;
  ranges_only.camera_randomization.radius_range_m = {2.0, 3.0};
  ranges_only.camera_randomization.focal_length_jitter = 0.2;
  Environment plain(options), with_ranges(ranges_only);
  for (const std::uint64_t seed : {4u, 9u}) {
    const StepResult a = plain.reset(seed), b = with_ranges.reset(seed);
    EXPECT_TRUE(sameBytes(a.observation->rgb, b.observation->rgb));
    EXPECT_TRUE(sameBytes(a.observation->depth, b.observation->depth));
    EXPECT_EQ(plain.camera().radius(), options.radius_m);
    EXPECT_EQ(plain.scene().scale, 1.0);
  }
}

TEST(SceneSetupTest, DrawsStayInsideTheirRanges) {
  const EnvironmentOptions options = randomizedOptions();
  const CameraRandomization& r = options.camera_randomization;
  std::set<std::string> worlds, sensors;
  std::set<int> widths;
  for (std::uint64_t seed = 0; seed < 300; ++seed) {
    const SceneSetup setup = drawSceneSetup(options, seed);
    worlds.insert(setup.world);
    sensors.insert(setup.depth_sensor);
    EXPECT_GE(setup.radius_m, r.radius_range_m[0]);
    EXPECT_LE(setup.radius_m, r.radius_range_m[1]);
    EXPECT_GE(setup.field_of_view_rad, r.field_of_view_range_rad[0]);
    EXPECT_LE(setup.field_of_view_rad, r.field_of_view_range_rad[1]);
    EXPECT_DOUBLE_EQ(setup.scene_scale, setup.radius_m / options.radius_m);
    const CameraIntrinsics& k = setup.intrinsics;
    widths.insert(k.width);
    EXPECT_GE(k.width, std::lround(96 * r.resolution_scale_range[0]));
    EXPECT_LE(k.width, std::lround(96 * r.resolution_scale_range[1]));
    EXPECT_EQ(k.height, k.width);  // the options' aspect ratio
    const double nominal_f = 0.5 * k.width / std::tan(0.5 * setup.field_of_view_rad);
    EXPECT_LE(std::abs(k.fx / nominal_f - 1.0), r.focal_length_jitter + 1e-12);
    EXPECT_LE(std::abs(k.fy / nominal_f - 1.0), r.focal_length_jitter + 1e-12);
    EXPECT_LE(std::abs(k.cx - 0.5 * (k.width - 1)), r.principal_point_jitter * k.width + 1e-9);
    EXPECT_LE(std::abs(k.cy - 0.5 * (k.height - 1)), r.principal_point_jitter * k.height + 1e-9);
  }
  EXPECT_EQ(worlds, (std::set<std::string>{"void", "room"}));
  EXPECT_EQ(sensors.size(), 4u);
  EXPECT_GT(widths.size(), 20u);
}

TEST(SceneSetupTest, SameSeedSameDrawsAndFrames) {
  Environment a(randomizedOptions()), b(randomizedOptions());
  for (const std::uint64_t seed : {1u, 2u, 3u, 5u, 8u}) {
    const StepResult first = a.reset(seed);
    const StepResult second = b.reset(seed);
    EXPECT_TRUE(a.sceneSetup() == b.sceneSetup());
    EXPECT_TRUE(sameBytes(first.observation->rgb, second.observation->rgb));
    EXPECT_TRUE(sameBytes(first.observation->depth, second.observation->depth));
    for (int t = 0; t < 3; ++t) {
      const StepResult x = a.step({0.3, 1.0}), y = b.step({0.3, 1.0});
      EXPECT_TRUE(sameBytes(x.observation->rgb, y.observation->rgb));
      EXPECT_TRUE(sameBytes(x.observation->depth, y.observation->depth));
      EXPECT_EQ(x.info.occlusion.total_pixels, y.info.occlusion.total_pixels);
    }
  }
  // Another seed: another camera.
  a.reset(1);
  const SceneSetup one = a.sceneSetup();
  a.reset(2);
  EXPECT_FALSE(one == a.sceneSetup());
}

TEST(SceneSetupTest, EnvironmentFollowsTheDrawnSetup) {
  Environment env(randomizedOptions());
  for (const std::uint64_t seed : {3u, 6u, 11u, 14u}) {
    const StepResult start = env.reset(seed);
    const SceneSetup& setup = env.sceneSetup();
    const CameraIntrinsics& k = env.intrinsics();
    EXPECT_EQ(k.width, setup.intrinsics.width);
    EXPECT_EQ(k.fx, setup.intrinsics.fx);
    EXPECT_EQ(k.cy, setup.intrinsics.cy);
    EXPECT_EQ(start.observation->rgb.cols, k.width);
    EXPECT_EQ(start.observation->depth.rows, k.height);
    EXPECT_EQ(env.camera().radius(), setup.radius_m);
    EXPECT_NEAR(env.info().world_from_optical.translation().norm(), setup.radius_m, 1e-9);
    EXPECT_EQ(env.scene().scale, setup.scene_scale);
    EXPECT_EQ(env.room() != nullptr, setup.world == "room");
    EXPECT_EQ(env.sensor().depthSensor(), setup.depth_sensor);
  }
}

// What `env`'s current episode shows unscaled (its objects, and its room as drawn, in the scene's
// own units) from the options' radius at the same pose, with the same intrinsics.
RenderBuffers unscaledView(const Environment& env, const EnvironmentOptions& options) {
  auto renderer = makeOsMesaRenderer(env.intrinsics());
  std::vector<PlacedMesh> placed;
  for (const SceneObject& object : env.scene().objects) {
    placed.push_back(
        {&object.model->render, Eigen::Affine3d(Eigen::Translation3d(object.position_m))});
  }
  renderer->setScene(placed);
  if (env.room()) renderer->setBackground(env.room()->background());
  const SphericalCamera unscaled(options.radius_m, options.elevation_limit_rad);
  RenderBuffers view;
  renderer->render(unscaled.worldFromOptical(env.info().pose), view);
  return view;
}

// The scaled scene seen from the drawn radius is the unscaled scene seen from `radius` with the
// same intrinsics: the same silhouettes (up to rasterisation at a few edge pixels), depth times
// the scale.
TEST(SceneSetupTest, ScaledSceneIsTheSceneSeenNearer) {
  EnvironmentOptions options = randomizedOptions();
  options.world.world = "void";
  options.sensor.depth_sensor = "ideal";
  Environment env(options);
  env.reset(7);
  const double scale = env.scene().scale;
  ASSERT_LT(scale, 0.5);
  const RenderBuffers reference = unscaledView(env, options);
  const RenderBuffers& scaled = env.renderBuffers();
  ASSERT_EQ(scaled.amodal_bits.size(), reference.amodal_bits.size());
  int differing = 0, compared = 0;
  for (int v = 0; v < reference.depth.rows; ++v) {
    for (int u = 0; u < reference.depth.cols; ++u) {
      differing +=
          scaled.amodal_bits.at<std::uint8_t>(v, u) != reference.amodal_bits.at<std::uint8_t>(v, u);
      const float near = scaled.depth.at<float>(v, u), far = reference.depth.at<float>(v, u);
      if (std::isfinite(near) && std::isfinite(far) &&
          scaled.instance.at<std::uint8_t>(v, u) == reference.instance.at<std::uint8_t>(v, u)) {
        EXPECT_NEAR(near, scale * far, 1e-4 * far) << "at " << u << ", " << v;
        ++compared;
      }
    }
  }
  EXPECT_LE(differing, static_cast<int>(0.005 * reference.amodal_bits.total()));
  EXPECT_GT(compared, 100);
}

// The same in a room: its floor, walls, ceiling and clutter scale with the scene, so the scaled
// room seen from the drawn radius is the unscaled room seen from `radius` (until 2026-12-06 the
// floor, walls and ceiling kept their size: objects floated above a floor drawn for 4 m).
TEST(SceneSetupTest, ScaledRoomIsTheRoomSeenNearer) {
  EnvironmentOptions options = randomizedOptions();
  options.world.world = "room";
  options.sensor.depth_sensor = "ideal";
  Environment env(options);
  for (const std::uint64_t seed : {7u, 12u}) {
    env.reset(seed);
    const double scale = env.scene().scale;
    ASSERT_LT(scale, 0.5);
    ASSERT_NE(env.room(), nullptr);
    const RenderBuffers reference = unscaledView(env, options);
    const RenderBuffers& scaled = env.renderBuffers();
    ASSERT_EQ(scaled.depth.size(), reference.depth.size());
    int differing = 0, compared = 0;
    for (int v = 0; v < reference.depth.rows; ++v) {
      for (int u = 0; u < reference.depth.cols; ++u) {
        const float near = scaled.depth.at<float>(v, u), far = reference.depth.at<float>(v, u);
        if (std::isfinite(near) && std::isfinite(far) &&
            std::abs(near - scale * far) <= 1e-3 * far) {
          ++compared;
        } else {
          ++differing;  // a floor or wall elsewhere, or an edge pixel rasterised otherwise
        }
      }
    }
    EXPECT_LE(differing, static_cast<int>(0.005 * reference.depth.total())) << "seed " << seed;
    EXPECT_GT(compared, static_cast<int>(0.9 * reference.depth.total())) << "seed " << seed;
  }
}

TEST(SceneSetupTest, ToolFlagsAndRefusals) {
  EnvironmentOptions options = smallOptions();
  applySceneRandomization(options, std::string("room"), std::nullopt, true);
  EXPECT_EQ(options.world.world, "room");
  EXPECT_EQ(options.sensor.depth_sensor, kRandomChoice);
  EXPECT_TRUE(options.camera_randomization.enabled);
  options = smallOptions();
  applySceneRandomization(options, std::nullopt, std::string("kinect_v1"), false);
  EXPECT_EQ(options.world.world, "void");
  EXPECT_EQ(options.sensor.depth_sensor, "kinect_v1");
  EXPECT_FALSE(options.camera_randomization.enabled);

  EnvironmentOptions bad = randomizedOptions();
  bad.camera_randomization.radius_range_m = {1.5, 0.5};
  EXPECT_THROW(bad.validate(), InvalidArgumentError);
  bad.camera_randomization.radius_range_m = {1.0};
  EXPECT_THROW(bad.validate(), InvalidArgumentError);
  bad = randomizedOptions();
  bad.camera_randomization.field_of_view_range_rad = {1.0, 3.5};
  EXPECT_THROW(bad.validate(), InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
