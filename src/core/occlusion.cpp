#include "occlusion_env/core/occlusion.hpp"

#include <array>
#include <bitset>

#include "occlusion_env/core/errors.hpp"
#include "occlusion_env/core/renderer.hpp"

namespace occlusion_env {

OcclusionStats computeOcclusion(const cv::Mat& amodal_bits, int num_objects,
                                cv::Mat* occlusion_mask) {
  if (amodal_bits.type() != CV_8UC1) {
    throw InvalidArgumentError("computeOcclusion: amodal bits must be CV_8UC1");
  }
  if (num_objects < 1 || num_objects > kMaxSceneObjects) {
    throw InvalidArgumentError("computeOcclusion: object count must lie in [1, 8], got " +
                               std::to_string(num_objects));
  }
  const std::uint8_t object_mask = static_cast<std::uint8_t>((1u << num_objects) - 1u);
  if (occlusion_mask) occlusion_mask->create(amodal_bits.size(), CV_8UC1);

  // One pass builds a histogram of bit patterns; every figure follows from its 256 bins.
  std::array<std::int64_t, 256> pattern_count{};
  for (int row = 0; row < amodal_bits.rows; ++row) {
    const std::uint8_t* bits = amodal_bits.ptr<std::uint8_t>(row);
    std::uint8_t* mask = occlusion_mask ? occlusion_mask->ptr<std::uint8_t>(row) : nullptr;
    for (int col = 0; col < amodal_bits.cols; ++col) {
      const std::uint8_t pattern = bits[col] & object_mask;
      ++pattern_count[pattern];
      // Two or more bits set: clearing the lowest one leaves something.
      if (mask) mask[col] = (pattern & (pattern - 1)) ? 255 : 0;
    }
  }

  OcclusionStats stats;
  for (int i = 0; i < num_objects; ++i) {
    for (int j = i + 1; j < num_objects; ++j) stats.pairs.push_back({i, j, 0});
  }
  for (int pattern = 1; pattern < 256; ++pattern) {
    const std::int64_t count = pattern_count[pattern];
    if (count == 0) continue;
    const std::int64_t objects = static_cast<std::int64_t>(std::bitset<8>(pattern).count());
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
