// The one episode rule (env/episode_rule.hpp), tested once for every environment that uses it:
// each implementation plays episodes, and every step's reward, terminated, truncated and step
// index must equal what a reference written from the rule's definition makes of the occlusion
// the implementation reported.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/episode_rule.hpp"
#include "occlusion_env/env/simulated_camera_rig.hpp"

namespace occlusion_env {
namespace {

// The environments that share the episode rule, each made with a given rule, and an episode of
// each that clears and one that stays occluded for three steps.
struct RuleScenario {
  std::uint64_t seed = 0;
  Action action;  // taken at every step
};

struct RuleImplementation {
  std::string name;
  /// The environment with `rule`; nullptr when it cannot have that rule.
  std::function<std::unique_ptr<EnvironmentInterface>(const EpisodeRuleOptions& rule)> make;
  RuleScenario clear_after_a_few_steps;   // a clear view within a dozen steps
  RuleScenario occluded_for_three_steps;  // no clear view in its first three steps
};

/// The in-process simulator, 64 x 64 px on the embedded objects: its rule ends an episode on
/// the first clear view only.
RuleImplementation simulatorRuleImplementation() {
  RuleImplementation simulator;
  simulator.name = "simulator";
  simulator.make = [](const EpisodeRuleOptions& rule) -> std::unique_ptr<EnvironmentInterface> {
    if (rule.confirm_views != 1) return nullptr;
    EnvironmentOptions options;
    options.width = options.height = 64;
    options.reward = rule.reward;
    options.max_steps = rule.max_steps;
    return std::make_unique<Environment>(options);
  };
  // Seeds 2 and 0 turning left clear after 4 and 12 steps (checked by the tests that use them).
  simulator.clear_after_a_few_steps = {2, {1.0, 0.0}};
  simulator.occluded_for_three_steps = {0, {1.0, 0.0}};
  return simulator;
}

// A camera whose frames are a grey wall at the sphere's radius and whose "estimates" are
// written out per scene: the estimate of the reset view, then of each step's view.
class ScriptedCamera : public CameraRig, public ViewOcclusionEstimator {
 public:
  explicit ScriptedCamera(std::map<std::uint64_t, std::vector<std::int64_t>> estimates)
      : estimates_(std::move(estimates)), sphere_(4.0, 1.3962634016) {
    frame_.rgb = cv::Mat(48, 64, CV_8UC3, cv::Scalar(128, 128, 128));
    frame_.depth = cv::Mat(48, 64, CV_32FC1, cv::Scalar(4.0f));
    frame_.intrinsics = CameraIntrinsics::fromFieldOfView(64, 48, 1.0);
  }
  void arrangeScene(std::uint64_t seed, const ResetOptions& /*overrides*/) override {
    script_ = &estimates_.at(seed);
    view_ = 0;
    frame_.sphere_from_optical = sphere_.worldFromOptical({0.0, 0.0});
  }
  Eigen::Isometry3d cameraPose() override { return frame_.sphere_from_optical; }
  const CameraFrame& moveTo(const SphericalPose& goal) override {
    frame_.sphere_from_optical = sphere_.worldFromOptical(goal);
    return frame_;
  }
  const CameraFrame& currentFrame() override { return frame_; }
  std::string describe() const override { return "a scripted camera"; }
  std::int64_t estimate(const cv::Mat& rgb, const cv::Mat& /*depth*/, const CameraIntrinsics&,
                        cv::Mat& mask) override {
    mask = cv::Mat::zeros(rgb.size(), CV_8UC1);
    const std::size_t view = std::min(view_++, script_->size() - 1);  // the last one repeats
    return (*script_)[view];
  }

 private:
  std::map<std::uint64_t, std::vector<std::int64_t>> estimates_;
  const std::vector<std::int64_t>* script_ = nullptr;
  std::size_t view_ = 0;
  SphericalCamera sphere_;
  CameraFrame frame_;
};

// The camera bridge's logic (CameraEnvironment) in front of the scripted camera.
class ScriptedBridge : public EnvironmentInterface {
 public:
  explicit ScriptedBridge(const EpisodeRuleOptions& rule)
      : camera_({{2, {40, 30, 0, 12, 0, 0, 0, 8}}, {0, {50, 50, 20, 10, 0}}}),
        bridge_(optionsFor(rule), camera_, &camera_) {}
  StepResult reset(std::uint64_t seed, const ResetOptions& overrides) override {
    return bridge_.reset(seed, overrides);
  }
  StepResult step(const Action& action) override { return bridge_.step(action); }
  std::string describe() const override { return bridge_.describe(); }

 private:
  static CameraEnvironmentOptions optionsFor(const EpisodeRuleOptions& rule) {
    CameraEnvironmentOptions options;
    options.occlusion_threshold_px = rule.reward.success_threshold_pixels;
    options.confirm_views = rule.confirm_views;
    options.success_bonus = rule.reward.success_bonus;
    options.step_penalty = rule.reward.step_penalty;
    options.max_steps = rule.max_steps;
    return options;
  }
  ScriptedCamera camera_;
  CameraEnvironment bridge_;
};

// The bridge's logic on a scripted camera: its episodes are written out above (seed 2 clear at
// step 2, and three clear steps in a row from step 4 on; seed 0 clear from step 4 on).
RuleImplementation bridgeRuleImplementation() {
  RuleImplementation bridge;
  bridge.name = "camera_bridge";
  bridge.make = [](const EpisodeRuleOptions& rule) -> std::unique_ptr<EnvironmentInterface> {
    if (rule.reward.normalization != RewardNormalization::kIntersection) return nullptr;
    return std::make_unique<ScriptedBridge>(rule);
  };
  bridge.clear_after_a_few_steps = {2, {1.0, 0.0}};
  bridge.occluded_for_three_steps = {0, {0.0, 1.0}};
  return bridge;
}

void PrintTo(const RuleImplementation& implementation, std::ostream* out) {
  *out << implementation.name;
}

std::vector<RuleImplementation> ruleImplementations() {
  return {simulatorRuleImplementation(), bridgeRuleImplementation()};
}

// The rule from its definition: R_t = (L_{t-1} - L_t) / max(1, L_0) + P, P the bonus on the
// view that ends the episode (the confirm_views-th clear step view in a row; the reset view never
// counts), truncation at max_steps; unknown occlusion earns nothing and never confirms.
struct ReferenceRule {
  EpisodeRuleOptions options;
  std::vector<std::int64_t> views;  // L_0, L_1, ...
  int run = 0;

  bool clear(std::int64_t l) const {
    return l >= 0 && l <= options.reward.success_threshold_pixels;
  }
  StepVerdict step(std::int64_t l) {
    views.push_back(l);
    const int t = static_cast<int>(views.size()) - 1;
    run = clear(l) ? run + 1 : 0;
    StepVerdict verdict;
    verdict.terminated = run >= options.confirm_views;
    verdict.truncated = !verdict.terminated && t >= options.max_steps;
    if (l >= 0) {
      const double z = std::max<double>(1.0, static_cast<double>(views.front()));
      const double bonus =
          verdict.terminated ? options.reward.success_bonus : options.reward.step_penalty;
      verdict.reward = (views[t - 1] >= 0 ? (views[t - 1] - l) / z : 0.0) + bonus;
    }
    return verdict;
  }
};

// The rule's parameters of a test (the intersection normalisation: both implementations have it).
EpisodeRuleOptions ruleOptions(int max_steps, int confirm_views, std::int64_t threshold_px) {
  EpisodeRuleOptions options;
  options.reward.normalization = RewardNormalization::kIntersection;
  options.reward.success_bonus = 5.0;
  options.reward.step_penalty = -0.2;
  options.reward.success_threshold_pixels = threshold_px;
  options.max_steps = max_steps;
  options.confirm_views = confirm_views;
  return options;
}

// Plays one episode of at most `steps` steps of `action` from `seed` on `environment` and checks
// every step against the reference; returns how it ended ("terminated", "truncated", "running").
std::string playAndCheck(EnvironmentInterface& environment, const EpisodeRuleOptions& options,
                         std::uint64_t seed, const Action& action, int steps) {
  const StepResult first = environment.reset(seed);
  EXPECT_EQ(first.info.step_index, 0);
  ReferenceRule reference{options, {first.info.occlusion.total_pixels}};
  for (int t = 1; t <= steps; ++t) {
    SCOPED_TRACE("step " + std::to_string(t));
    const StepResult result = environment.step(action);
    const StepVerdict expected = reference.step(result.info.occlusion.total_pixels);
    EXPECT_EQ(result.info.step_index, t);
    EXPECT_DOUBLE_EQ(result.reward, expected.reward);
    EXPECT_EQ(result.terminated, expected.terminated);
    EXPECT_EQ(result.truncated, expected.truncated);
    if (result.terminated || result.truncated) {
      // An ended episode refuses further steps.
      EXPECT_THROW(environment.step(action), InvalidStateError);
      return result.terminated ? "terminated" : "truncated";
    }
  }
  return "running";
}

class EpisodeRuleOfEveryEnvironment : public testing::TestWithParam<RuleImplementation> {};

TEST_P(EpisodeRuleOfEveryEnvironment, RefusesAStepBeforeAnyReset) {
  const auto environment = GetParam().make(ruleOptions(5, 1, 0));
  ASSERT_TRUE(environment);
  EXPECT_THROW(environment->step({1.0, 0.0}), InvalidStateError);
}

TEST_P(EpisodeRuleOfEveryEnvironment, EndsOnTheFirstClearViewWithTheBonus) {
  const EpisodeRuleOptions options = ruleOptions(50, 1, 0);
  const auto environment = GetParam().make(options);
  ASSERT_TRUE(environment);
  const RuleScenario scenario = GetParam().clear_after_a_few_steps;
  EXPECT_EQ(playAndCheck(*environment, options, scenario.seed, scenario.action, 50), "terminated");
}

TEST_P(EpisodeRuleOfEveryEnvironment, TruncatesAtMaxSteps) {
  const EpisodeRuleOptions options = ruleOptions(3, 1, 0);
  const auto environment = GetParam().make(options);
  ASSERT_TRUE(environment);
  const RuleScenario scenario = GetParam().occluded_for_three_steps;
  EXPECT_EQ(playAndCheck(*environment, options, scenario.seed, scenario.action, 10), "truncated");
  // A new episode starts afresh: step 0, and steps are taken again.
  EXPECT_EQ(playAndCheck(*environment, options, scenario.seed, scenario.action, 1), "running");
}

TEST_P(EpisodeRuleOfEveryEnvironment, ClearViewsMustFollowEachOther) {
  // confirm_views 3: only the third clear step view in a row ends the episode.
  const EpisodeRuleOptions options = ruleOptions(50, 3, 0);
  const auto environment = GetParam().make(options);
  if (!environment) GTEST_SKIP() << GetParam().name << " ends on the first clear view";
  const RuleScenario scenario = GetParam().clear_after_a_few_steps;
  EXPECT_EQ(playAndCheck(*environment, options, scenario.seed, scenario.action, 50), "terminated");
}

INSTANTIATE_TEST_SUITE_P(BothImplementations, EpisodeRuleOfEveryEnvironment,
                         testing::ValuesIn(ruleImplementations()),
                         [](const testing::TestParamInfo<RuleImplementation>& info) {
                           return info.param.name;
                         });

// The rule alone, on sequences written out by hand.
TEST(EpisodeRule, ConfirmViewsInARowAndUnknownViews) {
  EpisodeRule rule(ruleOptions(10, 2, 0));
  OcclusionStats first;
  first.total_pixels = 40;
  rule.start(first);
  EXPECT_THROW(EpisodeRule().step(0), InvalidStateError);  // before start()
  const std::vector<std::int64_t> views = {20, 0, kUnknownOcclusion, 0, 0};
  const std::vector<bool> ends = {false, false, false, false, true};
  const std::vector<double> rewards = {20.0 / 40 - 0.2, 20.0 / 40 - 0.2, 0.0, -0.2, 5.0};
  for (std::size_t t = 0; t < views.size(); ++t) {
    SCOPED_TRACE("step " + std::to_string(t + 1));
    const StepVerdict verdict = rule.step(views[t]);
    EXPECT_EQ(verdict.terminated, ends[t]);
    EXPECT_FALSE(verdict.truncated);
    EXPECT_DOUBLE_EQ(verdict.reward, rewards[t]);
  }
  EXPECT_TRUE(rule.over());
  EXPECT_THROW(rule.step(0), InvalidStateError);
  EXPECT_THROW(EpisodeRule(ruleOptions(10, 0, 0)), InvalidArgumentError);
  EXPECT_THROW(EpisodeRule(ruleOptions(0, 1, 0)), InvalidArgumentError);
}

TEST(EpisodeRule, TheSimulatorKeepsItsRewardNormalization) {
  // The simulator's default Z is the union of the silhouettes, not the first view's occlusion.
  EpisodeRuleOptions options = ruleOptions(10, 1, 0);
  options.reward.normalization = RewardNormalization::kUnion;
  EpisodeRule rule(options);
  OcclusionStats first;
  first.total_pixels = 40;
  first.union_pixels = 400;
  rule.start(first);
  EXPECT_DOUBLE_EQ(rule.step(30).reward, 10.0 / 400 - 0.2);
  EXPECT_DOUBLE_EQ(rule.step(0).reward, 30.0 / 400 + 5.0);
}

}  // namespace
}  // namespace occlusion_env
