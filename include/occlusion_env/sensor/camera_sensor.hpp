// Depth-sensor and colour-camera models applied to rendered frames: what a real RGB-D camera
// would give for the renderer's ideal images. Only the observation goes through them; the
// occlusion count, rewards and gradients keep the ideal buffers. ROS-free; no allocation per frame
// once the buffers have their size.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "occlusion_env/common/random.hpp"
#include "occlusion_env/geometry/camera.hpp"
#include "occlusion_env/sensor/sensor_parameters.hpp"

namespace occlusion_env {

/// The options an environment takes for its camera's sensor.
struct SensorOptions {
  std::string depth_sensor = "ideal";  // ideal | kinect_v1 | realsense_d435 | azure_kinect
  std::string parameters_file;         // empty: the built-in values (= config/sensors.yaml)
  bool rgb_effects = true;             // noise, exposure, white balance, blur (not for ideal)

  /// Throws InvalidArgumentError for an unknown sensor or an unreadable parameters file.
  void validate() const;
};

/// The depth sensors behind `depth_sensor`, in order.
const std::vector<std::string>& depthSensorNames();

/// Per-pixel geometry of an ideal depth image that several models read. Sized on first use.
struct DepthGeometry {
  cv::Mat cos_incidence;  // CV_32FC1, |cos| of the angle between surface normal and viewing ray
                          // (1 where unknown), NaN-free
  cv::Mat edge;           // CV_8UC1, 1 at a depth discontinuity (either side) or a surface
                          // pixel beside one with no depth

  /// Fills both maps from `depth` (CV_32FC1 [m], NaN = nothing).
  void compute(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
               const EdgeParameters& edge_parameters);

 private:
  std::vector<float> ray_x_;  // (u - cx) / fx per column
  std::vector<float> ray_y_;  // (v - cy) / fy per row
};

/// Counter-based random bits for per-pixel noise: splitmix64's output for the state
/// key + (counter + 1) * golden gamma. A frame draws its key from the episode's stream, so a seed
/// fixes every frame, and each pixel's bits depend only on the key and the pixel's counter: no
/// sequential state, any order, a few nanoseconds a draw.
class CounterNoise {
 public:
  explicit CounterNoise(std::uint64_t key) : key_(key) {}
  std::uint64_t bits(std::uint64_t counter) const {
    std::uint64_t z = key_ + (counter + 1) * 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t key_;
};

/// 256 equiprobable values of the standard normal (its quantiles at (k + 1/2) / 256, scaled to
/// unit variance, which the cut tails would lower by about 1 %): a normal draw from one random
/// byte, for per-pixel noise that is rounded to whole levels or millimetres afterwards.
const std::array<float, 256>& standardNormalLevels();

/// A uniform draw in [0, 1) from the top 24 of 64 bits, as a float (exact).
inline float uniform24(std::uint64_t bits) {
  return static_cast<float>(bits >> 40) * (1.0f / 16777216.0f);
}

/// One depth-sensor model. measure() writes the depth this sensor reports for an ideal depth image
/// (NaN where it reports nothing, REP 118), drawing every random number from `noise` (pixel
/// v * width + u uses the counters documented by each model).
class DepthSensorModel {
 public:
  virtual ~DepthSensorModel() = default;
  virtual std::string name() const = 0;
  virtual void measure(const cv::Mat& ideal_depth, const cv::Mat& rgb,
                       const CameraIntrinsics& intrinsics, const DepthGeometry& geometry,
                       const CounterNoise& noise, cv::Mat& measured) = 0;
};

/// Throws InvalidArgumentError for an unknown name.
std::unique_ptr<DepthSensorModel> makeDepthSensorModel(const std::string& name,
                                                       const SensorParameters& parameters);

/// A standard-normal draw from 32 random bits (4 x 8 bits, Irwin-Hall; exact mean and variance,
/// 1021 levels, tails cut at 3.46 sigma): for per-pixel depth noise, whose 1 mm quantisation is
/// coarser than its levels.
inline float byteSumNormal(std::uint32_t bits) {
  const std::uint32_t sum =
      (bits & 0xff) + ((bits >> 8) & 0xff) + ((bits >> 16) & 0xff) + (bits >> 24);
  constexpr float kMean = 2.0f * 255.0f;
  constexpr float kInverseSigma = 1.0f / 147.8005f;  // sqrt(4 (256^2 - 1) / 12)
  return (static_cast<float>(sum) - kMean) * kInverseSigma;
}

/// The whole camera: a depth model and the colour effects, with the episode's random stream.
/// startEpisode(seed) fixes every draw that follows, so the same seed and the same frames give
/// bit-identical output.
class CameraSensor {
 public:
  /// Validates the options (loading their parameters file, if any).
  explicit CameraSensor(const SensorOptions& options);
  CameraSensor(const SensorOptions& options, const SensorParameters& parameters);
  ~CameraSensor();

  /// True for `ideal`: apply() is not needed, the rendered images are the observation.
  bool isIdeal() const { return !depth_model_; }
  const std::string& depthSensor() const { return options_.depth_sensor; }
  const SensorParameters& parameters() const { return parameters_; }

  /// Reseeds the random stream from the episode's seed and draws the scene's exposure and white
  /// balance.
  void startEpisode(std::uint64_t seed);

  /// Applies the models to one rendered frame (rgb CV_8UC3, depth CV_32FC1 [m]); the results stay
  /// in rgb() and depth() until the next call. Each call draws the frame's noise keys from the
  /// episode's stream.
  void apply(const cv::Mat& rgb, const cv::Mat& depth, const CameraIntrinsics& intrinsics);
  const cv::Mat& rgb() const { return rgb_; }
  const cv::Mat& depth() const { return depth_; }

 private:
  void applyRgbEffects(const cv::Mat& rgb, const CounterNoise& noise);
  /// Blur of `rgb` into blurred_: binomial passes of variance rgb.blur_sigma_px^2 (rounded).
  void blur(const cv::Mat& rgb);

  SensorOptions options_;
  SensorParameters parameters_;
  std::unique_ptr<DepthSensorModel> depth_model_;
  RandomSource random_{0};
  DepthGeometry geometry_;
  /// Output level per channel, input level and noise draw: exposure x white balance, plus the
  /// noise's sigma there times one of kNoiseLevels equiprobable standard-normal values, rounded
  /// and clamped. Filled by startEpisode().
  static constexpr int kNoiseLevels = 256;
  std::vector<std::uint8_t> colour_table_;
  cv::Mat blur_rows_;  // CV_16UC3, the horizontal pass (x4)
  cv::Mat blurred_;
  cv::Mat rgb_;
  cv::Mat depth_;
  std::vector<std::uint8_t> jpeg_bytes_;
};

}  // namespace occlusion_env
