// N environments stepped together, each on a thread of its own: an in-process simulator keeps its
// GL context on the thread that made it, a ROS client waits on its own service call. One call
// sends every environment its request (reset, step or nothing) and returns when all have
// answered, so a trainer batches the N observations for one inference.
//
//   VectorEnvironment envs(4, [&](int i) { return std::make_unique<Environment>(options); });
//   envs.run(requests);  // requests[i]: reset(seed) | step(action) | idle
//   envs.result(i)       // what environment i answered last
//   envs.start(i, request); ...; envs.wait(i);  // one environment works while the caller does
//   envs.runOnEach([&](int i, EnvironmentInterface& env) { ... });  // each thread, on its own
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "occlusion_env/env/environment_interface.hpp"

namespace occlusion_env {

/// What one environment does in VectorEnvironment::run().
struct VectorRequest {
  enum class Kind { kIdle, kReset, kStep };
  Kind kind = Kind::kIdle;
  std::uint64_t seed = 0;  // kReset
  ResetOptions reset;      // kReset
  Action action;           // kStep

  static VectorRequest idle() { return {}; }
  static VectorRequest resetTo(std::uint64_t seed, const ResetOptions& options = {});
  static VectorRequest stepBy(const Action& action);
};

class VectorEnvironment {
 public:
  /// Makes environment i on its own thread (the thread that then makes all of its calls).
  using Factory = std::function<std::unique_ptr<EnvironmentInterface>(int index)>;
  /// Called on environment i's thread after each of its resets and steps, while its observation
  /// is valid: the place to convert it for a network in parallel (write into a batch slot).
  using Observer = std::function<void(int index, const StepResult& result)>;
  /// Work environment i's thread does with environment i, e.g. its share of a rollout: as many
  /// resets and steps as it needs, without waiting for the others.
  using Task = std::function<void(int index, EnvironmentInterface& environment)>;

  /// Starts `count` threads and makes the environments; rethrows the first factory error.
  VectorEnvironment(int count, Factory factory, Observer observer = {});
  ~VectorEnvironment();
  VectorEnvironment(const VectorEnvironment&) = delete;
  VectorEnvironment& operator=(const VectorEnvironment&) = delete;

  int size() const { return static_cast<int>(workers_.size()); }

  /// Environment i carries out requests[i], all concurrently; returns when all are done. Throws
  /// the first error (naming the environment) after all have answered; environments whose
  /// request succeeded keep their new state.
  void run(const std::vector<VectorRequest>& requests);

  /// Environment i starts on `request` (not idle) and the call returns at once: the caller can
  /// work (e.g. run inference for other environments) while it renders. InvalidStateError if
  /// environment i has not answered its last request yet (wait() for it first).
  void start(int index, const VectorRequest& request);
  /// Returns when environment i has answered the request start() gave it (at once if none is
  /// pending); throws its error as run() does, naming the environment.
  void wait(int index);
  /// Every environment's thread runs task(i, environment i), all concurrently; returns when all
  /// are done. The observer is not called (the task sees every result itself), and result(i)
  /// keeps the last request's answer, whose observation the task's calls may have overwritten.
  /// Errors as run().
  void runOnEach(const Task& task);

  /// Environment i's answer to its last reset or step. Its observation is valid until the next
  /// run() that resets or steps environment i.
  const StepResult& result(int index) const { return workers_.at(index)->result; }
  std::string describe(int index) const { return workers_.at(index)->description; }

 private:
  struct Worker {
    std::thread thread;
    std::unique_ptr<EnvironmentInterface> environment;
    VectorRequest request;
    const Task* task = nullptr;  // runOnEach()'s, instead of the request
    bool has_work = false;
    StepResult result;
    std::exception_ptr error;
    std::string description;
  };
  void serve(int index, const Factory& factory);
  // Waits for every environment, then throws the first error (naming its environment).
  void waitForAll();
  // Throws worker i's error, if any, naming the environment; clears it.
  void rethrowError(int index);

  Observer observer_;
  std::vector<std::unique_ptr<Worker>> workers_;
  std::mutex mutex_;
  std::condition_variable work_ready_, work_done_;
  int pending_ = 0;  // factories still making their environment
  bool stopping_ = false;
};

}  // namespace occlusion_env
