// What a real camera cannot count, estimated: the multi-task network's occlusion map of an RGB-D
// image (learning/multitask_unet.hpp), as a mask at the image's size and its pixel count. The
// camera bridge (ros/camera_bridge.hpp) reports it in place of the simulator's ground truth.
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <memory>
#include <optional>

#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/network_input.hpp"
#include "occlusion_env/occlusion/bounding_surfaces.hpp"

namespace occlusion_env {
namespace learning {

struct OcclusionEstimate {
  std::int64_t occluded_pixels = 0;  // [px] of the mask, at the image's resolution
  double mean_probability = 0.0;     // the network's mean occlusion probability over the image
  std::int64_t cleared_pixels = 0;   // [px] estimated on a bounding surface and cleared
};

class OcclusionEstimator {
 public:
  /// A pixel counts as occluded where the network's probability exceeds
  /// `probability_threshold` (0.5: the threshold of the validation IoU). With `surfaces`, a
  /// network pixel whose depth lies on a bounding surface (a floor, a wall:
  /// occlusion/bounding_surfaces.hpp) is never occluded; found with `surfaces`, or, for a model
  /// whose input clears them, with the input's options (clearedInputSurfaceOptions(): the
  /// planes its input showed as the void). Throws InvalidArgumentError for a
  /// missing model, a threshold outside (0, 1) or bad surface options.
  explicit OcclusionEstimator(std::shared_ptr<LoadedModel> model,
                              double probability_threshold = 0.5,
                              std::optional<BoundingSurfaceOptions> surfaces = std::nullopt);

  /// Runs the network on `rgb` (CV_8UC3) and `depth` (CV_32FC1 [m], NaN = nothing), seen with
  /// `intrinsics` (of their size), and writes `mask` (CV_8UC1 at rgb's size, 255 where
  /// occlusion is predicted, else 0, also outside the crop of a model with a view_crop; reused). No
  /// allocation once the buffers are sized, but for libtorch's own.
  OcclusionEstimate estimate(const cv::Mat& rgb, const cv::Mat& depth,
                             const CameraIntrinsics& intrinsics, cv::Mat& mask);

  /// The occluded pixels [px, at the image's resolution] that the last estimate() would have
  /// counted at `probability` instead of its own threshold, its floors and walls cleared as
  /// they were: several thresholds from one pass of the network. Throws InvalidStateError
  /// before the first estimate() and InvalidArgumentError for a probability outside (0, 1).
  std::int64_t occludedPixelsAt(double probability);
  /// The same pixels joined by those of `also_occluded` (CV_8UC1 at the last image's size, non-zero
  /// where another estimate sees occlusion, as EstimateUnion joins two maps), each counted once.
  /// Throws InvalidArgumentError for a mask of another size or type.
  std::int64_t occludedPixelsAt(double probability, const cv::Mat& also_occluded);

  const LoadedModel& model() const { return *model_; }
  /// The camera's distance from the sphere's centre [m] (4 until set), for a model whose depth
  /// is relative to it (depth_reference: radius; network_input.hpp). Throws InvalidArgumentError
  /// unless positive.
  void setCameraRadius(double radius_m);

 private:
  /// Clears the network pixels of small_mask_ that lie on a bounding surface of `depth`; returns
  /// how many image pixels that was.
  std::int64_t clearBoundingSurfaces(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                                     const cv::Size& image_size);
  /// Zeroes the network pixels of `small_mask` on the surfaces the last estimate found; returns
  /// how many it zeroed.
  std::int64_t clearFoundSurfaces(cv::Mat& small_mask) const;

  std::shared_ptr<LoadedModel> model_;
  float logit_threshold_;  // log(p / (1 - p)) of the probability threshold
  InputFormat format_;     // the model's, at the camera's radius
  InputScratch scratch_;
  torch::Tensor input_;
  cv::Mat small_mask_;  // at the network's resolution
  // The last estimate's logits ([1, 1, S, S], kept, not copied), the part of the image they
  // cover (seenViewRect: it may reach beyond a narrow camera's image) and the image's size, for
  // occludedPixelsAt().
  torch::Tensor last_logits_;
  cv::Rect last_seen_;
  cv::Size last_image_size_;
  cv::Mat other_small_mask_, other_mask_, both_mask_;  // occludedPixelsAt()'s, reused
  cv::Mat seen_depth_, seen_mask_;  // the seen part where it reaches beyond the image, reused
  // With surfaces: the finder, run on the network pixels' mean depths (network_input.hpp).
  std::optional<BoundingSurfaceFinder> surfaces_;
};

/// The network's estimate where the camera bridge's logic asks for one
/// (env/camera_environment.hpp): the occluded pixels of its mask.
class NetworkOcclusionEstimator : public ViewOcclusionEstimator {
 public:
  NetworkOcclusionEstimator(std::shared_ptr<LoadedModel> model, double probability_threshold,
                            std::optional<BoundingSurfaceOptions> surfaces = std::nullopt)
      : estimator_(std::move(model), probability_threshold, std::move(surfaces)) {}
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat& depth,
                        const CameraIntrinsics& intrinsics, cv::Mat& mask) override {
    return estimator_.estimate(rgb, depth, intrinsics, mask).occluded_pixels;
  }
  void setCameraRadius(double radius_m) { estimator_.setCameraRadius(radius_m); }

 private:
  OcclusionEstimator estimator_;
};

/// The camera bridge's estimator under `options` (its occlusion_probability,
/// clear_bounding_surfaces and radius_m): one place for the node, the in-process bridge and the
/// tools. With a `second_model`, the union of both networks' estimates (EstimateUnion), the
/// second's pixels occluded above options.second_occlusion_probability.
std::unique_ptr<ViewOcclusionEstimator> makeBridgeEstimator(
    std::shared_ptr<LoadedModel> model, const CameraEnvironmentOptions& options,
    std::shared_ptr<LoadedModel> second_model = nullptr);

}  // namespace learning
}  // namespace occlusion_env
