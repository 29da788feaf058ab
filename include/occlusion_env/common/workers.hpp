// Independent jobs shared out among worker threads, each worker with state of its own (a GL
// context, networks) made on its thread: the dataset, DAgger, the evaluation and the bridge
// calibration run their scenes this way.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <optional>

namespace occlusion_env {

/// The job indices 0..count-1, handed out once each to whichever worker asks first.
class JobSource {
 public:
  explicit JobSource(std::size_t count) : count_(count) {}
  /// The next job, or none after the last one or once stop() was called. Thread-safe.
  std::optional<std::size_t> next();
  /// No job is handed out after this (a worker failed). Thread-safe.
  void stop() { stopped_ = true; }

 private:
  std::size_t count_;
  std::atomic<std::size_t> next_{0};
  std::atomic<bool> stopped_{false};
};

/// Runs `work` on min(threads, max(1, jobs)) threads at once (on the calling thread when that is
/// one) and waits for them all. Each call takes its jobs from the JobSource it is given until that
/// gives none. When one throws, the others get no further jobs and the first exception is
/// rethrown here after all have ended.
void runWorkers(int threads, std::size_t jobs, const std::function<void(JobSource&)>& work);

}  // namespace occlusion_env
