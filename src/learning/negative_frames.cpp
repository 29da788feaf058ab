#include "occlusion_env/learning/negative_frames.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/learning/network_input.hpp"

namespace occlusion_env {
namespace learning {
namespace {

constexpr float kNoDepth = std::numeric_limits<float>::quiet_NaN();

// A surface's colour: a grey level with a little tint, in [0, 255].
Eigen::Vector3f surfaceColor(std::mt19937_64& random) {
  std::uniform_real_distribution<float> grey(40.0f, 220.0f), tint(-25.0f, 25.0f);
  const float level = grey(random);
  return Eigen::Vector3f(level + tint(random), level + tint(random), level + tint(random));
}

}  // namespace

CameraFrame bareSurfaceFrame(std::uint64_t seed, int size_px) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto uniform = [&](double low, double high) { return low + (high - low) * unit(random); };

  CameraFrame frame;
  frame.intrinsics =
      CameraIntrinsics::fromFieldOfView(size_px, size_px, uniform(50.0, 90.0) * M_PI / 180.0);
  const CameraIntrinsics& k = frame.intrinsics;
  const double height_m = uniform(0.4, 2.0);
  const double pitch_rad = uniform(0.0, 1.3);
  const double kind = unit(random);  // floor only, wall only, or both
  const bool floor = kind < 0.3 || kind >= 0.55;
  const bool wall = kind >= 0.3;
  const double wall_distance_m = uniform(0.7, 6.0);
  const double wall_yaw_rad = uniform(-1.0, 1.0);
  const bool tiled = unit(random) < 0.4;
  const double tile_m = uniform(0.2, 0.8);
  const Eigen::Vector3f floor_color = surfaceColor(random), wall_color = surfaceColor(random);
  // Shading: ambient + diffuse * max(n . l, 0), the light above and behind the camera.
  const Eigen::Vector3d to_light =
      Eigen::Vector3d(uniform(-0.5, 0.5), -uniform(0.5, 1.0), -uniform(0.0, 1.0)).normalized();
  const double ambient = uniform(0.3, 0.6);
  const double pixel_noise = uniform(0.0, 6.0);
  const double depth_noise_per_m2 = unit(random) < 0.5 ? uniform(0.001, 0.004) : 0.0;
  std::normal_distribution<float> gauss(0.0f, 1.0f);

  // The level frame: x right, y down, z forward and horizontal; the camera pitched down about x.
  const double c = std::cos(pitch_rad), s = std::sin(pitch_rad);
  const Eigen::Vector3d floor_normal(0.0, -1.0, 0.0);  // towards the camera
  const Eigen::Vector3d wall_normal(-std::sin(wall_yaw_rad), 0.0, -std::cos(wall_yaw_rad));
  const double floor_shade = ambient + (1.0 - ambient) * std::max(0.0, floor_normal.dot(to_light));
  const double wall_shade = ambient + (1.0 - ambient) * std::max(0.0, wall_normal.dot(to_light));

  frame.rgb.create(size_px, size_px, CV_8UC3);
  frame.depth.create(size_px, size_px, CV_32FC1);
  for (int row = 0; row < size_px; ++row) {
    for (int column = 0; column < size_px; ++column) {
      const double u = (column - k.cx) / k.fx;
      const double v = (row - k.cy) / k.fy;
      // The ray (u, v, 1) in the level frame; its parameter along it is the optical-axis depth.
      const Eigen::Vector3d ray(u, c * v + s, -s * v + c);
      double depth_m = std::numeric_limits<double>::infinity();
      Eigen::Vector3f color = Eigen::Vector3f::Zero();
      if (floor && ray.y() > 1e-6) {
        depth_m = height_m / ray.y();
        const Eigen::Vector3d hit = depth_m * ray;
        const bool dark = tiled && (static_cast<long>(std::floor(hit.x() / tile_m)) +
                                    static_cast<long>(std::floor(hit.z() / tile_m))) %
                                           2 !=
                                       0;
        color = floor_color * static_cast<float>(floor_shade * (dark ? 0.8 : 1.0));
      }
      const double toward_wall = -wall_normal.dot(ray);
      if (wall && toward_wall > 1e-6 && wall_distance_m / toward_wall < depth_m) {
        depth_m = wall_distance_m / toward_wall;
        color = wall_color * static_cast<float>(wall_shade);
      }
      const bool seen = depth_m < kFarDepthM;
      float& depth = frame.depth.at<float>(row, column);
      depth =
          seen ? static_cast<float>(depth_m * (1.0 + depth_noise_per_m2 * depth_m * gauss(random)))
               : kNoDepth;
      cv::Vec3b& pixel = frame.rgb.at<cv::Vec3b>(row, column);
      for (int channel = 0; channel < 3; ++channel) {
        const float value = seen ? color[channel] + pixel_noise * gauss(random) : 0.0f;
        pixel[channel] = cv::saturate_cast<unsigned char>(value);
      }
    }
  }
  return frame;
}

CameraFrame objectAloneFrame(const CameraFrame& frame, const cv::Mat& object_mask) {
  if (object_mask.size() != frame.rgb.size() || object_mask.size() != frame.depth.size()) {
    throw InvalidArgumentError("objectAloneFrame: the mask and the frame differ in size");
  }
  CameraFrame alone = frame;
  alone.rgb = cv::Mat(frame.rgb.size(), CV_8UC3, cv::Scalar::all(0));
  alone.depth = cv::Mat(frame.depth.size(), CV_32FC1, cv::Scalar(kNoDepth));
  frame.rgb.copyTo(alone.rgb, object_mask);
  frame.depth.copyTo(alone.depth, object_mask);
  return alone;
}

}  // namespace learning
}  // namespace occlusion_env
