// What a real camera cannot count, estimated: the multi-task network's occlusion map of an RGB-D
// image (learning/multitask_unet.hpp), as a mask at the image's size and its pixel count. The
// camera bridge (ros/camera_bridge.hpp) reports it in place of the simulator's ground truth.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <memory>

#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/network_input.hpp"

namespace occlusion_env {
namespace learning {

struct OcclusionEstimate {
  std::int64_t occluded_pixels = 0;  // [px] of the mask, at the image's resolution
  double mean_probability = 0.0;     // the network's mean occlusion probability over the image
};

class OcclusionEstimator {
 public:
  /// A pixel counts as occluded where the network's probability exceeds
  /// `probability_threshold` (0.5: the threshold of the validation IoU). Throws
  /// InvalidArgumentError for a missing model or a threshold outside (0, 1).
  explicit OcclusionEstimator(std::shared_ptr<LoadedModel> model,
                              double probability_threshold = 0.5);

  /// Runs the network on `rgb` (CV_8UC3) and `depth` (CV_32FC1 [m], NaN = nothing) and writes
  /// `mask` (CV_8UC1 at rgb's size, 255 where occlusion is predicted, else 0; reused). No
  /// allocation once the buffers are sized, but for libtorch's own.
  OcclusionEstimate estimate(const cv::Mat& rgb, const cv::Mat& depth, cv::Mat& mask);

  const LoadedModel& model() const { return *model_; }

 private:
  std::shared_ptr<LoadedModel> model_;
  float logit_threshold_;  // log(p / (1 - p)) of the probability threshold
  InputScratch scratch_;
  torch::Tensor input_;
  cv::Mat small_mask_;  // at the network's resolution
};

/// The network's estimate where the camera bridge's logic asks for one
/// (env/camera_environment.hpp): the occluded pixels of its mask.
class NetworkOcclusionEstimator : public ViewOcclusionEstimator {
 public:
  NetworkOcclusionEstimator(std::shared_ptr<LoadedModel> model, double probability_threshold)
      : estimator_(std::move(model), probability_threshold) {}
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat& depth, cv::Mat& mask) override {
    return estimator_.estimate(rgb, depth, mask).occluded_pixels;
  }

 private:
  OcclusionEstimator estimator_;
};

}  // namespace learning
}  // namespace occlusion_env
