// The one episode rule of every environment (issue 27): the step count, truncation at max_steps,
// the reward of Eq. 7-8 and termination on clear views. The simulator gives it the occlusion it
// counts and ends an episode on the first clear view; the camera bridge gives it the network's
// estimate and asks for confirm_views clear views in a row. The reset view never confirms.
#pragma once

#include <cstdint>

#include "occlusion_env/occlusion/occlusion.hpp"
#include "occlusion_env/occlusion/reward.hpp"

namespace occlusion_env {

/// A view whose occlusion nobody can say (a camera bridge without a model): it earns no reward
/// and never confirms a clear view, so only max_steps ends such an episode.
constexpr std::int64_t kUnknownOcclusion = -1;

struct EpisodeRuleOptions {
  RewardOptions reward;  // Z, the bonus and penalty P, and what counts as clear [px]
  int max_steps = 50;    // the step that reaches it ends the episode (truncated) unless it succeeds
  int confirm_views = 1;  // this many clear step views in a row end the episode (terminated)

  /// Throws InvalidArgumentError for max_steps or confirm_views below 1.
  void validate() const;
};

/// What the rule makes of one step's view.
struct StepVerdict {
  double reward = 0.0;      // (L_{t-1} - L_t) / Z + P; 0 when L_t is unknown
  bool terminated = false;  // the confirm_views-th clear view in a row
  bool truncated = false;   // max_steps reached without success
};

class EpisodeRule {
 public:
  explicit EpisodeRule(const EpisodeRuleOptions& options = {});

  /// Starts an episode at the reset view: step 0, no clear view yet, Z from `first_view` by the
  /// reward's normalisation (at least 1).
  void start(const OcclusionStats& first_view);

  /// InvalidStateError before start() or after the episode has ended; the caller asks before it
  /// changes anything, so that a refused step leaves the episode as it was.
  void requireStep() const;

  /// Counts the step whose view has occlusion `occlusion_px` [px] (kUnknownOcclusion: unknown)
  /// and returns its reward and end. Throws as requireStep() does.
  StepVerdict step(std::int64_t occlusion_px);

  /// A view at or below the success threshold; never an unknown one.
  bool clear(std::int64_t occlusion_px) const;

  int stepIndex() const { return step_index_; }
  bool started() const { return started_; }
  bool over() const { return over_; }
  int clearViewsInARow() const { return clear_views_; }
  const RewardFunction& reward() const { return reward_; }
  const EpisodeRuleOptions& options() const { return options_; }

 private:
  EpisodeRuleOptions options_;
  RewardFunction reward_;
  bool started_ = false;
  bool over_ = false;
  int step_index_ = 0;
  int clear_views_ = 0;                                 // step views in a row that were clear
  std::int64_t last_occlusion_px_ = kUnknownOcclusion;  // L_{t-1}
};

}  // namespace occlusion_env
