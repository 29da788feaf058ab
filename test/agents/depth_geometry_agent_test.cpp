#include "occlusion_env/agents/depth_geometry_agent.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>

#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/agents/random_agent.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

constexpr double kRadius = 4.0;  // [m]
constexpr int kSize = 128;       // [px]

// A depth image of the camera at azimuth 0, elevation 0 seeing flat patches facing it: each
// covers the columns [u0, u1) and rows [32, 96) at its depth [m]; NaN elsewhere.
struct Patch {
  int u0, u1;
  float depth_m;
};

struct View {
  cv::Mat rgb = cv::Mat(kSize, kSize, CV_8UC3, cv::Scalar::all(0));
  cv::Mat depth =
      cv::Mat(kSize, kSize, CV_32FC1, cv::Scalar::all(std::numeric_limits<float>::quiet_NaN()));
  CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(kSize, kSize, M_PI / 3);
  SphericalPose pose;
  Eigen::Isometry3d world_from_optical =
      SphericalCamera(kRadius, 1.3962634016).worldFromOptical(SphericalPose{});

  explicit View(std::initializer_list<Patch> patches) {
    for (const Patch& patch : patches)
      depth(cv::Rect(patch.u0, 32, patch.u1 - patch.u0, 64)) = patch.depth_m;
  }
  RigObservation observation() const {
    return {rgb, depth, intrinsics, pose, world_from_optical, Action{}, 0};
  }
};

TEST(DepthGeometryAgent, PartsANearPatchFromAFarOneByMovingTowardsTheNearSide) {
  // The near patch on the left, the far one right beside it in the image, 0.8 m behind: the
  // camera moving right (+azimuth: from +x towards +y, where the optical x axis points) shifts
  // the near patch left of the far one, parting them; moving left would slide it over.
  DepthGeometryAgent agent;
  const View view({{30, 60, 3.0f}, {60, 90, 3.8f}});
  const Action move = agent.act(view.observation());
  const DepthGeometryPlan& plan = agent.lastPlan();
  EXPECT_EQ(plan.objects, 2);
  EXPECT_TRUE(plan.found_clear_pose);
  EXPECT_EQ(plan.overlap_px, 0);
  EXPECT_GT(plan.target_d_azimuth_rad, 0.0);
  EXPECT_GT(move.d_azimuth_rad, 0.9);
  EXPECT_NEAR(std::hypot(move.d_azimuth_rad, move.d_elevation_rad), 1.0, 1e-12);

  // Mirrored: the near patch on the right, so the camera moves left.
  agent.reset(0);
  const View mirrored({{68, 98, 3.0f}, {38, 68, 3.8f}});
  EXPECT_LT(agent.act(mirrored.observation()).d_azimuth_rad, -0.9);
  EXPECT_EQ(agent.lastPlan().objects, 2);
}

TEST(DepthGeometryAgent, JoinsSurfacesCloserThanTheJoinDistanceIntoOneObject) {
  DepthGeometryAgent agent;  // joins within 15 voxels of 2 cm: 30 cm at 4 m
  agent.act(View({{30, 60, 3.0f}, {60, 90, 3.1f}}).observation());
  EXPECT_EQ(agent.lastPlan().objects, 1);
  EXPECT_FALSE(agent.lastPlan().found_clear_pose);

  DepthGeometryOptions no_join;  // within 3 voxels: 6 cm
  no_join.join_voxels = 1;       // neighbouring samples (2.7 cm apart at 3 m) still join
  DepthGeometryAgent splitting(no_join);
  splitting.act(View({{30, 60, 3.0f}, {60, 90, 3.1f}}).observation());
  EXPECT_EQ(splitting.lastPlan().objects, 2);
}

TEST(DepthGeometryAgent, FusesTheEpisodesViewsAndForgetsThemOnReset) {
  DepthGeometryAgent agent;
  agent.act(View({{30, 60, 3.0f}}).observation());
  const int one_view = agent.lastPlan().voxels;
  EXPECT_GT(one_view, 100);
  EXPECT_EQ(agent.lastPlan().objects, 1);
  agent.act(View({{70, 100, 3.8f}}).observation());
  EXPECT_GT(agent.lastPlan().voxels, one_view);
  EXPECT_EQ(agent.lastPlan().objects, 2);  // the first view's patch is still there
  agent.reset(0);
  agent.act(View({{30, 60, 3.0f}}).observation());
  EXPECT_EQ(agent.lastPlan().voxels, one_view);
  EXPECT_EQ(agent.lastPlan().objects, 1);
}

// The two patches of the first test standing on a floor 0.9 m below the camera (the world's z =
// -0.9 m): each patch reaches down to the floor, the floor fills the rest of the lower half up to
// 4.5 m away.
View onAFloor() {
  View view(std::initializer_list<Patch>{});
  const CameraIntrinsics& k = view.intrinsics;
  const auto floor_row = [&](float depth_m) {  // the first row below the floor at that depth
    return static_cast<int>(std::ceil(k.cy + k.fy * 0.9 / depth_m));
  };
  for (int v = static_cast<int>(std::ceil(k.cy)); v < kSize; ++v) {
    const double ray_down = (v - k.cy) / k.fy;  // the optical y axis points down the world's z
    // Up to 4.5 m away: farther, the floor's rows lie farther apart than the join distance.
    if (ray_down > 0.9 / 4.5) view.depth.row(v).setTo(static_cast<float>(0.9 / ray_down));
  }
  for (const Patch& patch : {Patch{30, 60, 3.0f}, Patch{60, 90, 3.8f}})
    view.depth(cv::Rect(patch.u0, 32, patch.u1 - patch.u0, floor_row(patch.depth_m) - 32)) =
        patch.depth_m;
  return view;
}

TEST(DepthGeometryAgent, LeavesOutAFloorThatWouldJoinTheObjects) {
  DepthGeometryAgent agent;
  agent.act(onAFloor().observation());
  EXPECT_EQ(agent.lastPlan().objects, 2);
  EXPECT_TRUE(agent.lastPlan().found_clear_pose);

  DepthGeometryOptions with_floor;
  with_floor.skip_bounding_surfaces = false;
  DepthGeometryAgent fusing_the_floor(with_floor);
  fusing_the_floor.act(onAFloor().observation());
  EXPECT_EQ(fusing_the_floor.lastPlan().objects, 1);
}

TEST(DepthGeometryAgent, PlansNoPoseBeyondAnElevationTheRigStoppedAt) {
  // The near patch above the far one: moving down parts them (the near one rises faster in the
  // image), so the agent asks for a move down.
  View view(std::initializer_list<Patch>{});
  view.depth(cv::Rect(0, 32, kSize, 32)) = 3.0f;
  view.depth(cv::Rect(0, 64, kSize, 32)) = 3.8f;
  DepthGeometryAgent agent;
  const Action first = agent.act(view.observation());
  ASSERT_LT(first.d_elevation_rad, -0.5);
  EXPECT_LT(agent.lastPlan().target_d_elevation_rad, 0.0);

  // The rig moved as asked, by a smaller step than the agent plans with: the agent goes on
  // downwards. (The same frame and depth: only the pose the rig reports matters here.)
  View moved = view;
  moved.pose = SphericalPose{first.d_azimuth_rad * 0.02, first.d_elevation_rad * 0.02};
  DepthGeometryAgent following;
  following.act(view.observation());
  following.act(moved.observation());
  EXPECT_LT(following.lastPlan().target_d_elevation_rad, 0.0);

  // The rig did not move (a floor, a joint limit): no pose below that elevation is planned.
  agent.act(view.observation());
  EXPECT_GE(agent.lastPlan().target_d_elevation_rad, 0.0);
  agent.reset(0);  // a new episode forgets the limit
  EXPECT_LT(agent.act(view.observation()).d_elevation_rad, -0.5);
}

TEST(DepthGeometryAgent, RefusesViewsWithoutIntrinsicsOrPoseAndBadOptions) {
  DepthGeometryAgent agent;
  View no_intrinsics({{30, 60, 3.0f}});
  no_intrinsics.intrinsics.fx = 0.0;
  EXPECT_THROW(agent.act(no_intrinsics.observation()), InvalidArgumentError);
  View no_pose({{30, 60, 3.0f}});
  no_pose.world_from_optical = Eigen::Isometry3d::Identity();
  EXPECT_THROW(agent.act(no_pose.observation()), InvalidArgumentError);
  View wrong_size({{30, 60, 3.0f}});
  wrong_size.intrinsics = CameraIntrinsics::fromFieldOfView(2 * kSize, 2 * kSize, M_PI / 3);
  EXPECT_THROW(agent.act(wrong_size.observation()), InvalidArgumentError);

  DepthGeometryOptions bad;
  bad.voxel_fraction = 0.0;
  EXPECT_THROW(DepthGeometryAgent{bad}, InvalidArgumentError);
  bad = {};
  bad.search_radius_steps = 0.5;
  EXPECT_THROW(DepthGeometryAgent{bad}, InvalidArgumentError);
}

TEST(DepthGeometryAgent, ClearsSimulatedScenesInFewerStepsThanRandomMoves) {
  EnvironmentOptions options;  // embedded objects
  options.width = options.height = kSize;
  Environment env(options);
  DepthGeometryAgent agent;
  RandomAgent random_agent;
  EpisodeRunOptions run_options;
  run_options.max_steps = 50;
  int successes = 0, steps = 0, random_steps = 0;
  for (std::uint64_t seed = 0; seed < 8; ++seed) {
    EpisodeRequest request;
    request.agent = "depth_geometry";
    request.scene_set = "test";
    request.seed = seed;
    request.reset.start_azimuth_rad = 0.0;
    const EpisodeRecord episode = runEpisode(env, agent, request, run_options);
    successes += episode.success();
    steps += episode.countedSteps();
    request.agent = "random";
    random_steps += runEpisode(env, random_agent, request, run_options).countedSteps();
  }
  std::cout << "[depth_geometry] 8 embedded scenes: " << successes << " clear, " << steps / 8.0
            << " steps on average; random moves " << random_steps / 8.0 << "\n";
  EXPECT_EQ(successes, 8);
  EXPECT_LT(2 * steps, random_steps);
}

}  // namespace
}  // namespace occlusion_env
