// runWorkers: every job runs once, on at most as many threads as asked, and a worker's exception
// stops the others taking jobs and comes back to the caller.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "occlusion_env/common/workers.hpp"

namespace occlusion_env {
namespace {

TEST(RunWorkers, RunsEveryJobOnceOnAtMostTheThreadsAsked) {
  for (const int threads : {1, 2, 3}) {
    std::vector<std::atomic<int>> runs(50);
    std::mutex mutex;
    std::set<std::thread::id> ids;
    int calls = 0;
    runWorkers(threads, runs.size(), [&](JobSource& jobs) {
      {
        const std::lock_guard<std::mutex> lock(mutex);
        ids.insert(std::this_thread::get_id());
        ++calls;
      }
      while (const auto job = jobs.next()) ++runs[*job];
    });
    EXPECT_EQ(calls, threads);  // each worker called once
    EXPECT_EQ(ids.size(), static_cast<std::size_t>(threads));
    for (const auto& count : runs) EXPECT_EQ(count, 1);
    if (threads == 1) {
      EXPECT_EQ(*ids.begin(), std::this_thread::get_id());  // on the caller's thread
    }
  }
}

TEST(RunWorkers, NoMoreWorkersThanJobsAndOneWithout) {
  std::atomic<int> calls{0};
  runWorkers(8, 2, [&](JobSource& jobs) {
    ++calls;
    while (jobs.next()) {
    }
  });
  EXPECT_EQ(calls, 2);
  calls = 0;
  int jobs_seen = 0;
  runWorkers(4, 0, [&](JobSource& jobs) {
    ++calls;
    while (jobs.next()) ++jobs_seen;
  });
  EXPECT_EQ(calls, 1);  // its setup still runs once, as a run with nothing to do
  EXPECT_EQ(jobs_seen, 0);
}

TEST(RunWorkers, TheFirstExceptionStopsTheJobsAndReachesTheCaller) {
  std::atomic<int> ran{0};
  try {
    runWorkers(2, 1000, [&](JobSource& jobs) {
      while (const auto job = jobs.next()) {
        if (*job == 10) throw std::runtime_error("job 10 failed");
        ++ran;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "job 10 failed");
  }
  EXPECT_LT(ran, 500);  // the other worker stopped soon after, not at job 999
  EXPECT_THROW(runWorkers(1, 3, [](JobSource&) { throw std::logic_error("setup"); }),
               std::logic_error);
}

}  // namespace
}  // namespace occlusion_env
