#include "occlusion_env/occlusion/occlusion.hpp"

#include <array>
#include <bitset>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/render/renderer.hpp"

namespace occlusion_env {

static_assert(kMaxSceneObjects <= 8, "amodal_bits holds one bit per object in a byte");

void PairOcclusionList::push_back(const PairOcclusion& pair) {
  if (size_ == kCapacity) {
    throw InvalidArgumentError("PairOcclusionList: more than " + std::to_string(kCapacity) +
                               " pairs");
  }
  pairs_[size_++] = pair;
}

void PairOcclusionList::resize(std::size_t size) {
  if (size > kCapacity) {
    throw InvalidArgumentError("PairOcclusionList: " + std::to_string(size) + " pairs, at most " +
                               std::to_string(kCapacity));
  }
  for (std::size_t i = size_; i < size; ++i) pairs_[i] = PairOcclusion{};
  size_ = size;
}

OcclusionStats computeOcclusion(const cv::Mat& amodal_bits, int num_objects,
                                cv::Mat* occlusion_mask) {
  return computeOcclusion(amodal_bits, num_objects, cv::Rect(cv::Point(), amodal_bits.size()),
                          occlusion_mask);
}

OcclusionStats computeOcclusion(const cv::Mat& amodal_bits, int num_objects, cv::Rect region,
                                cv::Mat* occlusion_mask) {
  if (amodal_bits.type() != CV_8UC1) {
    throw InvalidArgumentError("computeOcclusion: amodal bits must be CV_8UC1");
  }
  if (num_objects < 1 || num_objects > kMaxSceneObjects) {
    throw InvalidArgumentError("computeOcclusion: object count must lie in [1, 8], got " +
                               std::to_string(num_objects));
  }
  const std::uint8_t object_mask = static_cast<std::uint8_t>((1u << num_objects) - 1u);
  region &= cv::Rect(cv::Point(), amodal_bits.size());
  if (occlusion_mask) {
    const bool reused = occlusion_mask->data != nullptr && occlusion_mask->type() == CV_8UC1 &&
                        occlusion_mask->size() == amodal_bits.size();
    if (!reused) {
      occlusion_mask->create(amodal_bits.size(), CV_8UC1);
      occlusion_mask->setTo(0);  // what `region` leaves out
    }
  }

  // One pass builds a histogram of bit patterns; every figure follows from its 256 bins. Patterns
  // come in runs along a row: counting whole runs keeps the increments off the critical path.
  std::array<std::int64_t, 256> pattern_count{};
  for (int row = region.y; row < region.y + region.height; ++row) {
    const std::uint8_t* bits = amodal_bits.ptr<std::uint8_t>(row) + region.x;
    std::uint8_t run_pattern = 0;
    int run_length = 0;
    for (int col = 0; col < region.width; ++col) {
      const std::uint8_t pattern = bits[col] & object_mask;
      if (pattern != run_pattern) {
        pattern_count[run_pattern] += run_length;
        run_pattern = pattern;
        run_length = 0;
      }
      ++run_length;
    }
    pattern_count[run_pattern] += run_length;
    if (occlusion_mask) {
      std::uint8_t* mask = occlusion_mask->ptr<std::uint8_t>(row) + region.x;
      for (int col = 0; col < region.width; ++col) {
        const std::uint8_t pattern = bits[col] & object_mask;
        // Two or more bits set: clearing the lowest one leaves something.
        mask[col] = (pattern & (pattern - 1)) ? 255 : 0;
      }
    }
  }

  OcclusionStats stats;
  for (int i = 0; i < num_objects; ++i) {
    for (int j = i + 1; j < num_objects; ++j) stats.pairs.push_back({i, j, 0});
  }
  for (int pattern = 1; pattern < 256; ++pattern) {
    const std::int64_t count = pattern_count[pattern];
    if (count == 0) continue;
    const std::int64_t objects =
        static_cast<std::int64_t>(std::bitset<kMaxSceneObjects>(pattern).count());
    stats.union_pixels += count;
    if (objects < 2) continue;
    stats.occluded_area_pixels += count;
    stats.total_pixels += count * objects * (objects - 1) / 2;
    for (PairOcclusion& pair : stats.pairs) {
      if ((pattern >> pair.first & 1) && (pattern >> pair.second & 1)) pair.pixels += count;
    }
  }
  return stats;
}

}  // namespace occlusion_env
