#include "occlusion_env/env/vector_environment.hpp"

#include <stdexcept>
#include <utility>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {

VectorRequest VectorRequest::resetTo(std::uint64_t seed, const ResetOptions& options) {
  VectorRequest request;
  request.kind = Kind::kReset;
  request.seed = seed;
  request.reset = options;
  return request;
}

VectorRequest VectorRequest::stepBy(const Action& action) {
  VectorRequest request;
  request.kind = Kind::kStep;
  request.action = action;
  return request;
}

VectorEnvironment::VectorEnvironment(int count, Factory factory, Observer observer)
    : observer_(std::move(observer)) {
  if (count < 1 || count > 256) {
    throw InvalidArgumentError("vector environment: count must be in [1, 256], got " +
                               std::to_string(count));
  }
  if (!factory) throw InvalidArgumentError("vector environment: no factory");
  for (int i = 0; i < count; ++i) workers_.push_back(std::make_unique<Worker>());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_ = count;
  }
  for (int i = 0; i < count; ++i) {
    workers_[i]->thread = std::thread([this, i, factory] { serve(i, factory); });
  }
  std::exception_ptr first_error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    work_done_.wait(lock, [this] { return pending_ == 0; });
    for (auto& worker : workers_) {
      if (worker->error && !first_error) first_error = worker->error;
    }
  }
  if (first_error) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    work_ready_.notify_all();
    for (auto& worker : workers_) worker->thread.join();
    std::rethrow_exception(first_error);
  }
}

VectorEnvironment::~VectorEnvironment() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  work_ready_.notify_all();
  for (auto& worker : workers_) {
    if (worker->thread.joinable()) worker->thread.join();
  }
}

void VectorEnvironment::serve(int index, const Factory& factory) {
  Worker& worker = *workers_[index];
  try {
    worker.environment = factory(index);
    if (!worker.environment) throw std::runtime_error("the factory made no environment");
    worker.description = worker.environment->describe();
  } catch (...) {
    worker.error = std::current_exception();
  }
  std::unique_lock<std::mutex> lock(mutex_);
  if (--pending_ == 0) work_done_.notify_all();
  if (worker.error) return;  // the constructor stops every thread
  for (;;) {
    work_ready_.wait(lock, [&] { return stopping_ || worker.has_work; });
    if (stopping_) return;
    const VectorRequest request = worker.request;
    const Task* task = worker.task;
    lock.unlock();
    std::exception_ptr error;
    try {
      if (task) {
        (*task)(index, *worker.environment);
      } else {
        if (request.kind == VectorRequest::Kind::kReset) {
          worker.result = worker.environment->reset(request.seed, request.reset);
        } else {
          worker.result = worker.environment->step(request.action);
        }
        if (observer_) observer_(index, worker.result);
      }
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    worker.error = error;
    worker.task = nullptr;
    worker.has_work = false;
    work_done_.notify_all();
  }
}

void VectorEnvironment::run(const std::vector<VectorRequest>& requests) {
  if (requests.size() != workers_.size()) {
    throw InvalidArgumentError("vector environment: " + std::to_string(requests.size()) +
                               " requests for " + std::to_string(workers_.size()) +
                               " environments");
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& worker : workers_) {
      if (worker->has_work) throw InvalidStateError("vector environment: run() while busy");
    }
    for (std::size_t i = 0; i < workers_.size(); ++i) {
      workers_[i]->error = nullptr;
      if (requests[i].kind == VectorRequest::Kind::kIdle) continue;
      workers_[i]->request = requests[i];
      workers_[i]->has_work = true;
    }
  }
  work_ready_.notify_all();
  waitForAll();
}

void VectorEnvironment::runOnEach(const Task& task) {
  if (!task) throw InvalidArgumentError("vector environment: runOnEach() without a task");
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& worker : workers_) {
      if (worker->has_work) throw InvalidStateError("vector environment: runOnEach() while busy");
    }
    for (auto& worker : workers_) {
      worker->error = nullptr;
      worker->task = &task;
      worker->has_work = true;
    }
  }
  work_ready_.notify_all();
  waitForAll();
}

void VectorEnvironment::waitForAll() {
  std::exception_ptr first_error;
  for (std::size_t i = 0; i < workers_.size(); ++i) {
    try {
      wait(static_cast<int>(i));
    } catch (...) {
      if (!first_error) first_error = std::current_exception();
    }
  }
  if (first_error) std::rethrow_exception(first_error);
}

void VectorEnvironment::start(int index, const VectorRequest& request) {
  Worker& worker = *workers_.at(index);
  if (request.kind == VectorRequest::Kind::kIdle) {
    throw InvalidArgumentError("vector environment: start() needs a reset or a step");
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (worker.has_work) {
      throw InvalidStateError("vector environment: environment " + std::to_string(index) +
                              " is still busy");
    }
    worker.error = nullptr;
    worker.request = request;
    worker.has_work = true;
  }
  work_ready_.notify_all();
}

void VectorEnvironment::wait(int index) {
  Worker& worker = *workers_.at(index);
  {
    std::unique_lock<std::mutex> lock(mutex_);
    work_done_.wait(lock, [&worker] { return !worker.has_work; });
  }
  rethrowError(index);
}

void VectorEnvironment::rethrowError(int index) {
  Worker& worker = *workers_[index];
  if (!worker.error) return;
  const std::exception_ptr error = std::exchange(worker.error, nullptr);
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& error) {
    // Keep the core's exception type where there is one; name the environment.
    const std::string where =
        "environment " + std::to_string(index) + " (" + worker.description + "): " + error.what();
    if (dynamic_cast<const InvalidArgumentError*>(&error)) throw InvalidArgumentError(where);
    if (dynamic_cast<const InvalidStateError*>(&error)) throw InvalidStateError(where);
    if (dynamic_cast<const EnvironmentUnavailableError*>(&error)) {
      throw EnvironmentUnavailableError(where);
    }
    if (dynamic_cast<const SceneGenerationError*>(&error)) throw SceneGenerationError(where);
    throw std::runtime_error(where);
  }
}

}  // namespace occlusion_env
