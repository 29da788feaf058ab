#include "occlusion_env/learning/occlusion_estimator.hpp"

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace learning {

OcclusionEstimator::OcclusionEstimator(std::shared_ptr<LoadedModel> model,
                                       double probability_threshold)
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
}

OcclusionEstimate OcclusionEstimator::estimate(const cv::Mat& rgb, const cv::Mat& depth,
                                               cv::Mat& mask) {
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
  // Nearest neighbour: every image pixel takes its network pixel's verdict.
  cv::resize(small_mask_, mask, rgb.size(), 0.0, 0.0, cv::INTER_NEAREST);
  estimate.occluded_pixels = cv::countNonZero(mask);
  return estimate;
}

}  // namespace learning
}  // namespace occlusion_env
