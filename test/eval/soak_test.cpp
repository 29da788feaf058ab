// The soak loop on a scripted environment: seeds without an occluded start view are skipped,
// episodes end at reset_every or when the environment ends them, failed steps are counted and
// followed by a reset, a failing reset ends the soak, and windows come every report_every steps.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/eval/soak.hpp"

namespace occlusion_env {
namespace eval {
namespace {

// Answers reset and step from a script; records the seeds reset and the steps made.
class ScriptedEnvironment : public EnvironmentInterface {
 public:
  std::set<std::uint64_t> seeds_without_occlusion;  // reset throws SceneGenerationError
  std::set<int> failing_steps;                      // the n-th step call (1-based) throws
  int end_every = 0;                                // > 0: every episode ends after this many
  int fail_resets_from = -1;                        // >= 0: from this reset call on, throw

  std::vector<std::uint64_t> seeds;  // of the successful resets
  int step_calls = 0;

  StepResult reset(std::uint64_t seed, const ResetOptions&) override {
    ++reset_calls_;
    if (fail_resets_from >= 0 && reset_calls_ > fail_resets_from) {
      throw EnvironmentUnavailableError("gone");
    }
    if (seeds_without_occlusion.count(seed)) throw SceneGenerationError("no occluded view");
    seeds.push_back(seed);
    steps_in_episode_ = 0;
    return result();
  }
  StepResult step(const Action& action) override {
    ++step_calls;
    EXPECT_NEAR(action.d_azimuth_rad * action.d_azimuth_rad +
                    action.d_elevation_rad * action.d_elevation_rad,
                1.0, 1e-9);
    if (failing_steps.count(step_calls)) throw InvalidStateError("step refused");
    StepResult r = result();
    r.terminated = end_every > 0 && ++steps_in_episode_ >= end_every;
    return r;
  }
  std::string describe() const override { return "script"; }

 private:
  StepResult result() {
    StepResult r;
    r.observation = &observation_;
    return r;
  }
  Observation observation_;
  int reset_calls_ = 0;
  int steps_in_episode_ = 0;
};

SoakOptions smallSoak() {
  SoakOptions options;
  options.total_steps = 100;
  options.reset_every = 10;
  options.report_every = 30;
  options.warmup = 20;
  return options;
}

TEST(Soak, ResetsEveryFewStepsSkippingSeedsWithoutOcclusion) {
  ScriptedEnvironment env;
  env.seeds_without_occlusion = {1, 2, 5};
  std::vector<SoakWindow> windows;
  SoakHooks hooks;
  double memory = 10.0;
  hooks.resident_mib = [&memory] { return memory += 1.0; };
  hooks.on_window = [&windows](const SoakWindow& w) { windows.push_back(w); };
  const SoakReport report = runSoak(env, smallSoak(), hooks);
  EXPECT_EQ(report.steps, 100);
  EXPECT_EQ(env.step_calls, 100);
  EXPECT_EQ(report.failures, 0);
  // The first reset and one after every 10 steps: 11 scenes, seeds 1, 2 and 5 skipped.
  EXPECT_EQ(env.seeds, (std::vector<std::uint64_t>{0, 3, 4, 6, 7, 8, 9, 10, 11, 12, 13}));
  EXPECT_EQ(report.resets, 14u);
  ASSERT_EQ(windows.size(), 4u);  // at 30, 60, 90 and the end
  EXPECT_EQ(windows[0].step, 30);
  EXPECT_EQ(windows[3].step, 100);
  EXPECT_EQ(windows[0].resets, 7u);  // seeds 0..6 tried by step 30 (its reset included)
  // Memory read: at the start, at warm-up (step 20), at each window, at the end.
  EXPECT_DOUBLE_EQ(report.baseline_mib, 12.0);
  EXPECT_DOUBLE_EQ(report.end_mib, 17.0);
  EXPECT_DOUBLE_EQ(report.peak_mib, 16.0);
  EXPECT_DOUBLE_EQ(report.growthMiB(), 5.0);
  EXPECT_GT(report.first_rate, 0.0);
}

TEST(Soak, EpisodesTheEnvironmentEndsResetEarly) {
  ScriptedEnvironment env;
  env.end_every = 4;
  SoakHooks hooks;
  hooks.resident_mib = [] { return 1.0; };
  const SoakReport report = runSoak(env, smallSoak(), hooks);
  EXPECT_EQ(env.seeds.size(), 26u);  // the first, then one per 4 steps
}

TEST(Soak, FailedStepsAreCountedAndFollowedByAReset) {
  ScriptedEnvironment env;
  env.failing_steps = {5, 30};
  std::vector<long> failed_at;
  SoakHooks hooks;
  hooks.resident_mib = [] { return 1.0; };
  hooks.on_failure = [&failed_at](long step, const std::string&) { failed_at.push_back(step); };
  int windows = 0;
  hooks.on_window = [&windows](const SoakWindow&) { ++windows; };
  const SoakReport report = runSoak(env, smallSoak(), hooks);
  EXPECT_EQ(report.failures, 2);
  EXPECT_EQ(failed_at, (std::vector<long>{5, 30}));
  EXPECT_EQ(report.steps, 100);
  EXPECT_EQ(env.seeds[1], 1u);  // the reset after the failed 5th step
  EXPECT_EQ(windows, 3);        // the window ending on the failed step 30 is not reported
}

TEST(Soak, AFailingResetEndsTheSoakAndTheFirstIsThrown) {
  ScriptedEnvironment env;
  env.fail_resets_from = 2;  // the first two resets work
  SoakHooks hooks;
  hooks.resident_mib = [] { return 1.0; };
  const SoakReport report = runSoak(env, smallSoak(), hooks);
  EXPECT_EQ(report.failures, 1);
  EXPECT_EQ(report.steps, 20);  // the third reset, after step 20, failed

  ScriptedEnvironment gone;
  gone.fail_resets_from = 0;
  EXPECT_THROW(runSoak(gone, smallSoak(), hooks), EnvironmentUnavailableError);

  ScriptedEnvironment empty;
  for (std::uint64_t seed = 0; seed < 100; ++seed) empty.seeds_without_occlusion.insert(seed);
  EXPECT_THROW(runSoak(empty, smallSoak(), hooks), SceneGenerationError);

  SoakOptions bad = smallSoak();
  bad.warmup = bad.total_steps;
  EXPECT_THROW(runSoak(env, bad, hooks), InvalidArgumentError);
}

TEST(Soak, StopsWhenAskedTo) {
  ScriptedEnvironment env;
  SoakHooks hooks;
  hooks.resident_mib = [] { return 1.0; };
  hooks.keep_going = [&env] { return env.step_calls < 7; };
  EXPECT_EQ(runSoak(env, smallSoak(), hooks).steps, 7);
}

}  // namespace
}  // namespace eval
}  // namespace occlusion_env
