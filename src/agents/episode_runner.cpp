#include "occlusion_env/agents/episode_runner.hpp"

#include <chrono>
#include <cmath>
#include <thread>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace {

using Clock = std::chrono::steady_clock;

// Call from a catch block: the record ends as the exception in flight says (`what` names the
// request that failed).
void endWithCurrentError(const std::string& what, EpisodeRecord& record) {
  try {
    throw;
  } catch (const UnusableViewError& error) {
    record.end = EpisodeEnd::kUnusableView;
    record.message = "the camera's view at " + what + " could not be used: " + error.what();
  } catch (const EnvironmentUnavailableError& error) {
    record.end = EpisodeEnd::kEnvironmentLost;
    record.message = "lost the environment at " + what + ": " + error.what();
  } catch (const std::exception& error) {
    record.end = EpisodeEnd::kEnvironmentError;
    record.message = what + " failed: " + error.what();
  }
}

// Waits so that steps come at most `rate_hz` per second (0: never waits).
class StepPacer {
 public:
  explicit StepPacer(double rate_hz)
      : period_(rate_hz > 0.0 ? std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(1.0 / rate_hz))
                              : Clock::duration::zero()),
        next_(Clock::now()) {}
  void wait() {
    if (period_ == Clock::duration::zero()) return;
    std::this_thread::sleep_until(next_);
    next_ += period_;
  }

 private:
  Clock::duration period_;
  Clock::time_point next_;
};

// The record's view after `result`: its pose joins the path.
void observe(const StepResult& result, const EpisodeRunOptions& options, EpisodeRecord& record) {
  record.path.push_back(result.info.pose);
  record.final_occlusion_px = result.info.occlusion.total_pixels;
  record.occlusion_source = result.info.occlusion_source;
  if (options.on_result) options.on_result(result);
}

// Acts and steps until the episode ends; `result` is the reset's.
void stepUntilDone(EnvironmentInterface& environment, Agent& agent, StepResult result,
                   const EpisodeRunOptions& options, EpisodeRecord& record) {
  StepPacer pacer(options.step_rate_hz);
  record.end = EpisodeEnd::kStepLimit;
  while (record.steps < options.max_steps) {
    if (options.keep_running && !options.keep_running()) {
      record.end = EpisodeEnd::kStopped;
      record.message = "stopped after " + std::to_string(record.steps) + " steps";
      return;
    }
    pacer.wait();
    const std::string step_name = "step " + std::to_string(record.steps + 1);
    Action action;
    try {
      action = agent.act(rigObservationOf(result));
    } catch (const std::exception& error) {
      record.end = EpisodeEnd::kAgentFailed;
      record.message = "the agent could not act before " + step_name + ": " + error.what();
      return;
    }
    try {
      result = environment.step(action);
    } catch (...) {
      endWithCurrentError(step_name, record);
      return;
    }
    ++record.steps;
    observe(result, options, record);
    if (result.terminated || result.truncated) {
      record.end = result.terminated ? EpisodeEnd::kSuccess : EpisodeEnd::kTruncated;
      return;
    }
  }
}

}  // namespace

EpisodeRecord runEpisode(EnvironmentInterface& environment, Agent& agent,
                         const EpisodeRequest& request, const EpisodeRunOptions& options) {
  if (options.max_steps < 0) throw InvalidArgumentError("max_steps must be >= 0");
  if (!(options.step_rate_hz >= 0.0) || !std::isfinite(options.step_rate_hz)) {
    throw InvalidArgumentError("step_rate_hz must be finite and >= 0");
  }
  const Clock::time_point start = Clock::now();
  EpisodeRecord record;
  record.agent = request.agent;
  record.scene_set = request.scene_set;
  record.scene_seed = request.seed;
  record.max_steps = options.max_steps;
  record.start_azimuth_rad = request.reset.start_azimuth_rad.value_or(0.0);
  StepResult result;
  bool started = false;
  try {
    result = environment.reset(request.seed, request.reset);
    started = true;
  } catch (...) {
    endWithCurrentError("reset", record);
  }
  if (started) {
    agent.reset(request.seed);
    record.start_azimuth_rad =
        request.reset.start_azimuth_rad.value_or(result.info.pose.azimuth_rad);
    observe(result, options, record);
    stepUntilDone(environment, agent, result, options, record);
  }
  record.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return record;
}

}  // namespace occlusion_env
