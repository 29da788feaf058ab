#include "occlusion_env/occlusion/occlusion_gradient.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

constexpr int kImageSize = 256;  // [px]

/// Hand-made buffers: each object a filled axis-aligned rectangle at a constant depth.
struct HandMadeObject {
  cv::Rect rect;
  float depth_m;
};

RenderBuffers handMadeBuffers(const std::vector<HandMadeObject>& objects, int size_px) {
  RenderBuffers buffers;
  buffers.amodal_bits = cv::Mat(size_px, size_px, CV_8UC1, cv::Scalar(0));
  for (std::size_t k = 0; k < objects.size(); ++k) {
    cv::Mat depth(size_px, size_px, CV_32FC1, cv::Scalar(std::numeric_limits<float>::infinity()));
    buffers.object_depth.push_back(depth);
    if (objects[k].rect.area() == 0) continue;  // outside the view
    depth(objects[k].rect).setTo(objects[k].depth_m);
    cv::Mat bit = buffers.amodal_bits(objects[k].rect);
    bit |= cv::Scalar(1 << k);
  }
  return buffers;
}

TEST(OcclusionGradientTest, OpticalPointDerivativeMatchesTheCamerasPose) {
  const SphericalCamera camera(4.0, 1.3962634016);
  const Eigen::Vector3d world_point(1.2, -0.7, 0.4);
  for (const SphericalPose pose :
       {SphericalPose{0.0, 0.0}, SphericalPose{0.8, 0.5}, SphericalPose{-2.5, -1.1}}) {
    const Eigen::Vector3d point_optical = camera.worldFromOptical(pose).inverse() * world_point;
    const Eigen::Matrix<double, 3, 2> analytic =
        opticalPointDerivative(camera, pose, point_optical);
    const double h = 1e-6;
    for (int q = 0; q < 2; ++q) {
      SphericalPose plus = pose, minus = pose;
      (q == 0 ? plus.azimuth_rad : plus.elevation_rad) += h;
      (q == 0 ? minus.azimuth_rad : minus.elevation_rad) -= h;
      const Eigen::Vector3d numeric = (camera.worldFromOptical(plus).inverse() * world_point -
                                       camera.worldFromOptical(minus).inverse() * world_point) /
                                      (2.0 * h);
      EXPECT_LT((analytic.col(q) - numeric).norm(), 1e-6) << "angle " << q;
    }
  }
}

TEST(OcclusionGradientTest, SilhouetteInsideAnotherStillHasLossAndSlope) {
  // Object 1 (a small square, nearer) lies entirely inside object 0 (a large one, farther): the
  // hard overlap is the small square's area whichever way it moves a little, the smooth loss is
  // not constant.
  const RenderBuffers buffers = handMadeBuffers(
      {{cv::Rect(40, 40, 160, 160), 4.0f}, {cv::Rect(150, 110, 20, 20), 2.0f}}, kImageSize);
  SmoothOcclusionLoss loss(12.0);
  const double value = loss.evaluate(buffers.amodal_bits, 2);
  EXPECT_GT(value, 0.0);
  EXPECT_LT(value, 400.0);  // below the hard overlap: the small square's blur spills outside
  AnalyticOcclusionGradient gradient;
  const SphericalCamera camera(4.0, 1.3962634016);
  const CameraIntrinsics intrinsics =
      CameraIntrinsics::fromFieldOfView(kImageSize, kImageSize, 1.0471975512);
  const GradientResult result = gradient.compute(buffers, 2, intrinsics, camera, {0.0, 0.0});
  EXPECT_TRUE(result.valid) << result.reason;
  EXPECT_TRUE(result.gradient.allFinite());
  EXPECT_GT(result.gradient.norm(), 0.0);
  EXPECT_DOUBLE_EQ(result.loss, value);
  EXPECT_EQ(gradient.skippedBoundaryPixels(), 0);
}

TEST(OcclusionGradientTest, SmoothLossMatchesTheHardOverlapForWideShapesAndTinySigma) {
  const RenderBuffers buffers = handMadeBuffers(
      {{cv::Rect(20, 20, 100, 100), 4.0f}, {cv::Rect(70, 60, 100, 100), 3.0f}}, kImageSize);
  SmoothOcclusionLoss loss(0.3);  // a kernel of one pixel: no smoothing to speak of
  EXPECT_NEAR(loss.evaluate(buffers.amodal_bits, 2), 50.0 * 60.0, 1.0);
}

TEST(OcclusionGradientTest, FarApartOrSingleObjectsGiveAnInvalidZeroGradient) {
  const SphericalCamera camera(4.0, 1.3962634016);
  const CameraIntrinsics intrinsics =
      CameraIntrinsics::fromFieldOfView(kImageSize, kImageSize, 1.0471975512);
  AnalyticOcclusionGradient gradient;
  // 3 sigma = 36 px: squares 150 px apart are out of each other's reach.
  const RenderBuffers apart = handMadeBuffers(
      {{cv::Rect(10, 10, 30, 30), 4.0f}, {cv::Rect(190, 190, 30, 30), 3.0f}}, kImageSize);
  GradientResult result = gradient.compute(apart, 2, intrinsics, camera, {0.0, 0.0});
  EXPECT_FALSE(result.valid);
  EXPECT_EQ(result.loss, 0.0);
  EXPECT_EQ(result.gradient, Eigen::Vector2d::Zero());
  EXPECT_NE(result.reason.find("zero gradient"), std::string::npos) << result.reason;

  const RenderBuffers single = handMadeBuffers({{cv::Rect(10, 10, 30, 30), 4.0f}}, kImageSize);
  result = gradient.compute(single, 1, intrinsics, camera, {0.0, 0.0});
  EXPECT_FALSE(result.valid);
  EXPECT_EQ(result.gradient, Eigen::Vector2d::Zero());
  EXPECT_FALSE(result.reason.empty());

  // An empty object (outside the view) next to a visible one.
  const RenderBuffers empty =
      handMadeBuffers({{cv::Rect(10, 10, 30, 30), 4.0f}, {cv::Rect(0, 0, 0, 0), 3.0f}}, kImageSize);
  result = gradient.compute(empty, 2, intrinsics, camera, {0.0, 0.0});
  EXPECT_FALSE(result.valid);
  EXPECT_TRUE(result.gradient.allFinite());
}

TEST(OcclusionGradientTest, NoEpisodeAndBadOptionsAreReported) {
  EnvironmentOptions options;
  options.width = options.height = 64;
  Environment env(options);
  for (const char* method : {"analytic", "finite_difference"}) {
    const GradientResult result = makeOcclusionGradient(method)->compute(env);
    EXPECT_FALSE(result.valid) << method;
    EXPECT_EQ(result.gradient, Eigen::Vector2d::Zero());
    EXPECT_NE(result.reason.find("reset"), std::string::npos);
  }
  EXPECT_THROW(makeOcclusionGradient("newton"), InvalidArgumentError);
  OcclusionGradientOptions bad;
  bad.finite_difference_step_rad = 0.0;
  EXPECT_THROW(makeFiniteDifferenceGradient(bad), InvalidArgumentError);
  bad = {};
  bad.blur_sigma_px = std::nan("");
  EXPECT_THROW(makeAnalyticGradient(bad), InvalidArgumentError);
  EXPECT_THROW(SmoothOcclusionLoss(0.0), InvalidArgumentError);
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The analytic gradient against central finite differences over 100 seeded scenes of the embedded
// objects, and a small step along the negative analytic gradient. "Not negligible": the finite-
// difference gradient would change L_s by at least 1 % over one environment step (0.05 rad) along
// it, i.e. |grad_fd| * 0.05 rad >= 0.01 * L_s. Below that the reference itself is mostly pixel
// quantisation noise and the direction carries no information.
TEST(OcclusionGradientTest, AnalyticAgreesWithFiniteDifferencesOverSeededScenes) {
  EnvironmentOptions options;  // embedded objects, default scene
  options.width = options.height = kImageSize;
  Environment env(options);
  const OcclusionGradientOptions gradient_options;
  AnalyticOcclusionGradient analytic(gradient_options);
  FiniteDifferenceOcclusionGradient finite_difference(gradient_options);
  SmoothOcclusionLoss loss(blurSigmaFor(gradient_options, kImageSize));
  // Two fifths of an environment step; about 1.5-4 px of motion at 256 px (a step much below a
  // pixel often crosses no pixel centre at all: see doc/GRADIENT.md).
  const double descent_step_rad = 0.02;
  const bool verbose = std::getenv("OCCLUSION_GRADIENT_VERBOSE") != nullptr;

  std::vector<double> cosines;
  int scenes = 0, relevant = 0, cosine_above = 0, descended = 0;
  for (std::uint64_t seed = 0; seed < 100; ++seed) {
    env.reset(seed);
    ++scenes;
    const GradientResult exact = analytic.compute(env);
    const GradientResult reference = finite_difference.compute(env);
    ASSERT_TRUE(std::isfinite(exact.loss) && exact.gradient.allFinite()) << "seed " << seed;
    ASSERT_TRUE(std::isfinite(reference.loss) && reference.gradient.allFinite());
    EXPECT_DOUBLE_EQ(exact.loss, reference.loss);
    EXPECT_EQ(analytic.skippedBoundaryPixels(), 0);
    const bool not_negligible =
        reference.valid && reference.gradient.norm() * 0.05 >= 0.01 * reference.loss;
    double cosine = 0.0;
    bool lowered = false;
    if (exact.valid && reference.valid) {
      cosine = exact.gradient.dot(reference.gradient) /
               (exact.gradient.norm() * reference.gradient.norm());
    }
    if (exact.valid) {
      const Eigen::Vector2d direction = -exact.gradient.normalized();
      const SphericalPose pose = env.info().pose;
      const double moved =
          loss.evaluate(env.renderAt({pose.azimuth_rad + descent_step_rad * direction.x(),
                                      pose.elevation_rad + descent_step_rad * direction.y()})
                            .amodal_bits,
                        static_cast<int>(env.scene().objects.size()));
      lowered = moved < exact.loss;
    }
    if (verbose) {
      std::cout << "seed " << seed << " loss " << exact.loss << " analytic "
                << exact.gradient.transpose() << " fd " << reference.gradient.transpose() << " cos "
                << cosine << " relevant " << not_negligible << " lowered " << lowered << "\n";
    }
    if (!not_negligible) continue;
    ++relevant;
    cosines.push_back(cosine);
    cosine_above += cosine >= 0.8;
    descended += lowered;
  }
  ASSERT_GE(relevant, 50) << "too few scenes with a gradient to compare";
  const double median_cosine = median(cosines);
  const double fraction_above = static_cast<double>(cosine_above) / relevant;
  const double fraction_descended = static_cast<double>(descended) / relevant;
  std::cout << std::fixed << std::setprecision(3) << "[gradient check] " << scenes << " scenes, "
            << relevant << " with a non-negligible gradient: median cosine " << median_cosine
            << ", cosine >= 0.8 in " << fraction_above << ", a " << descent_step_rad
            << " rad step down the analytic gradient lowers L_s in " << fraction_descended << "\n";
  RecordProperty("scenes_compared", relevant);
  RecordProperty("median_cosine", std::to_string(median_cosine));
  RecordProperty("fraction_cosine_above_0_8", std::to_string(fraction_above));
  RecordProperty("fraction_descent_lowers_loss", std::to_string(fraction_descended));
  EXPECT_GE(median_cosine, 0.95);
  EXPECT_GE(fraction_above, 0.9);
  EXPECT_GE(fraction_descended, 0.9);
}

}  // namespace
}  // namespace occlusion_env
