// world: room: the objects stand on a floor inside walls with clutter and a light of their own,
// and the targets' silhouettes, visible instances and occlusion are those of the same scene with
// nothing around it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "occlusion_env/agents/oracle.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/occlusion/occlusion.hpp"
#include "occlusion_env/render/osmesa_renderer.hpp"

namespace occlusion_env {
namespace {

EnvironmentOptions roomOptions() {
  EnvironmentOptions options;
  options.width = options.height = 128;
  options.world.world = "room";
  options.world.clutter = 3;
  options.max_steps = 1000;
  return options;
}

bool sameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

/// The share of pixels where the room (instance 0 with a depth) shows.
double roomShare(const RenderBuffers& buffers) {
  long room = 0;
  for (int v = 0; v < buffers.depth.rows; ++v) {
    for (int u = 0; u < buffers.depth.cols; ++u) {
      room += buffers.instance.at<std::uint8_t>(v, u) == 0 &&
              std::isfinite(buffers.depth.at<float>(v, u));
    }
  }
  return static_cast<double>(room) / buffers.depth.total();
}

TEST(RoomTest, TargetsMasksAndOcclusionAreThoseWithoutTheRoom) {
  Environment env(roomOptions());
  auto bare = makeOsMesaRenderer(env.intrinsics());
  RenderBuffers without_room;
  for (const std::uint64_t seed : {3u, 8u, 21u}) {
    env.reset(seed);
    ASSERT_NE(env.room(), nullptr);
    std::vector<PlacedMesh> placed;
    for (const SceneObject& object : env.scene().objects) {
      placed.push_back(
          {&object.model->render, Eigen::Isometry3d(Eigen::Translation3d(object.position_m))});
    }
    bare->setScene(placed);
    // Start view, then poses all round: from low down (clamped above the floor), from behind
    // walls, from above.
    const SphericalPose poses[] = {env.info().pose, {0.0, -1.2}, {2.0, 0.3},
                                   {-2.5, 0.0},     {1.0, 1.3},  {3.1, -0.5}};
    for (const SphericalPose& pose : poses) {
      env.viewFrom(pose);
      bare->render(env.info().world_from_optical, without_room);
      const RenderBuffers& with_room = env.renderBuffers();
      EXPECT_TRUE(sameBytes(with_room.amodal_bits, without_room.amodal_bits)) << seed;
      EXPECT_TRUE(sameBytes(with_room.instance, without_room.instance)) << seed;
      for (std::size_t k = 0; k < placed.size(); ++k) {
        EXPECT_TRUE(sameBytes(with_room.object_depth[k], without_room.object_depth[k])) << seed;
      }
      const OcclusionStats bare_occlusion =
          computeOcclusion(without_room.amodal_bits, static_cast<int>(placed.size()));
      EXPECT_EQ(env.info().occlusion.total_pixels, bare_occlusion.total_pixels) << seed;
    }
    // From the start view (level, 4 m out) the room fills much of the picture.
    env.viewFrom(poses[0]);
    EXPECT_GT(roomShare(env.renderBuffers()), 0.3) << seed;
  }
}

TEST(RoomTest, ObjectsStandOnTheFloorAndTheClutterOutsideTheCameraSphere) {
  Environment env(roomOptions());
  env.reset(5);
  const Room& room = *env.room();
  for (const SceneObject& object : env.scene().objects) {
    const double bottom = object.position_m.z() - 0.5 * boundingBox(object.model->full).sizes().z();
    EXPECT_NEAR(bottom, room.floor_height_m + 0.001, 1e-6);
  }
  for (const SceneObject& clutter : room.clutter) {
    const Eigen::AlignedBox3d box = boundingBox(clutter.model->full).cast<double>();
    EXPECT_GT(clutter.position_m.head<2>().norm() - 0.5 * box.sizes().head<2>().norm(),
              env.options().radius_m);
    for (const SceneObject& target : env.scene().objects) {
      EXPECT_NE(clutter.model->info.id, target.model->info.id);
    }
  }
}

// No rig takes a camera under the floor, and the floor is not drawn from below: the camera, its
// start and the oracle's paths stay floor_clearance above it.
TEST(RoomTest, TheCameraAndTheOracleStayAboveTheFloor) {
  EnvironmentOptions options = roomOptions();
  options.world.floor_clearance_m = 0.15;
  Environment env(options);
  const double limit = options.elevation_limit_rad;
  int oracle_checked = 0;
  for (const std::uint64_t seed : {5u, 9u, 14u}) {
    ResetOptions below;
    below.start_elevation_rad = -1.0;  // asked for under the floor: lifted to the lowest
    env.reset(seed, below);
    const Room& room = *env.room();
    const double lowest = env.camera().lowestElevation();
    EXPECT_NEAR(lowest, std::asin((room.floor_height_m + 0.15) / options.radius_m), 1e-12);
    EXPECT_GT(lowest, -limit);
    EXPECT_DOUBLE_EQ(env.camera().highestElevation(), limit);
    EXPECT_DOUBLE_EQ(env.info().pose.elevation_rad, lowest) << seed;
    const auto heightAboveFloor = [&] {
      return env.info().world_from_optical.translation().z() - room.floor_height_m;
    };
    EXPECT_NEAR(heightAboveFloor(), 0.15, 1e-9) << seed;
    for (int step = 0; step < 10; ++step) {
      env.step({0.3, -1.0});
      EXPECT_GE(heightAboveFloor(), 0.15 - 1e-9) << seed;
    }
    // From the lowest pose, wherever it is occluded, the oracle's way out stays above the floor.
    for (const double azimuth : {0.0, 0.8, 1.6, 2.4, -0.8, -1.6, -2.4, 3.1}) {
      const SphericalPose from{azimuth, lowest};
      env.viewFrom(from);
      if (env.info().occlusion.total_pixels == 0) continue;
      OcclusionOracle oracle(env);
      const OracleAnswer answer = oracle.query(from);
      ASSERT_GT(answer.steps, 0) << seed;
      EXPECT_GE(answer.target.elevation_rad, lowest - 1e-12) << seed;
      double elevation = from.elevation_rad;
      for (const Action& move : answer.path) {
        elevation += move.d_elevation_rad;
        EXPECT_GE(elevation, lowest - 1e-9) << seed;
      }
      ++oracle_checked;
      break;
    }
  }
  EXPECT_GE(oracle_checked, 2);

  // The void has no floor: the camera goes as low as the limit.
  options.world.world = "void";
  Environment empty(options);
  empty.reset(5);
  EXPECT_DOUBLE_EQ(empty.camera().lowestElevation(), -limit);
  options.world.floor_clearance_m = -0.1;
  EXPECT_THROW(Environment{options}, InvalidArgumentError);
}

TEST(RoomTest, SameSeedSameRoomAndFramesTheVoidStaysBlack) {
  Environment first(roomOptions());
  Environment second(roomOptions());
  first.reset(12);
  second.reset(12);
  EXPECT_EQ(first.room()->floor.colors, second.room()->floor.colors);
  ASSERT_EQ(first.room()->walls.size(), second.room()->walls.size());
  for (std::size_t k = 0; k < first.room()->walls.size(); ++k) {
    EXPECT_EQ(first.room()->walls[k].origin, second.room()->walls[k].origin);
    EXPECT_EQ(first.room()->walls[k].step_u, second.room()->walls[k].step_u);
    EXPECT_EQ(first.room()->walls[k].colors, second.room()->walls[k].colors);
  }
  for (int t = 0; t < 3; ++t) {
    EXPECT_TRUE(sameBytes(first.observation().rgb, second.observation().rgb));
    EXPECT_TRUE(sameBytes(first.observation().depth, second.observation().depth));
    first.step({1.0, 0.3});
    second.step({1.0, 0.3});
  }
  EnvironmentOptions void_options = roomOptions();
  void_options.world.world = "void";
  Environment empty(void_options);
  empty.reset(12);
  EXPECT_EQ(empty.room(), nullptr);
  EXPECT_EQ(roomShare(empty.renderBuffers()), 0.0);
  void_options.world.world = "garden";
  EXPECT_THROW(Environment{void_options}, InvalidArgumentError);
}

// world: random draws the world per scene with one camera, so one renderer serves a room scene
// and then a void one: the void scene must look as it does on a renderer that never held a room
// (no floor, walls, clutter or the room's light left behind).
TEST(RoomTest, AVoidSceneAfterARoomSceneShowsNoRoom) {
  EnvironmentOptions options = roomOptions();
  options.world.world = "random";
  Environment drawn(options);
  std::uint64_t room_seed = 0, void_seed = 0;
  bool have_room = false, have_void = false;
  for (std::uint64_t seed = 1; seed < 64 && !(have_room && have_void); ++seed) {
    drawn.reset(seed);
    if (drawn.room() && !have_room) room_seed = seed, have_room = true;
    if (!drawn.room() && !have_void) void_seed = seed, have_void = true;
  }
  ASSERT_TRUE(have_room && have_void);
  Environment fresh(options);
  fresh.reset(void_seed);
  drawn.reset(room_seed);
  ASSERT_NE(drawn.room(), nullptr);
  drawn.reset(void_seed);
  EXPECT_EQ(roomShare(drawn.renderBuffers()), 0.0);
  EXPECT_TRUE(sameBytes(drawn.observation().rgb, fresh.observation().rgb));
  EXPECT_TRUE(sameBytes(drawn.observation().depth, fresh.observation().depth));
  drawn.step({1.0, 0.0});
  fresh.step({1.0, 0.0});
  EXPECT_TRUE(sameBytes(drawn.observation().rgb, fresh.observation().rgb));
}

}  // namespace
}  // namespace occlusion_env
