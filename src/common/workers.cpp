#include "occlusion_env/common/workers.hpp"

#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace occlusion_env {

std::optional<std::size_t> JobSource::next() {
  if (stopped_) return std::nullopt;
  const std::size_t job = next_++;
  if (job >= count_) return std::nullopt;
  return job;
}

void runWorkers(int threads, std::size_t jobs, const std::function<void(JobSource&)>& work) {
  JobSource source(jobs);
  std::mutex mutex;  // guards error
  std::exception_ptr error;
  const auto guarded = [&] {
    try {
      work(source);
    } catch (...) {
      source.stop();
      const std::lock_guard<std::mutex> lock(mutex);
      if (!error) error = std::current_exception();
    }
  };
  const std::size_t count = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)),
                                                  std::max<std::size_t>(1, jobs));
  if (count == 1) {
    guarded();
  } else {
    std::vector<std::thread> workers;
    for (std::size_t t = 0; t < count; ++t) workers.emplace_back(guarded);
    for (std::thread& worker : workers) worker.join();
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace occlusion_env
