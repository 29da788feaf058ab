#include "occlusion_env/env/episode_rule.hpp"

#include <string>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

void EpisodeRuleOptions::validate() const {
  if (max_steps < 1) {
    throw InvalidArgumentError("max_steps must be at least 1, got " + std::to_string(max_steps));
  }
  if (confirm_views < 1) {
    throw InvalidArgumentError("confirm_views must be at least 1, got " +
                               std::to_string(confirm_views));
  }
}

EpisodeRule::EpisodeRule(const EpisodeRuleOptions& options)
    : options_((options.validate(), options)), reward_(options.reward) {}

void EpisodeRule::start(const OcclusionStats& first_view) {
  reward_.startEpisode(first_view);
  last_occlusion_px_ = first_view.total_pixels;
  step_index_ = 0;
  clear_views_ = 0;  // the reset view does not confirm: views the agent has moved to must
  started_ = true;
  over_ = false;
}

void EpisodeRule::requireStep() const {
  if (!started_) throw InvalidStateError("step before any reset: call reset first");
  if (over_) throw InvalidStateError("the episode has ended (terminated or truncated): call reset");
}

bool EpisodeRule::clear(std::int64_t occlusion_px) const {
  return occlusion_px != kUnknownOcclusion && reward_.solved(occlusion_px);
}

StepVerdict EpisodeRule::step(std::int64_t occlusion_px) {
  requireStep();
  ++step_index_;
  clear_views_ = clear(occlusion_px) ? clear_views_ + 1 : 0;
  StepVerdict verdict;
  verdict.terminated = clear_views_ >= options_.confirm_views;
  if (occlusion_px != kUnknownOcclusion) {
    const RewardOptions& reward = reward_.options();
    // Eq. 7-8 on the view's occlusion; the bonus only on the view that ends the episode.
    const double shaping =
        last_occlusion_px_ == kUnknownOcclusion
            ? 0.0
            : static_cast<double>(last_occlusion_px_ - occlusion_px) / reward_.normalizer();
    verdict.reward = shaping + (verdict.terminated ? reward.success_bonus : reward.step_penalty);
  }
  verdict.truncated = !verdict.terminated && step_index_ >= options_.max_steps;
  last_occlusion_px_ = occlusion_px;
  over_ = verdict.terminated || verdict.truncated;
  return verdict;
}

}  // namespace occlusion_env
