#include "occlusion_env/learning/occlusion_estimator.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace learning {

OcclusionEstimator::OcclusionEstimator(std::shared_ptr<LoadedModel> model,
                                       double probability_threshold,
                                       std::optional<BoundingSurfaceOptions> surfaces)
    : model_(std::move(model)) {
  if (!model_ || !model_->network) throw InvalidArgumentError("occlusion estimator: no model");
  if (!(probability_threshold > 0.0 && probability_threshold < 1.0)) {
    throw InvalidArgumentError("occlusion probability threshold must lie in (0, 1)");
  }
  logit_threshold_ =
      static_cast<float>(std::log(probability_threshold / (1.0 - probability_threshold)));
  const int size = model_->network->config().input_size;
  input_ = torch::empty({1, 4, size, size});
  small_mask_.create(size, size, CV_8UC1);
  if (surfaces) surfaces_.emplace(*surfaces);
}

std::int64_t OcclusionEstimator::clearBoundingSurfaces(const cv::Mat& depth,
                                                       const CameraIntrinsics& intrinsics,
                                                       const cv::Size& image_size) {
  const int size = small_mask_.rows;
  // Each network pixel's depth: the mean of the readings of its block (none: NaN). The filled
  // input has summed them already.
  if (model_->network->config().inputFormat().depth_gaps != DepthGaps::kFilled) {
    sumValidDepth(depth, size, scratch_);
  }
  depth_small_.create(small_mask_.size(), CV_32FC1);
  for (int row = 0; row < size; ++row) {
    const float* sum = scratch_.depth_small.ptr<float>(row);
    const float* fraction = scratch_.valid_small.ptr<float>(row);
    float* out = depth_small_.ptr<float>(row);
    for (int col = 0; col < size; ++col) {
      // At least half of the block read: a mean over a few speckles is no surface.
      out[col] = fraction[col] >= 0.5f ? sum[col] / fraction[col]
                                       : std::numeric_limits<float>::quiet_NaN();
    }
  }
  // The intrinsics of the network's grid (pixel centres map to pixel centres).
  CameraIntrinsics small = intrinsics;
  const double sx = static_cast<double>(size) / image_size.width;
  const double sy = static_cast<double>(size) / image_size.height;
  small.width = small.height = size;
  small.fx *= sx;
  small.fy *= sy;
  small.cx = (intrinsics.cx + 0.5) * sx - 0.5;
  small.cy = (intrinsics.cy + 0.5) * sy - 0.5;
  surfaces_->find(depth_small_, small, on_surface_);
  std::int64_t cleared = 0;
  for (int row = 0; row < size; ++row) {
    std::uint8_t* verdict = small_mask_.ptr<std::uint8_t>(row);
    const std::uint8_t* surface = on_surface_.ptr<std::uint8_t>(row);
    for (int col = 0; col < size; ++col) {
      if (verdict[col] && surface[col]) {
        verdict[col] = 0;
        ++cleared;
      }
    }
  }
  // In image pixels, as the estimate counts.
  return static_cast<std::int64_t>(std::llround(cleared / (sx * sy)));
}

OcclusionEstimate OcclusionEstimator::estimate(const cv::Mat& rgb, const cv::Mat& depth,
                                               const CameraIntrinsics& intrinsics, cv::Mat& mask) {
  const int size = model_->network->config().input_size;
  writeNetworkInput(rgb, depth, model_->network->config().inputFormat(), scratch_,
                    input_.data_ptr<float>());
  torch::InferenceMode inference;
  const torch::Tensor logits = model_->network->forward(input_).occlusion_logits.contiguous();
  const float* logit = logits.data_ptr<float>();
  OcclusionEstimate estimate;
  double probability_sum = 0.0;
  for (int row = 0; row < size; ++row) {
    std::uint8_t* out = small_mask_.ptr<std::uint8_t>(row);
    for (int col = 0; col < size; ++col) {
      const float value = logit[row * size + col];
      out[col] = value > logit_threshold_ ? 255 : 0;
      probability_sum += 1.0 / (1.0 + std::exp(-static_cast<double>(value)));
    }
  }
  estimate.mean_probability = probability_sum / (static_cast<double>(size) * size);
  if (surfaces_) estimate.cleared_pixels = clearBoundingSurfaces(depth, intrinsics, rgb.size());
  // Nearest neighbour: every image pixel takes its network pixel's verdict.
  cv::resize(small_mask_, mask, rgb.size(), 0.0, 0.0, cv::INTER_NEAREST);
  estimate.occluded_pixels = cv::countNonZero(mask);
  return estimate;
}

std::unique_ptr<NetworkOcclusionEstimator> makeBridgeEstimator(
    std::shared_ptr<LoadedModel> model, const CameraEnvironmentOptions& options) {
  std::optional<BoundingSurfaceOptions> surfaces;
  if (options.clear_bounding_surfaces) surfaces.emplace();
  return std::make_unique<NetworkOcclusionEstimator>(std::move(model),
                                                     options.occlusion_probability, surfaces);
}

}  // namespace learning
}  // namespace occlusion_env
