#include "occlusion_env/render/depth_encoding.hpp"

#include <cstdint>
#include <limits>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

void toMillimetreDepth(const cv::Mat& depth_m, cv::Mat& millimetres) {
  if (depth_m.type() != CV_32FC1) throw InvalidArgumentError("toMillimetreDepth: not CV_32FC1");
  millimetres.create(depth_m.size(), CV_16UC1);
  for (int row = 0; row < depth_m.rows; ++row) {
    const float* metres = depth_m.ptr<float>(row);
    std::uint16_t* out = millimetres.ptr<std::uint16_t>(row);
    for (int col = 0; col < depth_m.cols; ++col) {
      const float mm = metres[col] * 1000.0f + 0.5f;
      // No reading (NaN, not positive, beyond the range of 16 bits) is 0, as drivers send it.
      out[col] = mm >= 1.0f && mm < 65536.0f ? static_cast<std::uint16_t>(mm) : 0;
    }
  }
}

void fromMillimetreDepth(const cv::Mat& millimetres, cv::Mat& depth_m) {
  if (millimetres.type() != CV_16UC1) {
    throw InvalidArgumentError("fromMillimetreDepth: not CV_16UC1");
  }
  depth_m.create(millimetres.size(), CV_32FC1);
  const float no_reading = std::numeric_limits<float>::quiet_NaN();
  for (int row = 0; row < millimetres.rows; ++row) {
    const std::uint16_t* in = millimetres.ptr<std::uint16_t>(row);
    float* out = depth_m.ptr<float>(row);
    for (int col = 0; col < millimetres.cols; ++col) {
      out[col] = in[col] == 0 ? no_reading : static_cast<float>(in[col]) * 0.001f;
    }
  }
}

}  // namespace occlusion_env
