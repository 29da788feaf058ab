// RevisitGuard: an agent remembers its last views and does not step back onto one.
#include <gtest/gtest.h>

#include <cmath>

#include "agents/rig_path.hpp"
#include "occlusion_env/agents/revisit_guard.hpp"

namespace occlusion_env {
namespace {

using testing_support::rigAt;

// Where a move along `direction` of `step` [rad] from `from` lands.
SphericalPose landing(const SphericalPose& from, const Action& direction, double step) {
  const double length = std::hypot(direction.d_azimuth_rad, direction.d_elevation_rad);
  return {from.azimuth_rad + step * direction.d_azimuth_rad / length,
          from.elevation_rad + step * direction.d_elevation_rad / length};
}

TEST(RevisitGuardTest, AMoveBackOntoTheLastViewTurnsAsideByTheSmallestAngle) {
  RevisitGuard guard;
  guard.observe(rigAt(0.0, 0.0, {}, 0));
  EXPECT_DOUBLE_EQ(guard.awayFromRecentViews({-1.0, 0.0}).d_azimuth_rad, -1.0);  // no move yet
  guard.observe(rigAt(0.05, 0.0, {1.0, 0.0}, 1));  // a step of 0.05 rad to the right
  const Action ahead{0.6, 0.8};
  EXPECT_DOUBLE_EQ(guard.awayFromRecentViews(ahead).d_azimuth_rad, 0.6);  // a new view
  const Action back{-2.0, 0.0};                                           // onto the start
  const Action turned = guard.awayFromRecentViews(back);
  EXPECT_NEAR(std::hypot(turned.d_azimuth_rad, turned.d_elevation_rad), 2.0, 1e-12);
  EXPECT_NEAR(std::atan2(std::abs(turned.d_elevation_rad), -turned.d_azimuth_rad), M_PI / 4.0,
              1e-12);
  const SphericalPose lands = landing({0.05, 0.0}, turned, 0.05);
  EXPECT_GT(std::hypot(lands.azimuth_rad, lands.elevation_rad), 0.025);
}

TEST(RevisitGuardTest, ItRemembersThreeViewsBackAndForgetsAtAReset) {
  RevisitGuard guard;
  // A square of steps of 0.05 rad: right, up, left; down would close it.
  guard.observe(rigAt(0.0, 0.0, {}, 0));
  guard.observe(rigAt(0.05, 0.0, {1.0, 0.0}, 1));
  guard.observe(rigAt(0.05, 0.05, {0.0, 1.0}, 2));
  guard.observe(rigAt(0.0, 0.05, {-1.0, 0.0}, 3));
  const Action down{0.0, -1.0};
  const Action turned = guard.awayFromRecentViews(down);
  EXPECT_NE(turned.d_azimuth_rad, 0.0);
  const SphericalPose lands = landing({0.0, 0.05}, turned, 0.05);
  EXPECT_GT(std::hypot(lands.azimuth_rad, lands.elevation_rad), 0.025);
  // Four views on, the start is forgotten.
  guard.observe(rigAt(-0.05, 0.05, {-1.0, 0.0}, 4));
  guard.observe(rigAt(-0.05, 0.0, {0.0, -1.0}, 5));
  EXPECT_DOUBLE_EQ(guard.awayFromRecentViews({1.0, 0.0}).d_elevation_rad, 0.0);
  // A reset forgets every view.
  guard.observe(rigAt(0.0, 0.0, {}, 0));
  EXPECT_DOUBLE_EQ(guard.awayFromRecentViews({1.0, 0.0}).d_elevation_rad, 0.0);
}

TEST(RevisitGuardTest, TheAzimuthsSeamIsNoWayBack) {
  RevisitGuard guard;
  guard.observe(rigAt(M_PI - 0.02, 0.0, {}, 0));
  guard.observe(rigAt(-M_PI + 0.03, 0.0, {1.0, 0.0}, 1));  // across +-pi
  const Action back = guard.awayFromRecentViews({-1.0, 0.0});
  EXPECT_NE(back.d_elevation_rad, 0.0);
  EXPECT_DOUBLE_EQ(guard.awayFromRecentViews({1.0, 0.0}).d_elevation_rad, 0.0);
}

}  // namespace
}  // namespace occlusion_env
