#include "occlusion_env/render/visualization.hpp"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "occlusion_env/common/limits.hpp"

namespace occlusion_env {
namespace {

// Distinct colours (RGB) for objects 0..7.
const cv::Vec3b kObjectColors[kMaxSceneObjects] = {{230, 159, 0},   {86, 180, 233}, {0, 158, 115},
                                                   {240, 228, 66},  {0, 114, 178},  {213, 94, 0},
                                                   {204, 121, 167}, {255, 255, 255}};

}  // namespace

cv::Mat colorizeDepth(const cv::Mat& depth) {
  CV_Assert(depth.type() == CV_32FC1);
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int row = 0; row < depth.rows; ++row) {
    for (int col = 0; col < depth.cols; ++col) {
      const float z = depth.at<float>(row, col);
      if (std::isfinite(z)) {
        lo = std::min(lo, z);
        hi = std::max(hi, z);
      }
    }
  }
  cv::Mat scaled(depth.size(), CV_8UC1, cv::Scalar(0));
  const float span = hi > lo ? hi - lo : 1.0f;
  for (int row = 0; row < depth.rows; ++row) {
    for (int col = 0; col < depth.cols; ++col) {
      const float z = depth.at<float>(row, col);
      // Near = 255 (warm), far = 1; 0 is kept for "nothing".
      if (std::isfinite(z))
        scaled.at<std::uint8_t>(row, col) = 255 - static_cast<int>(254 * (z - lo) / span);
    }
  }
  cv::Mat bgr;
  cv::applyColorMap(scaled, bgr, cv::COLORMAP_TURBO);
  bgr.setTo(cv::Scalar::all(0), scaled == 0);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

cv::Mat colorizeInstances(const cv::Mat& instance) {
  CV_Assert(instance.type() == CV_8UC1);
  cv::Mat rgb(instance.size(), CV_8UC3, cv::Scalar::all(0));
  for (int row = 0; row < instance.rows; ++row) {
    for (int col = 0; col < instance.cols; ++col) {
      const int id = instance.at<std::uint8_t>(row, col);
      if (id > 0) rgb.at<cv::Vec3b>(row, col) = kObjectColors[(id - 1) % 8];
    }
  }
  return rgb;
}

cv::Mat occlusionOverlay(const cv::Mat& rgb, const cv::Mat& amodal_bits, const cv::Mat& mask,
                         int num_objects) {
  CV_Assert(rgb.type() == CV_8UC3 && amodal_bits.type() == CV_8UC1 && mask.type() == CV_8UC1);
  cv::Mat overlay = rgb * 0.6;
  overlay.setTo(cv::Scalar(255, 0, 0), mask);
  cv::Mat blended;
  cv::addWeighted(rgb * 0.6, 0.45, overlay, 0.55, 0.0, blended);
  for (int k = 0; k < num_objects && k < kMaxSceneObjects; ++k) {
    cv::Mat silhouette = (amodal_bits & (1 << k)) != 0;
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(silhouette, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    const cv::Vec3b color = kObjectColors[k];
    cv::drawContours(blended, contours, -1, cv::Scalar(color[0], color[1], color[2]), 1);
  }
  return blended;
}

}  // namespace occlusion_env
