#include "occlusion_env/occlusion/bounding_surfaces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"

namespace occlusion_env {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// 64 x 64 px, 60 deg: the network's grid of the bridge's square crop.
CameraIntrinsics grid() {
  return CameraIntrinsics::fromFieldOfView(64, 64, M_PI / 3.0);
}

// The optical depth [m] of the plane n . p + d = 0 along pixel (u, v)'s ray; NaN where the ray
// does not meet it in front of the camera.
float planeDepth(const CameraIntrinsics& k, const Eigen::Vector3d& n, double d, int u, int v) {
  const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
  const double t = -d / n.dot(ray);
  return t > 0.0 ? static_cast<float>(t) : kNaN;
}

// A floor 1.5 m below a camera pitched down by 45 deg, filling the view.
cv::Mat floorDepth(const CameraIntrinsics& k) {
  const Eigen::Vector3d up(0.0, -std::cos(M_PI / 4), -std::sin(M_PI / 4));
  cv::Mat depth(k.height, k.width, CV_32FC1);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) depth.at<float>(v, u) = planeDepth(k, up, 1.5, u, v);
  }
  return depth;
}

TEST(BoundingSurfaces, AFloorFillingTheViewIsOneSurface) {
  const CameraIntrinsics k = grid();
  BoundingSurfaceFinder finder;
  cv::Mat on_surface;
  const auto& planes = finder.find(floorDepth(k), k, on_surface);
  ASSERT_EQ(planes.size(), 1u);
  EXPECT_NEAR(planes[0].offset_m, 1.5, 1e-3);
  EXPECT_NEAR(planes[0].normal.y(), -std::cos(M_PI / 4), 1e-3);
  EXPECT_EQ(cv::countNonZero(on_surface), 64 * 64);
}

TEST(BoundingSurfaces, AnObjectOnTheFloorIsNotPartOfIt) {
  const CameraIntrinsics k = grid();
  cv::Mat depth = floorDepth(k);
  const cv::Rect box(20, 20, 16, 16);  // something 0.5 m nearer than the floor behind it
  depth(box) -= 0.5f;
  BoundingSurfaceFinder finder;
  cv::Mat on_surface;
  EXPECT_EQ(finder.find(depth, k, on_surface).size(), 1u);
  EXPECT_EQ(cv::countNonZero(on_surface(box)), 0);
  EXPECT_EQ(cv::countNonZero(on_surface), 64 * 64 - box.area());
}

TEST(BoundingSurfaces, AnObjectsFaceWithSomethingSeenBehindItIsNot) {
  // A flat face 2 m away over the middle of the view, more than half of it; around it a wall
  // 4 m away. The face is the largest plane, but the wall is seen beyond it.
  const CameraIntrinsics k = grid();
  cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(4.0f));
  const cv::Rect face(8, 8, 48, 48);
  depth(face).setTo(2.0f);
  BoundingSurfaceFinder finder;
  cv::Mat on_surface;
  const auto& planes = finder.find(depth, k, on_surface);
  ASSERT_EQ(planes.size(), 1u);
  EXPECT_NEAR(planes[0].offset_m, 4.0, 1e-3);
  EXPECT_EQ(cv::countNonZero(on_surface(face)), 0);
  EXPECT_EQ(cv::countNonZero(on_surface), 64 * 64 - face.area());
}

TEST(BoundingSurfaces, ANoisyFloorAt4MetresIsFoundAndTheVoidIsNothing) {
  // The top half is the void (no reading), the bottom a floor 4-6 m away read with a stereo
  // camera's error (sigma 0.0037 z^2 per pixel, averaged over a block of 16: a quarter of it).
  const CameraIntrinsics k = grid();
  const Eigen::Vector3d up(0.0, -std::cos(0.3), -std::sin(0.3));
  cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(kNaN));
  RandomSource random(7);
  for (int v = 32; v < 64; ++v) {
    for (int u = 0; u < 64; ++u) {
      const float z = planeDepth(k, up, 1.6, u, v);
      depth.at<float>(v, u) = z + static_cast<float>(random.normal(0.0, 0.0037 * z * z / 4));
    }
  }
  BoundingSurfaceFinder finder;
  cv::Mat on_surface;
  const auto& planes = finder.find(depth, k, on_surface);
  ASSERT_EQ(planes.size(), 1u);
  EXPECT_EQ(cv::countNonZero(on_surface(cv::Rect(0, 0, 64, 32))), 0);
  EXPECT_GT(cv::countNonZero(on_surface), 0.95 * 64 * 32);

  // The same depth gives the same planes and mask.
  cv::Mat again;
  const std::vector<SurfacePlane> first = planes;
  const auto& second = finder.find(depth, k, again);
  ASSERT_EQ(second.size(), first.size());
  EXPECT_EQ(second[0].normal, first[0].normal);
  EXPECT_EQ(cv::countNonZero(again != on_surface), 0);
}

TEST(BoundingSurfaces, TooLittleOfAPlaneIsNone) {
  // A floor in one row of the view is under min_support.
  const CameraIntrinsics k = grid();
  cv::Mat depth(64, 64, CV_32FC1, cv::Scalar(kNaN));
  floorDepth(k).row(63).copyTo(depth.row(63));
  BoundingSurfaceFinder finder;
  cv::Mat on_surface;
  EXPECT_TRUE(finder.find(depth, k, on_surface).empty());
  EXPECT_EQ(cv::countNonZero(on_surface), 0);
}

TEST(BoundingSurfaces, BadOptionsAndInputsAreRefused) {
  BoundingSurfaceOptions options;
  options.min_support = 0.0;
  EXPECT_THROW(BoundingSurfaceFinder{options}, InvalidArgumentError);
  options = {};
  options.tolerance_m = options.tolerance_per_m2 = 0.0;
  EXPECT_THROW(BoundingSurfaceFinder{options}, InvalidArgumentError);
  options = {};
  options.max_behind = 1.0;
  EXPECT_THROW(BoundingSurfaceFinder{options}, InvalidArgumentError);
  BoundingSurfaceFinder finder;
  cv::Mat on_surface;
  EXPECT_THROW(finder.find(cv::Mat(8, 8, CV_8UC1), grid(), on_surface), InvalidArgumentError);
  CameraIntrinsics no_focal_length = grid();
  no_focal_length.fx = 0.0;
  EXPECT_THROW(finder.find(cv::Mat(8, 8, CV_32FC1, cv::Scalar(1.0f)), no_focal_length, on_surface),
               InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
