// The soak: an environment driven for many steps in random directions, with a reset every few
// steps or when an episode ends, while the memory of the process behind it and the step rate are
// watched. One loop over EnvironmentInterface: occlusion_soak runs it on the in-process simulator,
// occlusion_service_soak on the simulator's ROS services (EnvironmentClient).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {
namespace eval {

struct SoakOptions {
  long total_steps = 100000;
  long reset_every = 50;              // steps; an episode that ends resets earlier
  long report_every = 5000;           // steps per window
  long warmup = 1000;                 // steps before the memory baseline is taken
  std::uint64_t action_seed = 12345;  // the random directions
};

/// The soak's verdict: what --check / ~check hold it to.
struct SoakLimits {
  bool check = false;           // fail on a failed step or reset, memory growth or rate decay
  double max_growth_mib = 5.0;  // memory growth after warm-up at most [MiB]
  double min_rate_ratio = 0.7;  // the last window's step rate at least this part of the first's
};

/// The declared options of SoakOptions (steps, reset_every, report_every, warmup) and of
/// SoakLimits (check, max_growth_mb, min_rate_ratio): occlusion_soak's flags and
/// occlusion_service_soak's parameters.
const OptionTable<SoakOptions>& soakOptionTable();
const OptionTable<SoakLimits>& soakLimitsTable();

/// One window of steps, reported at its end.
struct SoakWindow {
  long step = 0;              // steps so far
  std::uint64_t resets = 0;   // resets tried so far (the next scene seed)
  double steps_per_s = 0.0;   // over the window
  double resident_mib = 0.0;  // at its end
};

struct SoakReport {
  long steps = 0;             // steps carried out (total_steps unless stopped)
  std::uint64_t resets = 0;   // resets tried
  int failures = 0;           // steps and resets that failed
  double seconds = 0.0;       // from the first step on, resets included
  double baseline_mib = 0.0;  // after warm-up
  double end_mib = 0.0;
  double peak_mib = 0.0;                     // the largest window figure after warm-up
  double first_rate = 0.0, last_rate = 0.0;  // steps/s of the first and last windows

  double growthMiB() const { return end_mib - baseline_mib; }
  double rateRatio() const { return last_rate / first_rate; }
};

struct SoakHooks {
  std::function<double()> resident_mib;              // memory watched [MiB]; required
  std::function<void(const SoakWindow&)> on_window;  // every report_every steps and at the end
  std::function<void(long step, const std::string& what)> on_failure;  // a step or reset failed
  std::function<bool()> keep_going;  // checked before each step (e.g. ros::ok)
};

/// Resident set size of process `pid` (0: this process) [MiB], from /proc; -1 when unreadable.
double residentMiB(int pid = 0);

/// What makes the soak fail under `limits` (one sentence each); none when it passes or
/// limits.check is off.
std::vector<std::string> soakProblems(const SoakReport& report, const SoakLimits& limits);

/// Runs the soak. Seeds 0, 1, ... in turn; a seed without an occluded start view
/// (SceneGenerationError) is skipped, as a training loop would. A step that throws counts as a
/// failure and is followed by a reset; a reset that fails otherwise (or 100 seeds in a row
/// without an occluded start view) counts as a failure and ends the soak. The first reset's
/// failure is thrown. Throws InvalidArgumentError for options out of range.
SoakReport runSoak(EnvironmentInterface& env, const SoakOptions& options, const SoakHooks& hooks);

}  // namespace eval
}  // namespace occlusion_env
