#include "occlusion_env/learning/network_input.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace learning {

void writeNetworkInput(const cv::Mat& rgb, const cv::Mat& depth, int size, InputScratch& scratch,
                       float* out) {
  if (rgb.type() != CV_8UC3 || depth.type() != CV_32FC1 || rgb.size() != depth.size() ||
      rgb.empty()) {
    throw InvalidArgumentError("network input: needs CV_8UC3 RGB and CV_32FC1 depth of one size");
  }
  scratch.depth_filled.create(depth.size(), CV_32FC1);
  for (int row = 0; row < depth.rows; ++row) {
    const float* in = depth.ptr<float>(row);
    float* filled = scratch.depth_filled.ptr<float>(row);
    for (int col = 0; col < depth.cols; ++col) {
      const float d = in[col];
      filled[col] =
          std::isfinite(d) ? std::min(std::max(d, 0.0f), float(kFarDepthM)) : float(kFarDepthM);
    }
  }
  const cv::Size target(size, size);
  if (rgb.size() == target) {
    scratch.rgb_small = rgb;
    scratch.depth_small = scratch.depth_filled;
  } else {
    cv::resize(rgb, scratch.rgb_small, target, 0, 0, cv::INTER_AREA);
    cv::resize(scratch.depth_filled, scratch.depth_small, target, 0, 0, cv::INTER_AREA);
  }
  const std::size_t plane = static_cast<std::size_t>(size) * size;
  for (int row = 0; row < size; ++row) {
    const cv::Vec3b* pixels = scratch.rgb_small.ptr<cv::Vec3b>(row);
    const float* depths = scratch.depth_small.ptr<float>(row);
    for (int col = 0; col < size; ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * size + col;
      for (int c = 0; c < 3; ++c) out[c * plane + i] = (pixels[col][c] / 255.0f - 0.5f) / 0.25f;
      out[3 * plane + i] = (depths[col] / float(kFarDepthM) - 0.5f) / 0.25f;
    }
  }
}

}  // namespace learning
}  // namespace occlusion_env
