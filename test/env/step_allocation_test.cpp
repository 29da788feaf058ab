// The step path allocates nothing once an episode runs: a counting global operator new watches it.
// (The renderer's C library, llvmpipe, uses malloc and is not counted.)
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "occlusion_env/env/environment.hpp"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace occlusion_env {
namespace {

class StepAllocationTest : public ::testing::TestWithParam<std::string> {};

TEST_P(StepAllocationTest, StepsAllocateNothingAfterTheFirst) {
  EnvironmentOptions options;
  options.width = options.height = 128;
  // "room+SENSOR": in a room, through SENSOR.
  const std::string room_prefix = "room+";
  const bool in_room = GetParam().rfind(room_prefix, 0) == 0;
  options.world.world = in_room ? "room" : "void";
  options.sensor.depth_sensor = in_room ? GetParam().substr(room_prefix.size()) : GetParam();
  // "randomized": world, sensor and camera drawn per scene (seed 3's draw).
  if (GetParam() == "randomized")
    applySceneRandomization(options, std::nullopt, std::nullopt, true);
  options.max_steps = 1000;
  Environment env(options);
  env.reset(3);
  // The first steps may size buffers (e.g. the footprint grows); then nothing more.
  for (int t = 0; t < 5; ++t) env.step({t % 2 == 0 ? 1.0 : -1.0, 0.0});
  const long before = g_allocations.load();
  std::int64_t checksum = 0;
  for (int t = 0; t < 40; ++t) {
    const StepResult result = env.step({(t / 4) % 2 == 0 ? 1.0 : -1.0, 0.0});
    checksum +=
        result.info.occlusion.total_pixels + static_cast<long>(result.info.occlusion.pairs.size());
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "operator new calls in 40 steps";
  EXPECT_GT(checksum, 0);
}

INSTANTIATE_TEST_SUITE_P(DepthSensors, StepAllocationTest,
                         ::testing::Values("ideal", "kinect_v1", "realsense_d435", "azure_kinect",
                                           "room+ideal", "room+realsense_d435", "randomized"));

}  // namespace
}  // namespace occlusion_env
