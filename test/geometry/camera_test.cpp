#include "occlusion_env/geometry/camera.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

constexpr double kTolerance = 1e-12;

TEST(SphericalCameraTest, StartPoseLooksAlongMinusXFromPlusX) {
  const SphericalCamera camera(4.0, 80.0 * M_PI / 180.0);
  const SphericalPose start{0.0, 0.0};
  EXPECT_TRUE(camera.position(start).isApprox(Eigen::Vector3d(4, 0, 0), kTolerance));
  const Eigen::Isometry3d world_from_optical = camera.worldFromOptical(start);
  const Eigen::Matrix3d rotation = world_from_optical.linear();
  // Optical z forward (towards the origin), x right, y down; REP 103 world z up.
  EXPECT_TRUE(rotation.col(2).isApprox(Eigen::Vector3d(-1, 0, 0), kTolerance));
  EXPECT_TRUE(rotation.col(1).isApprox(Eigen::Vector3d(0, 0, -1), kTolerance));
  EXPECT_TRUE(rotation.col(0).isApprox(Eigen::Vector3d(0, 1, 0), kTolerance));
  // The body frame: x forward, y left, z up.
  const Eigen::Matrix3d body = camera.worldFromBody(start).linear();
  EXPECT_TRUE(body.col(0).isApprox(Eigen::Vector3d(-1, 0, 0), kTolerance));
  EXPECT_TRUE(body.col(1).isApprox(Eigen::Vector3d(0, -1, 0), kTolerance));
  EXPECT_TRUE(body.col(2).isApprox(Eigen::Vector3d(0, 0, 1), kTolerance));
}

TEST(SphericalCameraTest, EveryPoseLooksAtTheOriginWithProperRotation) {
  const SphericalCamera camera(2.5, 1.3);
  for (double azimuth = -3.1; azimuth < 3.2; azimuth += 0.37) {
    for (double elevation = -1.3; elevation <= 1.3; elevation += 0.26) {
      const SphericalPose pose{azimuth, elevation};
      const Eigen::Isometry3d world_from_optical = camera.worldFromOptical(pose);
      const Eigen::Matrix3d rotation = world_from_optical.linear();
      EXPECT_NEAR(rotation.determinant(), 1.0, 1e-12);
      EXPECT_TRUE((rotation.transpose() * rotation).isIdentity(1e-12));
      // The origin lies on the optical axis, radius metres ahead.
      const Eigen::Vector3d origin_optical = world_from_optical.inverse() * Eigen::Vector3d::Zero();
      EXPECT_NEAR(origin_optical.x(), 0.0, 1e-12);
      EXPECT_NEAR(origin_optical.y(), 0.0, 1e-12);
      EXPECT_NEAR(origin_optical.z(), 2.5, 1e-12);
      // Image "up" (-y optical) never points below the horizon: no roll.
      EXPECT_GE(-rotation.col(1).z(), 0.0);
      EXPECT_NEAR(rotation.col(0).z(), 0.0, 1e-12);  // image x stays horizontal
      EXPECT_NEAR(camera.position(pose).norm(), 2.5, 1e-12);
    }
  }
}

TEST(SphericalCameraTest, ElevationRaisesTheCameraAndAzimuthTurnsCounterClockwise) {
  const SphericalCamera camera(4.0, 1.3);
  EXPECT_GT(camera.position({0.0, 0.3}).z(), 0.0);
  EXPECT_GT(camera.position({0.3, 0.0}).y(), 0.0);  // about +z, from +x towards +y
}

TEST(SphericalCameraTest, ClampsElevationAndWrapsAzimuth) {
  const SphericalCamera camera(4.0, 80.0 * M_PI / 180.0);
  const SphericalPose high = camera.moved({0.0, 1.3}, 0.0, 0.5);
  EXPECT_DOUBLE_EQ(high.elevation_rad, 80.0 * M_PI / 180.0);
  const SphericalPose low = camera.moved({0.0, -1.3}, 0.0, -0.5);
  EXPECT_DOUBLE_EQ(low.elevation_rad, -80.0 * M_PI / 180.0);
  const SphericalPose wrapped = camera.moved({3.1, 0.0}, 0.1, 0.0);
  EXPECT_NEAR(wrapped.azimuth_rad, 3.2 - 2.0 * M_PI, 1e-12);
  EXPECT_DOUBLE_EQ(camera.normalized({-M_PI, 0.0}).azimuth_rad, M_PI);  // (-pi, pi]
}

TEST(SphericalCameraTest, AnElevationRangeOfItsOwnClampsBothEnds) {
  const SphericalCamera camera(4.0, -0.1, 1.2);  // e.g. above a floor
  EXPECT_DOUBLE_EQ(camera.lowestElevation(), -0.1);
  EXPECT_DOUBLE_EQ(camera.highestElevation(), 1.2);
  EXPECT_DOUBLE_EQ(camera.moved({0.0, 0.0}, 0.0, -0.5).elevation_rad, -0.1);
  EXPECT_DOUBLE_EQ(camera.moved({0.0, 1.0}, 0.0, 0.5).elevation_rad, 1.2);
  EXPECT_DOUBLE_EQ(camera.moved({0.0, 0.0}, 0.0, -0.05).elevation_rad, -0.05);
  const SphericalCamera symmetric(4.0, 1.2);
  EXPECT_DOUBLE_EQ(symmetric.lowestElevation(), -1.2);
  EXPECT_DOUBLE_EQ(symmetric.highestElevation(), 1.2);
  EXPECT_THROW(SphericalCamera(4.0, 0.3, 0.2), InvalidArgumentError);  // lowest above highest
  EXPECT_THROW(SphericalCamera(4.0, -M_PI / 2.0, 0.2), InvalidArgumentError);
  EXPECT_THROW(SphericalCamera(4.0, NAN, 0.2), InvalidArgumentError);
  EXPECT_NO_THROW(SphericalCamera(4.0, 0.2, 0.2));
}

TEST(SphericalCameraTest, SphericalPoseOfAPositionInvertsPosition) {
  const SphericalCamera camera(4.0, 80.0 * M_PI / 180.0);
  for (const SphericalPose pose : {SphericalPose{0.0, 0.0}, SphericalPose{0.3, -0.2},
                                   SphericalPose{-3.0, 1.2}, SphericalPose{M_PI, 0.5}}) {
    const SphericalPose recovered = sphericalPoseOf(camera.position(pose));
    EXPECT_NEAR(recovered.azimuth_rad, pose.azimuth_rad, kTolerance);
    EXPECT_NEAR(recovered.elevation_rad, pose.elevation_rad, kTolerance);
    // The distance does not count.
    const SphericalPose far = sphericalPoseOf(3.0 * camera.position(pose));
    EXPECT_NEAR(far.elevation_rad, pose.elevation_rad, kTolerance);
  }
  const SphericalPose origin = sphericalPoseOf(Eigen::Vector3d::Zero());
  EXPECT_EQ(origin.azimuth_rad, 0.0);
  EXPECT_EQ(origin.elevation_rad, 0.0);
}

TEST(SphericalCameraTest, RejectsBadConstruction) {
  EXPECT_THROW(SphericalCamera(0.0, 1.0), InvalidArgumentError);
  EXPECT_THROW(SphericalCamera(-1.0, 1.0), InvalidArgumentError);
  EXPECT_THROW(SphericalCamera(NAN, 1.0), InvalidArgumentError);
  EXPECT_THROW(SphericalCamera(4.0, M_PI / 2.0), InvalidArgumentError);
  EXPECT_THROW(SphericalCamera(4.0, -0.1), InvalidArgumentError);
}

TEST(CameraIntrinsicsTest, FromFieldOfViewUsesRosPixelCentres) {
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(256, 128, M_PI / 2.0);
  EXPECT_DOUBLE_EQ(intrinsics.fx, 128.0);  // half-width / tan(45 deg)
  EXPECT_DOUBLE_EQ(intrinsics.fy, 128.0);
  EXPECT_DOUBLE_EQ(intrinsics.cx, 127.5);
  EXPECT_DOUBLE_EQ(intrinsics.cy, 63.5);
  const Eigen::Vector2d centre = intrinsics.project({0.0, 0.0, 3.0});
  EXPECT_DOUBLE_EQ(centre.x(), 127.5);
  // A point at the edge of the field of view lands on the image's outer pixel edge.
  EXPECT_DOUBLE_EQ(intrinsics.project({1.0, 0.0, 1.0}).x(), 255.5);
  EXPECT_THROW(CameraIntrinsics::fromFieldOfView(0, 256, 1.0), InvalidArgumentError);
  EXPECT_THROW(CameraIntrinsics::fromFieldOfView(256, 256, 0.0), InvalidArgumentError);
  EXPECT_THROW(CameraIntrinsics::fromFieldOfView(256, 256, M_PI), InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
