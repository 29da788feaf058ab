// The reward of Eq. 7-8: R_t = (L_{t-1} - L_t) / Z + P(L_t).
#pragma once

#include <cstdint>
#include <string>

#include "occlusion_env/occlusion/occlusion.hpp"

namespace occlusion_env {

/// How the occlusion difference is normalised (Z in R_t).
enum class RewardNormalization {
  kUnion,         // Z = union of the silhouettes in the first frame [px]
  kIntersection,  // Z = occlusion L in the first frame [px]
  kNone,          // Z = 1
};

/// "union" | "intersection" | "none"; throws InvalidArgumentError otherwise.
RewardNormalization parseRewardNormalization(const std::string& text);
std::string toString(RewardNormalization normalization);

struct RewardOptions {
  RewardNormalization normalization = RewardNormalization::kUnion;
  double success_bonus = 5.0;                 // P when L_t <= threshold
  double step_penalty = -0.2;                 // P otherwise
  std::int64_t success_threshold_pixels = 0;  // L_t at or below this ends the episode [px]
};

class RewardFunction {
 public:
  explicit RewardFunction(const RewardOptions& options = {});

  /// Fixes Z from the episode's first frame. Z never drops below 1.
  void startEpisode(const OcclusionStats& first_frame);

  double normalizer() const { return normalizer_; }
  bool solved(std::int64_t occlusion_pixels) const;
  /// Reward for going from L_{t-1} = `previous` to L_t = `current` [px].
  double operator()(std::int64_t previous, std::int64_t current) const;

  const RewardOptions& options() const { return options_; }

 private:
  RewardOptions options_;
  double normalizer_ = 1.0;
};

}  // namespace occlusion_env
