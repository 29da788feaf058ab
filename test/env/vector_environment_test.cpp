// N environments on their own threads give what the same environments give one after another,
// the observer sees every answer on the environment's thread, and errors name the environment.
#include "occlusion_env/env/vector_environment.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"

namespace occlusion_env {
namespace {

EnvironmentOptions smallOptions() {
  EnvironmentOptions options;  // embedded objects
  options.width = 96;
  options.height = 96;
  options.max_steps = 6;
  return options;
}

VectorEnvironment::Factory inProcess() {
  return [](int) { return std::make_unique<Environment>(smallOptions()); };
}

bool sameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() &&
         std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
}

TEST(VectorEnvironmentTest, ThreadsGiveWhatOneEnvironmentGivesInTurn) {
  constexpr int kCount = 3;
  std::vector<std::thread::id> observed(kCount);
  std::atomic<int> observations{0};
  VectorEnvironment envs(kCount, inProcess(), [&](int i, const StepResult& result) {
    ASSERT_NE(result.observation, nullptr);
    observed[i] = std::this_thread::get_id();
    ++observations;
  });
  ASSERT_EQ(envs.size(), kCount);
  EXPECT_EQ(envs.describe(1), "in-process simulator");

  Environment reference(smallOptions());
  std::vector<VectorRequest> requests;
  for (int i = 0; i < kCount; ++i) requests.push_back(VectorRequest::resetTo(40 + i));
  envs.run(requests);
  EXPECT_EQ(observations.load(), kCount);
  for (int i = 0; i < kCount; ++i) EXPECT_NE(observed[i], std::this_thread::get_id());

  for (int step = 0; step < 4; ++step) {
    for (int i = 0; i < kCount; ++i) {
      requests[i] = VectorRequest::stepBy({0.3 * (i + 1), 0.1 * step});
    }
    requests[1] = VectorRequest::idle();  // environment 1 waits this round
    envs.run(requests);
  }
  // Replay each environment's history on one environment and compare the final views.
  for (int i = 0; i < kCount; ++i) {
    StepResult expected = reference.reset(40 + i);
    if (i != 1) {
      for (int step = 0; step < 4; ++step) expected = reference.step({0.3 * (i + 1), 0.1 * step});
    }
    const StepResult& actual = envs.result(i);
    EXPECT_EQ(actual.info.step_index, expected.info.step_index) << i;
    EXPECT_EQ(actual.info.occlusion.total_pixels, expected.info.occlusion.total_pixels);
    EXPECT_DOUBLE_EQ(actual.reward, expected.reward) << i;
    EXPECT_TRUE(sameImage(actual.observation->rgb, expected.observation->rgb)) << i;
    EXPECT_TRUE(sameImage(actual.observation->depth, expected.observation->depth)) << i;
  }
}

TEST(VectorEnvironmentTest, AnErrorNamesTheEnvironmentAndKeepsTheOthersState) {
  VectorEnvironment envs(2, inProcess());
  envs.run({VectorRequest::resetTo(7), VectorRequest::idle()});
  // Environment 1 has no episode: its step is refused with the core's exception type.
  try {
    envs.run({VectorRequest::stepBy({1.0, 0.0}), VectorRequest::stepBy({1.0, 0.0})});
    FAIL() << "a step before any reset was accepted";
  } catch (const InvalidStateError& error) {
    EXPECT_NE(std::string(error.what()).find("environment 1"), std::string::npos) << error.what();
  }
  EXPECT_EQ(envs.result(0).info.step_index, 1);  // environment 0's step went through
  EXPECT_THROW(envs.run({VectorRequest::idle()}), InvalidArgumentError);  // wrong count
}

// start() returns at once and wait() gives the answer: one environment can work while the
// caller starts or waits for another; the answers equal run()'s. A busy environment refuses a
// second start(), and wait() throws an environment's error with its name.
TEST(VectorEnvironmentTest, StartAndWaitGiveWhatRunGives) {
  VectorEnvironment started(2, inProcess()), ran(2, inProcess());
  ran.run({VectorRequest::resetTo(11), VectorRequest::resetTo(12)});
  ran.run({VectorRequest::stepBy({0.4, 0.0}), VectorRequest::stepBy({0.0, 0.3})});
  started.start(0, VectorRequest::resetTo(11));
  started.start(1, VectorRequest::resetTo(12));
  EXPECT_THROW(started.start(1, VectorRequest::stepBy({0.0, 0.3})), InvalidStateError);
  started.wait(0);
  started.start(0, VectorRequest::stepBy({0.4, 0.0}));  // while environment 1 may still reset
  started.wait(1);
  started.start(1, VectorRequest::stepBy({0.0, 0.3}));
  started.wait(1);
  started.wait(0);
  started.wait(0);  // nothing pending: returns at once
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(started.result(i).info.step_index, 1) << i;
    EXPECT_EQ(started.result(i).info.occlusion.total_pixels,
              ran.result(i).info.occlusion.total_pixels);
    EXPECT_TRUE(sameImage(started.result(i).observation->rgb, ran.result(i).observation->rgb));
  }
  EXPECT_THROW(started.start(0, VectorRequest::idle()), InvalidArgumentError);
  VectorEnvironment fresh(1, inProcess());
  fresh.start(0, VectorRequest::stepBy({1.0, 0.0}));  // no episode yet
  try {
    fresh.wait(0);
    FAIL() << "a step before any reset was accepted";
  } catch (const InvalidStateError& error) {
    EXPECT_NE(std::string(error.what()).find("environment 0"), std::string::npos) << error.what();
  }
  fresh.wait(0);  // the error was reported once
}

// runOnEach() runs a task on every environment's own thread, each with its own environment, all
// at once: each does what the same calls on one environment do, the observer is not called, the
// environments keep the state the task left, and an error names its environment after all are
// done.
TEST(VectorEnvironmentTest, RunOnEachGivesEveryThreadItsOwnEnvironment) {
  constexpr int kCount = 2;
  std::atomic<int> observations{0};
  VectorEnvironment envs(kCount, inProcess(), [&](int, const StepResult&) { ++observations; });
  std::vector<std::thread::id> ran_on(kCount);
  std::vector<std::int64_t> occlusion(kCount);
  std::atomic<int> inside{0}, most_inside{0};
  envs.runOnEach([&](int i, EnvironmentInterface& environment) {
    ran_on[i] = std::this_thread::get_id();
    const int now = ++inside;
    for (int seen = most_inside.load();
         now > seen && !most_inside.compare_exchange_weak(seen, now);) {
    }
    environment.reset(60 + i);
    // Stay until the other thread is inside too (or a second has passed): they run at once.
    for (int wait = 0; wait < 1000 && most_inside.load() < kCount; ++wait) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    StepResult result;
    for (int step = 0; step < 3; ++step) result = environment.step({0.2 * (i + 1), 0.1});
    occlusion[i] = result.info.occlusion.total_pixels;
    --inside;
  });
  EXPECT_EQ(most_inside.load(), kCount) << "the tasks ran one after the other";
  EXPECT_EQ(observations.load(), 0);
  EXPECT_NE(ran_on[0], ran_on[1]);
  for (int i = 0; i < kCount; ++i) {
    EXPECT_NE(ran_on[i], std::this_thread::get_id());
    Environment reference(smallOptions());
    reference.reset(60 + i);
    StepResult expected;
    for (int step = 0; step < 3; ++step) expected = reference.step({0.2 * (i + 1), 0.1});
    EXPECT_EQ(occlusion[i], expected.info.occlusion.total_pixels) << i;
  }
  // The environments keep their episodes: a step continues where the task stopped.
  envs.run({VectorRequest::stepBy({0.1, 0.0}), VectorRequest::stepBy({0.1, 0.0})});
  EXPECT_EQ(envs.result(0).info.step_index, 4);
  EXPECT_EQ(observations.load(), kCount);
  try {
    envs.runOnEach([](int i, EnvironmentInterface&) {
      if (i == 1) throw InvalidStateError("the task failed");
    });
    FAIL() << "a task's error was lost";
  } catch (const InvalidStateError& error) {
    EXPECT_NE(std::string(error.what()).find("environment 1"), std::string::npos) << error.what();
  }
  EXPECT_THROW(envs.runOnEach({}), InvalidArgumentError);
}
TEST(VectorEnvironmentTest, AFactoryErrorReachesTheCaller) {
  EXPECT_THROW(VectorEnvironment(2,
                                 [](int i) -> std::unique_ptr<EnvironmentInterface> {
                                   if (i == 1) throw InvalidArgumentError("no camera here");
                                   return std::make_unique<Environment>(smallOptions());
                                 }),
               InvalidArgumentError);
  EXPECT_THROW(VectorEnvironment(0, inProcess()), InvalidArgumentError);
}

}  // namespace
}  // namespace occlusion_env
