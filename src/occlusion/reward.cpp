#include "occlusion_env/occlusion/reward.hpp"

#include <algorithm>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

RewardNormalization parseRewardNormalization(const std::string& text) {
  if (text == "union") return RewardNormalization::kUnion;
  if (text == "intersection") return RewardNormalization::kIntersection;
  if (text == "none") return RewardNormalization::kNone;
  throw InvalidArgumentError("reward_normalization must be union, intersection or none, got " +
                             quoted(text));
}

std::string toString(RewardNormalization normalization) {
  switch (normalization) {
    case RewardNormalization::kUnion:
      return "union";
    case RewardNormalization::kIntersection:
      return "intersection";
    case RewardNormalization::kNone:
      return "none";
  }
  return "unknown";
}

RewardFunction::RewardFunction(const RewardOptions& options) : options_(options) {}

void RewardFunction::startEpisode(const OcclusionStats& first_frame) {
  double normalizer = 1.0;
  switch (options_.normalization) {
    case RewardNormalization::kUnion:
      normalizer = static_cast<double>(first_frame.union_pixels);
      break;
    case RewardNormalization::kIntersection:
      normalizer = static_cast<double>(first_frame.total_pixels);
      break;
    case RewardNormalization::kNone:
      break;
  }
  normalizer_ = std::max(1.0, normalizer);
}

bool RewardFunction::solved(std::int64_t occlusion_pixels) const {
  return occlusion_pixels <= options_.success_threshold_pixels;
}

double RewardFunction::operator()(std::int64_t previous, std::int64_t current) const {
  const double shaping = static_cast<double>(previous - current) / normalizer_;
  return shaping + (solved(current) ? options_.success_bonus : options_.step_penalty);
}

}  // namespace occlusion_env
