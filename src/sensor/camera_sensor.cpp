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

SensorParameters parametersFor(const SensorOptions& options) {
  options.validate();
  return options.parameters_file.empty() ? SensorParameters{}
                                         : loadSensorParameters(options.parameters_file);
}

}  // namespace

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
  const double exposure =
      std::exp2(random_.uniform(-rgb.exposure_log2_range, rgb.exposure_log2_range));
  for (int c = 0; c < 3; ++c) {
    const double gain =
        exposure * (1.0 + random_.uniform(-rgb.white_balance_range, rgb.white_balance_range));
    for (int value = 0; value < 256; ++value) {
      // The noise grows with the signal (shot noise) above a floor (read noise).
      const double signal = gain * value;
      signal_[c][value] = static_cast<float>(signal);
      noise_sigma_[c][value] =
          static_cast<float>(std::sqrt(rgb.read_noise * rgb.read_noise + rgb.shot_noise * signal));
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
  geometry_.compute(depth, intrinsics, parameters_.edge);
  depth_model_->measure(depth, rgb, intrinsics, geometry_, random_, depth_);
  if (options_.rgb_effects) {
    applyRgbEffects(rgb);
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
      for (int i = 0; i < 3 * w; ++i) {
        const int left = i >= 3 ? i - 3 : i;
        const int right = i + 3 < 3 * w ? i + 3 : i;
        out[i] = static_cast<std::uint16_t>(in[left] + 2 * in[i] + in[right]);  // x4
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

void CameraSensor::applyRgbEffects(const cv::Mat& rgb) {
  const RgbEffectParameters& p = parameters_.rgb;
  const cv::Mat* source = &rgb;
  if (p.blur_sigma_px > 0.0) {
    blur(rgb);
    source = &blurred_;
  }
  rgb_.create(rgb.size(), CV_8UC3);
  for (int v = 0; v < rgb.rows; ++v) {
    const std::uint8_t* in = source->ptr<std::uint8_t>(v);
    std::uint8_t* out = rgb_.ptr<std::uint8_t>(v);
    for (int i = 0; i < 3 * rgb.cols; i += 3) {
      // Two draws per random word; exposure, white balance and the noise's sigma from the tables.
      const std::uint64_t bits = random_.nextU64();
      const float noise[3] = {byteSumNormal(static_cast<std::uint32_t>(bits)),
                              byteSumNormal(static_cast<std::uint32_t>(bits >> 32)),
                              fastStandardNormal(random_)};
      for (int c = 0; c < 3; ++c) {
        const float value = signal_[c][in[i + c]] + noise_sigma_[c][in[i + c]] * noise[c];
        out[i + c] = static_cast<std::uint8_t>(std::clamp(value, 0.0f, 255.0f) + 0.5f);
      }
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
