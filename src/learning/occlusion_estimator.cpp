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
  logit_threshold_ = occlusionLogit(probability_threshold);
  format_ = model_->network->config().inputFormat().atRadius(kWorkingRadiusM);
  const int size = model_->network->config().input_size;
  input_ = torch::empty({1, format_.channels(), size, size});
  small_mask_.create(size, size, CV_8UC1);
  // A model that clears floors and walls from its input has found them there (with the input's
  // options, clearedInputSurfaceOptions()); the estimate's clearing reuses what it found.
  if (surfaces) surfaces_.emplace(*surfaces);
}

void OcclusionEstimator::setCameraRadius(double radius_m) {
  if (!(std::isfinite(radius_m) && radius_m > 0.0)) {
    throw InvalidArgumentError("occlusion estimator: the camera's radius must be positive");
  }
  format_.radius_m = radius_m;
}

std::int64_t OcclusionEstimator::clearBoundingSurfaces(const cv::Mat& depth,
                                                       const CameraIntrinsics& intrinsics,
                                                       const cv::Size& image_size) {
  const int size = small_mask_.rows;
  // An input that clears them has found this view's surfaces already, with its own options.
  if (!format_.clear_bounding_surfaces) {
    // Searched in metres up to kFarDepthM, so summed again where the input's sums clamp
    // elsewhere (depth relative to a radius other than 4 m).
    if (!format_.sumsValidDepth() || format_.farReadingM() != static_cast<float>(kFarDepthM)) {
      sumValidDepth(depth, size, scratch_);
    }
    findGridBoundingSurfaces(intrinsics, image_size, *surfaces_, scratch_);
  }
  const std::int64_t cleared = clearFoundSurfaces(small_mask_);
  // In image pixels, as the estimate counts.
  const double grid_area = static_cast<double>(size) * size;
  return static_cast<std::int64_t>(
      std::llround(cleared * static_cast<double>(image_size.area()) / grid_area));
}

std::int64_t OcclusionEstimator::clearFoundSurfaces(cv::Mat& small_mask) const {
  std::int64_t cleared = 0;
  for (int row = 0; row < small_mask.rows; ++row) {
    std::uint8_t* verdict = small_mask.ptr<std::uint8_t>(row);
    const std::uint8_t* surface = scratch_.on_surface.ptr<std::uint8_t>(row);
    for (int col = 0; col < small_mask.cols; ++col) {
      if (verdict[col] && surface[col]) {
        verdict[col] = 0;
        ++cleared;
      }
    }
  }
  return cleared;
}

std::int64_t OcclusionEstimator::occludedPixelsAt(double probability) {
  if (last_image_size_.empty()) {
    throw InvalidStateError("occlusion estimator: occludedPixelsAt() before any estimate()");
  }
  const float logit_threshold = occlusionLogit(probability);
  const int size = small_mask_.rows;
  const cv::Mat logits(size, size, CV_32FC1, last_logits_.data_ptr<float>());
  cv::compare(logits, logit_threshold, other_small_mask_, cv::CMP_GT);
  if (surfaces_) clearFoundSurfaces(other_small_mask_);
  // At the size of the part of the image the network saw, counted inside the image: the rest is
  // never occluded.
  cv::resize(other_small_mask_, other_mask_, last_seen_.size(), 0.0, 0.0, cv::INTER_NEAREST);
  const cv::Rect inside = last_seen_ & cv::Rect(cv::Point(0, 0), last_image_size_);
  return cv::countNonZero(other_mask_(inside - last_seen_.tl()));
}

std::int64_t OcclusionEstimator::occludedPixelsAt(double probability,
                                                  const cv::Mat& also_occluded) {
  const std::int64_t own = occludedPixelsAt(probability);
  if (also_occluded.size() != last_image_size_ || also_occluded.type() != CV_8UC1) {
    throw InvalidArgumentError("occlusion estimator: the other estimate's mask must be CV_8UC1 " +
                               std::to_string(last_image_size_.width) + "x" +
                               std::to_string(last_image_size_.height) + ", as the image");
  }
  // Counted once where both see occlusion; outside the seen part only the other's count.
  const cv::Rect inside = last_seen_ & cv::Rect(cv::Point(0, 0), last_image_size_);
  cv::bitwise_and(other_mask_(inside - last_seen_.tl()), also_occluded(inside), both_mask_);
  return own + cv::countNonZero(also_occluded) - cv::countNonZero(both_mask_);
}

OcclusionEstimate OcclusionEstimator::estimate(const cv::Mat& rgb, const cv::Mat& depth,
                                               const CameraIntrinsics& intrinsics, cv::Mat& mask) {
  const int size = model_->network->config().input_size;
  writeNetworkInput(rgb, depth, intrinsics, format_, scratch_, input_.data_ptr<float>());
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
  last_logits_ = logits;  // for occludedPixelsAt()
  // The part of the image the network saw (all of it but for a model with a view_crop or a
  // view_field_of_view, whose part may reach beyond the image); nothing outside it is estimated
  // occluded.
  const cv::Rect seen = seenViewRect(rgb.size(), intrinsics, format_);
  const cv::Rect whole(cv::Point(0, 0), rgb.size());
  const cv::Rect inside = seen & whole;
  last_seen_ = seen;
  last_image_size_ = rgb.size();
  if (surfaces_) {
    const float no_depth = std::numeric_limits<float>::quiet_NaN();
    estimate.cleared_pixels =
        clearBoundingSurfaces(viewPart(depth, seen, cv::Scalar::all(no_depth), seen_depth_),
                              croppedIntrinsics(intrinsics, seen), seen.size());
  }
  mask.create(rgb.size(), CV_8UC1);
  if (seen != whole) mask.setTo(0);
  // Nearest neighbour: every image pixel takes its network pixel's verdict.
  if (inside == seen) {
    cv::Mat seen_mask = mask(seen);
    cv::resize(small_mask_, seen_mask, seen.size(), 0.0, 0.0, cv::INTER_NEAREST);
  } else {
    cv::resize(small_mask_, seen_mask_, seen.size(), 0.0, 0.0, cv::INTER_NEAREST);
    if (!inside.empty()) seen_mask_(inside - seen.tl()).copyTo(mask(inside));
  }
  estimate.occluded_pixels = cv::countNonZero(mask);
  return estimate;
}

std::unique_ptr<ViewOcclusionEstimator> makeBridgeEstimator(
    std::shared_ptr<LoadedModel> model, const CameraEnvironmentOptions& options,
    std::shared_ptr<LoadedModel> second_model) {
  std::optional<BoundingSurfaceOptions> surfaces;
  if (options.clear_bounding_surfaces) surfaces.emplace();
  const auto network = [&](std::shared_ptr<LoadedModel> loaded, double probability) {
    auto estimator =
        std::make_unique<NetworkOcclusionEstimator>(std::move(loaded), probability, surfaces);
    estimator->setCameraRadius(options.radius_m);
    return estimator;
  };
  if (!second_model) return network(std::move(model), options.occlusion_probability);
  return std::make_unique<EstimateUnion>(
      network(std::move(model), options.occlusion_probability),
      network(std::move(second_model), options.second_occlusion_probability));
}

}  // namespace learning
}  // namespace occlusion_env
