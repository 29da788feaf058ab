#include "occlusion_env/sensor/camera_sensor.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

/// Separates the sensor's random stream from the scene's, which reset() seeds with the same seed.
constexpr std::uint64_t kSensorStream = 0x5e4503c0ffee1234ULL;

/// n equiprobable values of the standard normal: the quantiles at (k + 1/2) / n, scaled to unit
/// variance.
template <int n>
std::array<float, n> normalLevels() {
  std::array<double, n> levels;
  double sum_sq = 0.0;
  for (int k = 0; k < n; ++k) {
    const double p = (k + 0.5) / n;
    double lo = -10.0, hi = 10.0;  // Phi(x) = erfc(-x / sqrt 2) / 2, bisected
    for (int iteration = 0; iteration < 100; ++iteration) {
      const double mid = 0.5 * (lo + hi);
      (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
    }
    levels[k] = 0.5 * (lo + hi);
    sum_sq += levels[k] * levels[k];
  }
  std::array<float, n> scaled;
  for (int k = 0; k < n; ++k) scaled[k] = static_cast<float>(levels[k] / std::sqrt(sum_sq / n));
  return scaled;
}

SensorParameters parametersFor(const SensorOptions& options) {
  options.validate();
  return options.parameters_file.empty() ? SensorParameters{}
                                         : loadSensorParameters(options.parameters_file);
}

}  // namespace

const std::array<float, 256>& standardNormalLevels() {
  static const std::array<float, 256> levels = normalLevels<256>();
  return levels;
}

void SensorOptions::validate() const {
  const std::vector<std::string>& names = depthSensorNames();
  if (std::find(names.begin(), names.end(), depth_sensor) == names.end()) {
    throw InvalidArgumentError(
        "option 'depth_sensor' must be one of ideal, kinect_v1, realsense_d435, azure_kinect, "
        "got " +
        quoted(depth_sensor));
  }
}

CameraSensor::CameraSensor(const SensorOptions& options)
    : CameraSensor(options, parametersFor(options)) {}

CameraSensor::CameraSensor(const SensorOptions& options, const SensorParameters& parameters)
    : options_(options), parameters_(parameters) {
  options_.validate();
  occlusion_env::validate(parameters_);
  depth_model_ = makeDepthSensorModel(options_.depth_sensor, parameters_);
  startEpisode(0);
}

CameraSensor::~CameraSensor() = default;

void CameraSensor::startEpisode(std::uint64_t seed) {
  random_ = RandomSource(seed ^ kSensorStream);
  const RgbEffectParameters& rgb = parameters_.rgb;
  static_assert(kNoiseLevels == 256, "one random byte per channel");
  const std::array<float, 256>& normal = standardNormalLevels();
  colour_table_.resize(3 * 256 * kNoiseLevels);
  const double exposure =
      std::exp2(random_.uniform(-rgb.exposure_log2_range, rgb.exposure_log2_range));
  for (int c = 0; c < 3; ++c) {
    const double gain =
        exposure * (1.0 + random_.uniform(-rgb.white_balance_range, rgb.white_balance_range));
    for (int value = 0; value < 256; ++value) {
      // The noise grows with the signal (shot noise) above a floor (read noise).
      const float signal = static_cast<float>(gain * value);
      const float sigma =
          static_cast<float>(std::sqrt(rgb.read_noise * rgb.read_noise + rgb.shot_noise * signal));
      std::uint8_t* out = &colour_table_[(c * 256 + value) * kNoiseLevels];
      for (int k = 0; k < kNoiseLevels; ++k) {
        out[k] =
            static_cast<std::uint8_t>(std::clamp(signal + sigma * normal[k], 0.0f, 255.0f) + 0.5f);
      }
    }
  }
}

void CameraSensor::apply(const cv::Mat& rgb, const cv::Mat& depth,
                         const CameraIntrinsics& intrinsics) {
  if (isIdeal()) {
    rgb.copyTo(rgb_);
    depth.copyTo(depth_);
    return;
  }
  if (depth.type() != CV_32FC1 || rgb.type() != CV_8UC3 || rgb.size() != depth.size()) {
    throw InvalidArgumentError("the camera sensor takes rgb8 and 32FC1 images of one size");
  }
  // Two keys per frame, in frame order: the depth model's and the colour noise's.
  const CounterNoise depth_noise(random_.nextU64());
  const CounterNoise colour_noise(random_.nextU64());
  geometry_.compute(depth, intrinsics, parameters_.edge);
  depth_model_->measure(depth, rgb, intrinsics, geometry_, depth_noise, depth_);
  if (options_.rgb_effects) {
    applyRgbEffects(rgb, colour_noise);
  } else {
    rgb.copyTo(rgb_);
  }
}

void CameraSensor::blur(const cv::Mat& rgb) {
  // n passes of the binomial [1 2 1] / 4 (variance 1/2 each), n = round(2 sigma^2) >= 1: integer
  // arithmetic, edges clamped.
  const double sigma = parameters_.rgb.blur_sigma_px;
  const int passes = std::max(1, static_cast<int>(std::lround(2.0 * sigma * sigma)));
  const int w = rgb.cols;
  const int h = rgb.rows;
  blur_rows_.create(rgb.size(), CV_16UC3);
  blurred_.create(rgb.size(), CV_8UC3);
  const cv::Mat* source = &rgb;
  for (int pass = 0; pass < passes; ++pass) {
    for (int v = 0; v < h; ++v) {
      const std::uint8_t* in = source->ptr<std::uint8_t>(v);
      std::uint16_t* out = blur_rows_.ptr<std::uint16_t>(v);
      // x4; the border pixels count themselves for the missing neighbour. Interior without
      // index clamping, so that it vectorises.
      const int n = 3 * w;
      for (int i = 0; i < std::min(3, n); ++i) {
        out[i] = static_cast<std::uint16_t>(3 * in[i] + (i + 3 < n ? in[i + 3] : in[i]));
      }
      for (int i = 3; i + 3 < n; ++i) {
        out[i] = static_cast<std::uint16_t>(in[i - 3] + 2 * in[i] + in[i + 3]);
      }
      for (int i = std::max(3, n - 3); i < n; ++i) {
        out[i] = static_cast<std::uint16_t>(in[i - 3] + 3 * in[i]);
      }
    }
    for (int v = 0; v < h; ++v) {
      const std::uint16_t* up = blur_rows_.ptr<std::uint16_t>(std::max(v - 1, 0));
      const std::uint16_t* centre = blur_rows_.ptr<std::uint16_t>(v);
      const std::uint16_t* down = blur_rows_.ptr<std::uint16_t>(std::min(v + 1, h - 1));
      std::uint8_t* out = blurred_.ptr<std::uint8_t>(v);
      for (int i = 0; i < 3 * w; ++i) {
        out[i] = static_cast<std::uint8_t>((up[i] + 2 * centre[i] + down[i] + 8) >> 4);
      }
    }
    source = &blurred_;
  }
}

void CameraSensor::applyRgbEffects(const cv::Mat& rgb, const CounterNoise& noise) {
  const RgbEffectParameters& p = parameters_.rgb;
  const cv::Mat* source = &rgb;
  if (p.blur_sigma_px > 0.0) {
    blur(rgb);
    source = &blurred_;
  }
  rgb_.create(rgb.size(), CV_8UC3);
  // Exposure, white balance and noise from the episode's table: one random byte per channel, six
  // of each pixel pair's 64 bits (counter = v * pairs per row + u / 2).
  const std::uint8_t* table = colour_table_.data();
  constexpr int kChannel = 256 * kNoiseLevels;
  static_assert(kNoiseLevels == 256, "one random byte per channel");
  const auto pixel = [table](const std::uint8_t* in, std::uint8_t* out, std::uint64_t bits) {
    out[0] = table[in[0] * kNoiseLevels + (bits & 0xff)];
    out[1] = table[kChannel + in[1] * kNoiseLevels + ((bits >> 8) & 0xff)];
    out[2] = table[2 * kChannel + in[2] * kNoiseLevels + ((bits >> 16) & 0xff)];
  };
  const int pairs_per_row = (rgb.cols + 1) / 2;
  for (int v = 0; v < rgb.rows; ++v) {
    const std::uint8_t* in = source->ptr<std::uint8_t>(v);
    std::uint8_t* out = rgb_.ptr<std::uint8_t>(v);
    const std::uint64_t first = static_cast<std::uint64_t>(v) * pairs_per_row;
    for (int u = 0; u < rgb.cols; u += 2) {
      const std::uint64_t bits = noise.bits(first + u / 2);
      pixel(in + 3 * u, out + 3 * u, bits);
      if (u + 1 < rgb.cols) pixel(in + 3 * u + 3, out + 3 * u + 3, bits >> 24);
    }
  }
  if (p.jpeg_quality > 0) {
    // Encoding and decoding allocate: an option for datasets, not for the step path.
    cv::cvtColor(rgb_, blurred_, cv::COLOR_RGB2BGR);
    cv::imencode(".jpg", blurred_, jpeg_bytes_, {cv::IMWRITE_JPEG_QUALITY, p.jpeg_quality});
    cv::imdecode(jpeg_bytes_, cv::IMREAD_COLOR, &blurred_);
    cv::cvtColor(blurred_, rgb_, cv::COLOR_BGR2RGB);
  }
}

}  // namespace occlusion_env
