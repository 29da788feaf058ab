// The depth-sensor models against their formulas on synthetic walls, where they lose pixels, and
// their determinism; the environment's observation through a sensor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <tuple>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/sensor/camera_sensor.hpp"

namespace occlusion_env {
namespace {

constexpr int kSize = 256;
const CameraIntrinsics kIntrinsics = CameraIntrinsics::fromFieldOfView(kSize, kSize, M_PI / 3.0);

cv::Mat grey() {
  return cv::Mat(kSize, kSize, CV_8UC3, cv::Scalar(128, 128, 128));
}

/// A fronto-parallel wall at `z_m`.
cv::Mat wall(float z_m) {
  return cv::Mat(kSize, kSize, CV_32FC1, cv::Scalar(z_m));
}

/// A wall at 2 m with a 64 x 64 px box face at 1 m in the middle (columns and rows 96..159).
cv::Mat boxBeforeWall() {
  cv::Mat depth = wall(2.0f);
  depth(cv::Rect(96, 96, 64, 64)).setTo(1.0f);
  return depth;
}

cv::Mat measure(const std::string& sensor, const cv::Mat& depth, std::uint64_t seed) {
  SensorOptions options;
  options.depth_sensor = sensor;
  CameraSensor camera(options);
  camera.startEpisode(seed);
  camera.apply(grey(), depth, kIntrinsics);
  return camera.depth().clone();
}

/// The per-pixel standard deviation each model promises for a fronto-parallel wall at z (its
/// documented formula, plus the variance of the 1 mm quantisation).
double promisedSigma(const std::string& sensor, double z) {
  const SensorParameters p;
  double sigma = 0.0;
  double step = 0.0;
  if (sensor == "kinect_v1") {
    sigma = 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4);
    step = p.kinect_v1.quantisation_m;
  } else if (sensor == "realsense_d435") {
    sigma = z * z * p.realsense_d435.disparity_sigma_px /
            (p.realsense_d435.focal_length_px * p.realsense_d435.baseline_m);
    step = p.realsense_d435.quantisation_m;
  } else {
    sigma = p.azure_kinect.axial_constant_m + p.azure_kinect.axial_linear * z;
    step = p.azure_kinect.quantisation_m;
  }
  return std::sqrt(sigma * sigma + step * step / 12.0);
}

struct Region {
  double invalid_fraction = 0.0;
  double error_sigma = 0.0;  // of measured - ideal over the valid pixels
  double error_mean = 0.0;
};

Region inspect(const cv::Mat& measured, const cv::Mat& ideal, const cv::Rect& rect) {
  double sum = 0.0, sum_sq = 0.0;
  long valid = 0, invalid = 0;
  for (int v = rect.y; v < rect.y + rect.height; ++v) {
    for (int u = rect.x; u < rect.x + rect.width; ++u) {
      const float z = measured.at<float>(v, u);
      if (!std::isfinite(z)) {
        ++invalid;
        continue;
      }
      const double error = z - ideal.at<float>(v, u);
      sum += error;
      sum_sq += error * error;
      ++valid;
    }
  }
  Region region;
  region.invalid_fraction = static_cast<double>(invalid) / rect.area();
  if (valid > 1) {
    region.error_mean = sum / valid;
    region.error_sigma = std::sqrt(sum_sq / valid - region.error_mean * region.error_mean);
  }
  return region;
}

class DepthSensorTest : public ::testing::TestWithParam<std::string> {};

TEST_P(DepthSensorTest, NoiseOnAFlatWallMatchesTheFormula) {
  const cv::Rect centre(64, 64, 128, 128);
  for (const float z : {1.0f, 2.0f, 3.0f}) {
    const cv::Mat ideal = wall(z);
    const Region region = inspect(measure(GetParam(), ideal, 5), ideal, centre);
    const double promised = promisedSigma(GetParam(), z);
    std::printf("%s at %.0f m: sigma %.5f m, formula %.5f m, ratio %.3f, mean %+.6f m\n",
                GetParam().c_str(), z, region.error_sigma, promised, region.error_sigma / promised,
                region.error_mean);
    EXPECT_NEAR(region.error_sigma / promised, 1.0, 0.15)
        << GetParam() << " at " << z << " m: measured " << region.error_sigma << " m, formula "
        << promised << " m";
    EXPECT_LT(std::abs(region.error_mean), 0.2 * promised) << GetParam() << " biased at " << z;
  }
}

TEST_P(DepthSensorTest, HolesOnlyAtDiscontinuitiesNotInTheMiddleOfAWall) {
  const SensorParameters p;
  const double hole_rate = GetParam() == "kinect_v1"        ? p.kinect_v1.hole_rate
                           : GetParam() == "realsense_d435" ? p.realsense_d435.hole_rate
                                                            : p.azure_kinect.hole_rate;
  const cv::Mat ideal = boxBeforeWall();
  const cv::Mat measured = measure(GetParam(), ideal, 9);
  // The wall away from the box and from the image's left border; the box face's inside.
  const cv::Rect wall_middle(180, 20, 60, 216);
  const cv::Rect box_middle(104, 104, 48, 48);
  for (const cv::Rect& flat : {wall_middle, box_middle}) {
    const double allowed = hole_rate + 4.0 * std::sqrt(hole_rate / flat.area()) + 1e-9;
    EXPECT_LE(inspect(measured, ideal, flat).invalid_fraction, allowed) << GetParam();
  }
  // Along the box's edges a real sensor loses (or, for ToF, corrupts) pixels.
  long lost = 0, edge_pixels = 0;
  for (int v = 100; v < 156; ++v) {
    for (const int u : {94, 95, 96, 159, 160, 161}) {
      const float z = measured.at<float>(v, u);
      ++edge_pixels;
      if (!std::isfinite(z) || std::abs(z - ideal.at<float>(v, u)) > 0.05f) ++lost;
    }
  }
  std::printf("%s: %.3f of the pixels beside the box's edges lost or off by > 5 cm\n",
              GetParam().c_str(), static_cast<double>(lost) / edge_pixels);
  EXPECT_GT(static_cast<double>(lost) / edge_pixels, 0.3) << GetParam();
}

TEST_P(DepthSensorTest, SameSeedGivesBitIdenticalFramesAnotherSeedOthers) {
  const cv::Mat ideal = boxBeforeWall();
  const cv::Mat first = measure(GetParam(), ideal, 21);
  const cv::Mat again = measure(GetParam(), ideal, 21);
  const cv::Mat other = measure(GetParam(), ideal, 22);
  const std::size_t bytes = first.total() * first.elemSize();
  EXPECT_EQ(std::memcmp(first.data, again.data, bytes), 0);
  EXPECT_NE(std::memcmp(first.data, other.data, bytes), 0);
}

INSTANTIATE_TEST_SUITE_P(Models, DepthSensorTest,
                         ::testing::Values("kinect_v1", "realsense_d435", "azure_kinect"));

// The share of an image a discontinuity spoils is the sensor's, whatever the render's size: a
// coarse pixel holds several sensor pixels, of which only those in the sensor's edge band drop.
// The share of pixels without a reading beside the box's right edge (the left one also has the
// second view's shadow; azure_kinect's flying pixels and multipath, which read, are not counted),
// 10 seeds.
double lostBesideTheRightEdge(const std::string& sensor, int size) {
  const CameraIntrinsics intrinsics = CameraIntrinsics::fromFieldOfView(size, size, M_PI / 3.0);
  cv::Mat ideal(size, size, CV_32FC1, cv::Scalar(2.0f));
  ideal(cv::Rect(3 * size / 8, 3 * size / 8, size / 4, size / 4)).setTo(1.0f);
  const cv::Rect beside(5 * size / 8 - size / 16, 3 * size / 8 + size / 16, size / 8, size / 8);
  SensorOptions options;
  options.depth_sensor = sensor;
  CameraSensor camera(options);
  const cv::Mat colour(size, size, CV_8UC3, cv::Scalar(128, 128, 128));
  long lost = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    camera.startEpisode(seed);
    camera.apply(colour, ideal, intrinsics);
    for (int v = beside.y; v < beside.y + beside.height; ++v) {
      for (int u = beside.x; u < beside.x + beside.width; ++u) {
        const float z = camera.depth().at<float>(v, u);
        if (!std::isfinite(z)) ++lost;
      }
    }
  }
  return static_cast<double>(lost) / (10.0 * beside.area());
}

TEST(DepthSensorEdgesTest, ACoarseRenderLosesTheSameShareAtEdges) {
  // realsense_d435: 2 sensor px at f = 430 px are 0.5 px at 128 px (60 deg) and 2.1 at 512;
  // azure_kinect: a sensor pixel (f = 209 px) is 0.27 of a 64 px pixel's width, 0.8 of 192's.
  for (const auto& [sensor, coarse, fine] :
       {std::tuple<std::string, int, int>{"realsense_d435", 128, 512},
        std::tuple<std::string, int, int>{"azure_kinect", 64, 192}}) {
    const double lost_coarse = lostBesideTheRightEdge(sensor, coarse);
    const double lost_fine = lostBesideTheRightEdge(sensor, fine);
    std::printf("%s: %.4f of the pixels beside an edge without depth at %d px, %.4f at %d px\n",
                sensor.c_str(), lost_coarse, coarse, lost_fine, fine);
    EXPECT_GT(lost_fine, 0.01) << sensor;
    EXPECT_NEAR(lost_coarse / lost_fine, 1.0, 0.3) << sensor;
  }
}

TEST(KinectV1Test, ProjectorShadowLiesLeftOfTheEdgeWithTheBaselineWidth) {
  const cv::Mat ideal = boxBeforeWall();
  const cv::Mat measured = measure("kinect_v1", ideal, 3);
  // Width f b (1/z_near - 1/z_far) = 221.7 * 0.075 * 0.5 = 8.3 px, left of column 96.
  const double width = kIntrinsics.fx * 0.075 * (1.0 / 1.0 - 1.0 / 2.0);
  const int inner = static_cast<int>(std::floor(width)) - 1;
  EXPECT_GT(inspect(measured, ideal, cv::Rect(96 - inner, 100, inner - 1, 56)).invalid_fraction,
            0.95);
  EXPECT_LT(inspect(measured, ideal, cv::Rect(96 - inner - 6, 100, 4, 56)).invalid_fraction, 0.05);
  EXPECT_LT(inspect(measured, ideal, cv::Rect(162, 100, 10, 56)).invalid_fraction, 0.05);
}

TEST(RealSenseD435Test, LeftBandAndRangeLimitsHaveNoDepth) {
  const cv::Mat ideal = wall(2.0f);
  const cv::Mat measured = measure("realsense_d435", ideal, 4);
  // u < f B / z = 5.5 px: the right imager does not see these columns.
  EXPECT_EQ(inspect(measured, ideal, cv::Rect(0, 0, 5, kSize)).invalid_fraction, 1.0);
  EXPECT_LT(inspect(measured, ideal, cv::Rect(8, 0, 8, kSize)).invalid_fraction, 0.02);
  const cv::Mat too_near = wall(0.2f);
  EXPECT_EQ(inspect(measure("realsense_d435", too_near, 4), too_near, cv::Rect(64, 64, 64, 64))
                .invalid_fraction,
            1.0);
  const cv::Mat dark_wall = wall(1.0f);
  SensorOptions options;
  options.depth_sensor = "realsense_d435";
  CameraSensor camera(options);
  camera.startEpisode(4);
  camera.apply(cv::Mat(kSize, kSize, CV_8UC3, cv::Scalar(5, 5, 5)), dark_wall, kIntrinsics);
  EXPECT_NEAR(inspect(camera.depth(), dark_wall, cv::Rect(64, 64, 128, 128)).invalid_fraction, 0.5,
              0.05);
}

TEST(AzureKinectTest, ConcaveCornerReadsFartherThanItIs) {
  // A vertical concave corner: depth rises linearly to the middle column, then falls.
  cv::Mat ideal(kSize, kSize, CV_32FC1);
  for (int u = 0; u < kSize; ++u) {
    ideal.col(u).setTo(2.0f + 0.004f * static_cast<float>(kSize / 2 - std::abs(u - kSize / 2)));
  }
  const Region corner =
      inspect(measure("azure_kinect", ideal, 6), ideal, cv::Rect(127, 0, 3, kSize));
  const Region plane =
      inspect(measure("azure_kinect", ideal, 6), ideal, cv::Rect(40, 0, 40, kSize));
  EXPECT_GT(corner.error_mean, 0.004);
  EXPECT_LT(std::abs(plane.error_mean), 0.001);
}

// The colour noise: per channel, sigma^2 = read^2 + shot * signal around the exposed and
// white-balanced level (doc/SENSORS.md), and independent from pixel to pixel.
TEST(ColourEffectsTest, NoiseMatchesItsModelAndIsUncorrelated) {
  const RgbEffectParameters p;
  for (const int level : {10, 60, 128, 220}) {
    SensorOptions options;
    options.depth_sensor = "realsense_d435";
    CameraSensor camera(options);
    camera.startEpisode(7);
    camera.apply(cv::Mat(kSize, kSize, CV_8UC3, cv::Scalar(level, level, level)), wall(2.0f),
                 kIntrinsics);
    const cv::Mat& rgb = camera.rgb();
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0, sum_sq = 0.0, lag_sum = 0.0;
      long n = 0, lags = 0;
      for (int v = 8; v < kSize - 8; ++v) {
        for (int u = 8; u < kSize - 8; ++u) {
          const double x = rgb.at<cv::Vec3b>(v, u)[c];
          sum += x;
          sum_sq += x * x;
          ++n;
        }
      }
      const double mean = sum / n;
      const double sigma = std::sqrt(sum_sq / n - mean * mean);
      for (int v = 8; v < kSize - 8; ++v) {
        for (int u = 8; u < kSize - 9; ++u) {
          lag_sum += (rgb.at<cv::Vec3b>(v, u)[c] - mean) * (rgb.at<cv::Vec3b>(v, u + 1)[c] - mean);
          ++lags;
        }
      }
      // The gain (exposure x white balance) is drawn per episode: read it off the mean. Rounding
      // to whole levels adds 1/12 to the variance.
      const double promised =
          std::sqrt(p.read_noise * p.read_noise + p.shot_noise * mean + 1.0 / 12.0);
      const double correlation = lag_sum / lags / (sigma * sigma);
      std::printf("level %d channel %d: mean %.1f sigma %.3f model %.3f, neighbour corr. %+.3f\n",
                  level, c, mean, sigma, promised, correlation);
      EXPECT_NEAR(sigma / promised, 1.0, 0.1) << "level " << level << " channel " << c;
      EXPECT_LT(std::abs(correlation), 0.05) << "level " << level << " channel " << c;
    }
  }
}

TEST(SensorParametersTest, ShippedFileHoldsTheBuiltInValues) {
  const SensorParameters shipped =
      loadSensorParameters(std::string(OCCLUSION_ENV_SOURCE_DIR) + "/config/sensors.yaml");
  const SensorParameters built_in;
  EXPECT_EQ(std::memcmp(&shipped.kinect_v1, &built_in.kinect_v1, sizeof(KinectV1Parameters)), 0);
  EXPECT_EQ(std::memcmp(&shipped.realsense_d435, &built_in.realsense_d435,
                        sizeof(RealSenseD435Parameters)),
            0);
  EXPECT_EQ(
      std::memcmp(&shipped.azure_kinect, &built_in.azure_kinect, sizeof(AzureKinectParameters)), 0);
  EXPECT_EQ(shipped.rgb.exposure_log2_range, built_in.rgb.exposure_log2_range);
  EXPECT_EQ(shipped.rgb.white_balance_range, built_in.rgb.white_balance_range);
  EXPECT_EQ(shipped.rgb.read_noise, built_in.rgb.read_noise);
  EXPECT_EQ(shipped.rgb.shot_noise, built_in.rgb.shot_noise);
  EXPECT_EQ(shipped.rgb.blur_sigma_px, built_in.rgb.blur_sigma_px);
  EXPECT_EQ(shipped.rgb.jpeg_quality, built_in.rgb.jpeg_quality);
  EXPECT_EQ(shipped.edge.max_slope, built_in.edge.max_slope);
}

TEST(SensorParametersTest, UnknownSensorIsRefused) {
  SensorOptions options;
  options.depth_sensor = "kinect_v3";
  EXPECT_THROW(CameraSensor{options}, InvalidArgumentError);
}

// The environment: the observation goes through the sensor, the occlusion count does not.
EnvironmentOptions smallOptions(const std::string& sensor) {
  EnvironmentOptions options;
  options.width = options.height = 128;
  options.sensor.depth_sensor = sensor;
  return options;
}

bool sameBytes(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

TEST(EnvironmentSensorTest, SameSeedSameFramesAndTheOcclusionOfTheIdealCamera) {
  Environment ideal(smallOptions("ideal"));
  Environment first(smallOptions("realsense_d435"));
  Environment second(smallOptions("realsense_d435"));
  StepResult a = first.reset(17);
  StepResult b = second.reset(17);
  StepResult c = ideal.reset(17);
  for (int t = 0; t < 4; ++t) {
    EXPECT_TRUE(sameBytes(a.observation->depth, b.observation->depth)) << "step " << t;
    EXPECT_TRUE(sameBytes(a.observation->rgb, b.observation->rgb)) << "step " << t;
    EXPECT_FALSE(sameBytes(a.observation->depth, c.observation->depth)) << "step " << t;
    EXPECT_FALSE(sameBytes(a.observation->rgb, c.observation->rgb)) << "step " << t;
    EXPECT_TRUE(sameBytes(first.renderBuffers().depth, ideal.renderBuffers().depth));
    EXPECT_TRUE(sameBytes(a.observation->occlusion_mask, c.observation->occlusion_mask));
    EXPECT_EQ(a.info.occlusion.total_pixels, c.info.occlusion.total_pixels);
    EXPECT_EQ(a.reward, c.reward);
    a = first.step({1.0, 0.2});
    b = second.step({1.0, 0.2});
    c = ideal.step({1.0, 0.2});
  }
}

}  // namespace
}  // namespace occlusion_env
