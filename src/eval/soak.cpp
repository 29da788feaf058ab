#include "occlusion_env/eval/soak.hpp"

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"

namespace occlusion_env {
namespace eval {

const OptionTable<SoakOptions>& soakOptionTable() {
  using O = SoakOptions;
  static const auto table =
      OptionTable<O>()
          .add("steps", &O::total_steps, OptionSpec("steps in all").atLeast(1))
          .add("reset_every", &O::reset_every,
               OptionSpec("steps per episode at most (an episode that ends resets earlier)")
                   .atLeast(1))
          .add("report_every", &O::report_every,
               OptionSpec("steps per line of the report (rate and memory)").atLeast(1))
          .add("warmup", &O::warmup,
               OptionSpec("steps before the memory baseline is taken").atLeast(0));
  return table;
}

const OptionTable<SoakLimits>& soakLimitsTable() {
  using O = SoakLimits;
  static const auto table =
      OptionTable<O>()
          .add("check", &O::check,
               OptionSpec("exit 1 when a step or reset failed, memory grew or the rate decayed "
                          "beyond the limits"))
          .add("max_growth_mb", &O::max_growth_mib,
               OptionSpec("check: memory growth after warm-up at most").unit("MiB").atLeast(0))
          .add("min_rate_ratio", &O::min_rate_ratio,
               OptionSpec("check: the last window's step rate at least this part of the first's")
                   .range(0, 1));
  return table;
}

std::vector<std::string> soakProblems(const SoakReport& report, const SoakLimits& limits) {
  std::vector<std::string> problems;
  if (!limits.check) return problems;
  if (report.failures > 0) problems.push_back(std::to_string(report.failures) + " requests failed");
  if (report.growthMiB() > limits.max_growth_mib) {
    problems.push_back("memory grew " + std::to_string(report.growthMiB()) + " MiB > " +
                       std::to_string(limits.max_growth_mib));
  }
  if (report.last_rate < limits.min_rate_ratio * report.first_rate) {
    problems.push_back("the step rate decayed to " + std::to_string(report.rateRatio()) +
                       " of the first window's");
  }
  return problems;
}

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kSeedsPerReset = 100;  // seeds tried for an occluded start view before giving up

// The soak's state between steps: the scene seed and the steps of the current episode.
class SoakEpisodes {
 public:
  explicit SoakEpisodes(EnvironmentInterface& env) : env_(env) {}

  // Resets on the next seed with an occluded start view; throws what the environment throws
  // otherwise, or SceneGenerationError after kSeedsPerReset seeds without one.
  void resetNext() {
    for (int tries = 0; tries < kSeedsPerReset; ++tries) {
      try {
        env_.reset(next_seed_++);
        steps_in_episode_ = 0;
        return;
      } catch (const SceneGenerationError&) {
      }
    }
    throw SceneGenerationError(std::to_string(kSeedsPerReset) +
                               " consecutive seeds without an occluded start view");
  }

  // One step; whether the episode is over (ended, or reset_every steps long).
  bool step(const Action& action, long reset_every) {
    const StepResult result = env_.step(action);
    ++steps_in_episode_;
    return result.terminated || result.truncated || steps_in_episode_ >= reset_every;
  }

  std::uint64_t resets() const { return next_seed_; }

 private:
  EnvironmentInterface& env_;
  std::uint64_t next_seed_ = 0;
  long steps_in_episode_ = 0;
};

}  // namespace

double residentMiB(int pid) {
  std::ifstream statm(pid > 0 ? "/proc/" + std::to_string(pid) + "/statm" : "/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return -1.0;
  return static_cast<double>(pages_resident) * sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0);
}

SoakReport runSoak(EnvironmentInterface& env, const SoakOptions& options, const SoakHooks& hooks) {
  if (options.total_steps <= options.warmup || options.warmup < 0 || options.reset_every < 1 ||
      options.report_every < 1) {
    throw InvalidArgumentError("need steps > warmup >= 0, reset-every >= 1, report-every >= 1");
  }
  SoakEpisodes episodes(env);
  episodes.resetNext();
  SoakReport report;
  const auto fail = [&](long step, const std::string& what) {
    ++report.failures;
    if (hooks.on_failure) hooks.on_failure(step, what);
  };
  RandomSource random(options.action_seed);
  const auto start = Clock::now();
  auto window_start = start;
  report.baseline_mib = hooks.resident_mib();
  for (long step = 1; step <= options.total_steps; ++step) {
    if (hooks.keep_going && !hooks.keep_going()) break;
    const double angle = random.uniform(-M_PI, M_PI);
    report.steps = step;
    bool step_failed = false, episode_over = false;
    try {
      episode_over = episodes.step({std::cos(angle), std::sin(angle)}, options.reset_every);
    } catch (const std::exception& error) {
      fail(step, std::string("step failed: ") + error.what());
      step_failed = episode_over = true;  // a failed step ends the episode
    }
    if (episode_over) {
      try {
        episodes.resetNext();
      } catch (const std::exception& error) {
        fail(step, std::string("reset failed: ") + error.what());
        break;
      }
    }
    if (step_failed) continue;  // not counted in the windows
    if (step == options.warmup) report.baseline_mib = hooks.resident_mib();
    if (step % options.report_every == 0 || step == options.total_steps) {
      const auto now = Clock::now();
      const long window_steps =
          step % options.report_every == 0 ? options.report_every : step % options.report_every;
      const double rate = window_steps / std::chrono::duration<double>(now - window_start).count();
      window_start = now;
      if (report.first_rate == 0.0) report.first_rate = rate;
      report.last_rate = rate;
      const double rss = hooks.resident_mib();
      if (step > options.warmup) report.peak_mib = std::max(report.peak_mib, rss);
      if (hooks.on_window) hooks.on_window({step, episodes.resets(), rate, rss});
    }
  }
  report.resets = episodes.resets();
  report.end_mib = hooks.resident_mib();
  report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return report;
}

}  // namespace eval
}  // namespace occlusion_env
