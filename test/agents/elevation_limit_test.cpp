// ElevationLimitTracker: an agent tells from the rig's pose and its own moves that a floor (or the
// top of the rig's reach) stopped it, and turns along it.
#include <gtest/gtest.h>

#include <cmath>

#include "agents/rig_path.hpp"
#include "occlusion_env/agents/elevation_limit.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

using testing_support::rigAt;

TEST(ElevationLimitTest, AMoveTheRigStoppedBlocksThatWayUntilItMovesBack) {
  ElevationLimitTracker tracker;
  tracker.observe(rigAt(0.0, 0.1, {}, 0));
  EXPECT_EQ(tracker.blockedDirection(), 0);
  // Down and right by a step of 0.2 rad, done in full.
  tracker.observe(rigAt(0.12, -0.06, {0.6, -0.8}, 1));
  EXPECT_EQ(tracker.blockedDirection(), 0);
  // The same move, the elevation stopped after 0.02 rad (a floor at -0.08).
  tracker.observe(rigAt(0.24, -0.08, {0.6, -0.8}, 2));
  EXPECT_EQ(tracker.blockedDirection(), -1);
  // Down, not moving at all in elevation; along the floor: still blocked.
  tracker.observe(rigAt(0.24, -0.08, {0.0, -1.0}, 3));
  EXPECT_EQ(tracker.blockedDirection(), -1);
  tracker.observe(rigAt(0.44, -0.08, {1.0, 0.0}, 4));
  EXPECT_EQ(tracker.blockedDirection(), -1);
  // Up: free again.
  tracker.observe(rigAt(0.44, 0.12, {0.0, 1.0}, 5));
  EXPECT_EQ(tracker.blockedDirection(), 0);
}

TEST(ElevationLimitTest, TheTopOfTheReachAndTheAzimuthsSeamAreReadAlike) {
  ElevationLimitTracker tracker;
  tracker.observe(rigAt(3.1, 1.35, {}, 0));
  // Up and across +-pi: azimuth 3.1 + 0.1 wraps to -3.083; the elevation stopped at 1.4.
  tracker.observe(rigAt(3.2 - 2.0 * M_PI, 1.4, {0.5, 1.0}, 1));
  EXPECT_EQ(tracker.blockedDirection(), 1);
  // A reset forgets it.
  tracker.observe(rigAt(0.0, 0.0, {}, 0));
  EXPECT_EQ(tracker.blockedDirection(), 0);
  // Across the seam in full: 0.1 in azimuth, 0.2 in elevation.
  tracker.observe(rigAt(3.1, 0.0, {}, 0));
  tracker.observe(rigAt(3.2 - 2.0 * M_PI, 0.2, {0.5, 1.0}, 1));
  EXPECT_EQ(tracker.blockedDirection(), 0);
}

TEST(ElevationLimitTest, OnlyADirectionIntoTheLimitTurnsAlongIt) {
  ElevationLimitTracker tracker;
  const Action down_left{-0.28, -0.96};
  EXPECT_DOUBLE_EQ(tracker.alongTheLimit(down_left).d_elevation_rad, -0.96);  // not blocked
  tracker.observe(rigAt(0.0, -0.08, {}, 0));
  tracker.observe(rigAt(0.1, -0.08, {0.5, -0.5}, 1));
  ASSERT_EQ(tracker.blockedDirection(), -1);
  const Action along = tracker.alongTheLimit(down_left);
  EXPECT_DOUBLE_EQ(along.d_elevation_rad, 0.0);
  EXPECT_NEAR(along.d_azimuth_rad, -1.0, 1e-12);  // the whole length, on its azimuth's side
  const Action up{0.6, 0.8};
  EXPECT_DOUBLE_EQ(tracker.alongTheLimit(up).d_elevation_rad, 0.8);
  // Once along the limit to the left, it keeps going left whatever side the direction leans.
  tracker.observe(rigAt(0.0, -0.08, {-0.28, 0.0}, 2));
  EXPECT_NEAR(tracker.alongTheLimit({0.28, -0.96}).d_azimuth_rad, -1.0, 1e-12);
  EXPECT_DOUBLE_EQ(tracker.alongTheLimit({0.28, 0.96}).d_azimuth_rad, 0.28);  // up: as it is
  // Straight down, before any move along the limit: on the side of the last move's azimuth.
  tracker.observe(rigAt(0.1, -0.08, {}, 0));
  tracker.observe(rigAt(0.0, -0.08, {-0.5, -0.5}, 1));
  ASSERT_EQ(tracker.blockedDirection(), -1);
  EXPECT_NEAR(tracker.alongTheLimit({0.0, -2.0}).d_azimuth_rad, -2.0, 1e-12);
  tracker.observe(rigAt(0.0, -0.08, {}, 0));
  tracker.observe(rigAt(0.1, -0.08, {0.5, -0.5}, 1));
  ASSERT_EQ(tracker.blockedDirection(), -1);
  EXPECT_NEAR(tracker.alongTheLimit({0.0, -2.0}).d_azimuth_rad, 2.0, 1e-12);
}

TEST(ElevationLimitTest, ARoomsFloorIsNoticedFromTheEnvironmentsSteps) {
  EnvironmentOptions options;
  options.width = options.height = 64;
  options.world.world = "room";
  options.world.clutter = 0;
  Environment env(options);
  env.reset(3);  // the floor's limit is the scene's
  ResetOptions low;
  low.start_elevation_rad = env.camera().lowestElevation() + 0.5 * options.step_size_rad;
  ElevationLimitTracker tracker;
  StepResult result = env.reset(3, low);
  tracker.observe(rigObservationOf(result));
  // Straight down: half a step, then the floor. Without an azimuth part the tracker cannot tell
  // a short move from a stopped one; the next move down does not move at all.
  result = env.step({0.0, -1.0});
  tracker.observe(rigObservationOf(result));
  EXPECT_EQ(tracker.blockedDirection(), 0);
  result = env.step({0.0, -1.0});
  tracker.observe(rigObservationOf(result));
  EXPECT_EQ(tracker.blockedDirection(), -1);
  ResetOptions lower = low;
  lower.start_elevation_rad = env.camera().lowestElevation() + 0.3 * options.step_size_rad;
  tracker.observe(rigObservationOf(env.reset(3, lower)));
  // Oblique: 0.89 of a step asked down, 0.3 done; the azimuth says how far it should have gone.
  result = env.step({0.5, -1.0});
  tracker.observe(rigObservationOf(result));
  EXPECT_EQ(tracker.blockedDirection(), -1);
  result = env.step({1.0, 0.0});  // along the floor
  tracker.observe(rigObservationOf(result));
  EXPECT_EQ(tracker.blockedDirection(), -1);
  result = env.step({0.0, 1.0});
  tracker.observe(rigObservationOf(result));
  EXPECT_EQ(tracker.blockedDirection(), 0);
}

}  // namespace
}  // namespace occlusion_env
