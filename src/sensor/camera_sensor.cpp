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
}

CameraSensor::~CameraSensor() = default;

void CameraSensor::startEpisode(std::uint64_t seed) {
  random_ = RandomSource(seed ^ kSensorStream);
  const RgbEffectParameters& rgb = parameters_.rgb;
  const double exposure =
      std::exp2(random_.uniform(-rgb.exposure_log2_range, rgb.exposure_log2_range));
  for (float& gain : channel_gain_) {
    gain = static_cast<float>(
        exposure * (1.0 + random_.uniform(-rgb.white_balance_range, rgb.white_balance_range)));
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
  // Separable Gaussian, edges clamped; cv::GaussianBlur would allocate its kernels every call.
  const double sigma = parameters_.rgb.blur_sigma_px;
  const int radius = std::min(kMaxBlurRadius, static_cast<int>(std::ceil(3.0 * sigma)));
  float weights[2 * kMaxBlurRadius + 1];
  float total = 0.0f;
  for (int k = -radius; k <= radius; ++k) {
    weights[k + radius] = static_cast<float>(std::exp(-0.5 * k * k / (sigma * sigma)));
    total += weights[k + radius];
  }
  for (int k = 0; k <= 2 * radius; ++k) weights[k] /= total;
  const int w = rgb.cols;
  const int h = rgb.rows;
  blur_rows_.create(rgb.size(), CV_32FC3);
  for (int v = 0; v < h; ++v) {
    const cv::Vec3b* in = rgb.ptr<cv::Vec3b>(v);
    cv::Vec3f* out = blur_rows_.ptr<cv::Vec3f>(v);
    for (int u = 0; u < w; ++u) {
      cv::Vec3f sum(0.0f, 0.0f, 0.0f);
      for (int k = -radius; k <= radius; ++k) {
        const cv::Vec3b& pixel = in[std::clamp(u + k, 0, w - 1)];
        sum += weights[k + radius] * cv::Vec3f(pixel[0], pixel[1], pixel[2]);
      }
      out[u] = sum;
    }
  }
  blurred_.create(rgb.size(), CV_8UC3);
  for (int v = 0; v < h; ++v) {
    cv::Vec3b* out = blurred_.ptr<cv::Vec3b>(v);
    for (int u = 0; u < w; ++u) {
      cv::Vec3f sum(0.0f, 0.0f, 0.0f);
      for (int k = -radius; k <= radius; ++k) {
        sum += weights[k + radius] * blur_rows_.ptr<cv::Vec3f>(std::clamp(v + k, 0, h - 1))[u];
      }
      out[u] = cv::Vec3b(cv::saturate_cast<std::uint8_t>(sum[0]),
                         cv::saturate_cast<std::uint8_t>(sum[1]),
                         cv::saturate_cast<std::uint8_t>(sum[2]));
    }
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
  const float read_variance = static_cast<float>(p.read_noise * p.read_noise);
  const float shot = static_cast<float>(p.shot_noise);
  for (int v = 0; v < rgb.rows; ++v) {
    const std::uint8_t* in = source->ptr<std::uint8_t>(v);
    std::uint8_t* out = rgb_.ptr<std::uint8_t>(v);
    for (int i = 0; i < 3 * rgb.cols; ++i) {
      // Exposure and white balance scale the signal; the noise grows with it (shot noise).
      const float signal = channel_gain_[i % 3] * static_cast<float>(in[i]);
      const float sigma = std::sqrt(read_variance + shot * signal);
      const float value = signal + sigma * fastStandardNormal(random_);
      out[i] = static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
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
