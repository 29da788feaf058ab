// Counting occlusion from amodal silhouettes (Eq. 9 of the paper, with hard masks).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>

#include "occlusion_env/common/limits.hpp"

namespace occlusion_env {

/// Overlap of the amodal silhouettes of objects `first` < `second` [px].
struct PairOcclusion {
  int first = 0;
  int second = 0;
  std::int64_t pixels = 0;
};

/// The pairs of a scene's objects, stored inline: a step's figures are computed and copied into
/// its result without allocating. Holds the pairs of the largest scene (kMaxObjectPairs).
class PairOcclusionList {
 public:
  static constexpr std::size_t kCapacity = kMaxObjectPairs;

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  PairOcclusion& operator[](std::size_t i) { return pairs_[i]; }
  const PairOcclusion& operator[](std::size_t i) const { return pairs_[i]; }
  PairOcclusion* begin() { return pairs_.data(); }
  PairOcclusion* end() { return pairs_.data() + size_; }
  const PairOcclusion* begin() const { return pairs_.data(); }
  const PairOcclusion* end() const { return pairs_.data() + size_; }

  /// Throws InvalidArgumentError beyond kCapacity pairs.
  void push_back(const PairOcclusion& pair);
  /// New pairs are zero; throws InvalidArgumentError beyond kCapacity.
  void resize(std::size_t size);
  void clear() { size_ = 0; }

 private:
  std::array<PairOcclusion, kCapacity> pairs_{};
  std::size_t size_ = 0;
};

/// Where a view's occlusion figures come from: the simulator counts them; behind the camera
/// bridge a network estimates them, or nothing does.
enum class OcclusionSource { kGroundTruth, kEstimated, kUnavailable };

struct OcclusionStats {
  /// L = sum over object pairs of their overlap [px]; a pixel covered by k objects counts
  /// k(k-1)/2 times, as in Eq. 9.
  std::int64_t total_pixels = 0;
  /// Pixels where at least two silhouettes overlap (the occlusion mask's area) [px].
  std::int64_t occluded_area_pixels = 0;
  /// Pixels covered by at least one silhouette [px].
  std::int64_t union_pixels = 0;
  /// Every pair i < j, in order (0,1), (0,2), ..., (1,2), ...
  PairOcclusionList pairs;
};

/// Computes the statistics from `amodal_bits` (CV_8UC1, bit k = object k) for `num_objects`
/// objects (1..8). When `occlusion_mask` is non-null it receives a CV_8UC1 image, 255 where two or
/// more silhouettes overlap and 0 elsewhere (reusing its buffer when the size matches).
/// Throws InvalidArgumentError on a wrong image type or object count.
OcclusionStats computeOcclusion(const cv::Mat& amodal_bits, int num_objects,
                                cv::Mat* occlusion_mask = nullptr);

/// The same figures, reading `amodal_bits` inside `region` only: outside it every object bit must
/// be 0 (as outside RenderBuffers::footprint). `occlusion_mask` is written inside `region` only and
/// keeps its other pixels (all 0 when it is allocated here): a caller reusing one mask passes a
/// region that also covers the one of its last call.
OcclusionStats computeOcclusion(const cv::Mat& amodal_bits, int num_objects, cv::Rect region,
                                cv::Mat* occlusion_mask = nullptr);

}  // namespace occlusion_env
