// occlusion_bench: reset and step rates of the core environment (Google Benchmark).
//   make bench            (or: .build_ws/devel/lib/occlusion_env/occlusion_bench)
// Scenes: "embedded" = a seeded random scene of the embedded objects; "oak_chairs" = three copies
// of Sweet Home 3D's Blend Swap oak chair (31,786 triangles each) in the paper's layout.
// LOD 1 renders the level-of-detail meshes (5000 triangles per object), LOD 0 the full meshes;
// BM_StepLodBudget steps the oak chairs at other budgets. BM_VectorStep steps N environments at
// once on their own threads (VectorEnvironment), as a trainer does.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/env/vector_environment.hpp"
#include "occlusion_env/occlusion/bounding_surfaces.hpp"
#include "occlusion_env/occlusion/occlusion_gradient.hpp"
#include "occlusion_env/scene/model_split.hpp"
#include "occlusion_env/scene/object_catalog.hpp"

namespace occlusion_env {
namespace {

constexpr const char* kOakChairId = "Blend Swap CC-0#oakChair";
constexpr std::size_t kLodBudget = 5000;

enum SceneKind { kEmbedded = 0, kOakChairs = 1 };

/// Libraries are shared between benchmarks so that mesh loading and simplification are paid once.
std::shared_ptr<ObjectLibrary> sharedLibrary(SceneKind kind, std::size_t lod_budget) {
  static std::map<std::pair<int, std::size_t>, std::shared_ptr<ObjectLibrary>> libraries;
  auto& library = libraries[{kind, lod_budget}];
  if (!library) {
    CatalogOptions catalog;
    catalog.source = kind == kEmbedded ? "embedded" : "sweethome3d";
    library = std::make_shared<ObjectLibrary>(makeCatalog(catalog), lod_budget);
  }
  return library;
}

struct Setup {
  SceneKind kind = kEmbedded;
  EnvironmentOptions options;
  ResetOptions reset;
};

/// `lod_budget` triangles per object, 0 = full meshes.
Setup setupFor(int size, SceneKind kind, std::size_t lod_budget) {
  Setup setup;
  setup.kind = kind;
  setup.options.width = setup.options.height = size;
  setup.options.lod_triangle_budget = lod_budget;
  setup.options.max_steps = 1 << 30;  // stepping never truncates
  setup.options.catalog.source = kind == kEmbedded ? "embedded" : "sweethome3d";
  if (kind == kOakChairs) setup.reset.object_ids = {kOakChairId, kOakChairId, kOakChairId};
  return setup;
}

/// Arguments size, scene, lod (on = the default budget) of the scene benchmarks.
Setup setupFor(const benchmark::State& state) {
  return setupFor(static_cast<int>(state.range(0)), static_cast<SceneKind>(state.range(1)),
                  state.range(2) ? kLodBudget : 0);
}

std::unique_ptr<Environment> makeEnvironment(const Setup& setup) {
  return std::make_unique<Environment>(
      setup.options, sharedLibrary(setup.kind, setup.options.lod_triangle_budget));
}

void labelFor(benchmark::State& state) {
  state.SetLabel(std::string(state.range(1) == kEmbedded ? "embedded" : "oak_chairs") +
                 (state.range(2) ? " lod" : " full") + " " + std::to_string(state.range(0)) + "px");
}

void stepBenchmark(benchmark::State& state, const Setup& setup) {
  std::unique_ptr<Environment> env;
  try {
    env = makeEnvironment(setup);
    env->reset(1, setup.reset);
  } catch (const std::exception& error) {
    state.SkipWithError(error.what());
    return;
  }
  // Swing the camera back and forth around the start pose so the scene stays occluded.
  int t = 0;
  for (auto _ : state) {
    const double direction = (t++ / 4) % 2 == 0 ? 1.0 : -1.0;
    const StepResult result = env->step({direction, 0.0});
    if (result.terminated || result.truncated) env->reset(t, setup.reset);
    benchmark::DoNotOptimize(result.info.occlusion.total_pixels);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Step(benchmark::State& state) {
  stepBenchmark(state, setupFor(state));
  labelFor(state);
}

// The oak-chair scene at other LOD budgets (arguments size, budget; 0 = full meshes): the speed
// side of the budget trade-off, whose silhouette side occlusion_lod_report measures.
void BM_StepLodBudget(benchmark::State& state) {
  stepBenchmark(state, setupFor(static_cast<int>(state.range(0)), kOakChairs,
                                static_cast<std::size_t>(state.range(1))));
  state.SetLabel("oak_chairs budget " + std::to_string(state.range(1)) + " " +
                 std::to_string(state.range(0)) + "px");
}

// A camera-like world (arguments scene kind, world 0 void / 1 room, depth sensor index of
// depthSensorNames(): 0 ideal, 2 realsense_d435) at 256 px with LOD: the rate against today's
// (void, ideal) for the same scenes.
void BM_StepWorld(benchmark::State& state) {
  Setup setup = setupFor(256, static_cast<SceneKind>(state.range(0)), kLodBudget);
  setup.options.world.world = state.range(1) ? "room" : "void";
  setup.options.sensor.depth_sensor = depthSensorNames().at(state.range(2));
  stepBenchmark(state, setup);
  state.SetLabel(std::string(state.range(0) == kEmbedded ? "embedded" : "oak_chairs") + " " +
                 setup.options.world.world + " " + setup.options.sensor.depth_sensor + " 256px");
}

void worldArguments(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"scene", "room", "sensor"});
  for (int kind : {kEmbedded, kOakChairs}) {
    for (const auto& [room, sensor] : {std::pair{0, 0}, {1, 0}, {0, 2}, {1, 2}}) {
      benchmark->Args({kind, room, sensor});
    }
  }
  benchmark->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();
}

// The camera bridge's floor-and-wall finder (occlusion/bounding_surfaces.hpp) on the network's
// 64 x 64 grid of a start view of a room through the D435 model (sampled, not block-averaged).
void BM_BoundingSurfaces(benchmark::State& state) {
  Setup setup = setupFor(256, kEmbedded, kLodBudget);
  setup.options.world.world = "room";
  setup.options.sensor.depth_sensor = "realsense_d435";
  Environment env(setup.options);
  const StepResult start = env.reset(1);
  cv::Mat depth;
  cv::resize(start.observation->depth, depth, cv::Size(64, 64), 0.0, 0.0, cv::INTER_NEAREST);
  CameraIntrinsics grid = start.info.intrinsics;
  grid.width = grid.height = 64;
  grid.fx *= 0.25;
  grid.fy *= 0.25;
  grid.cx = (grid.cx + 0.5) * 0.25 - 0.5;
  grid.cy = (grid.cy + 0.5) * 0.25 - 0.5;
  BoundingSurfaceFinder finder;
  cv::Mat on_surface;
  std::size_t planes = 0;
  for (auto _ : state) planes = finder.find(depth, grid, on_surface).size();
  state.SetLabel(std::to_string(planes) + " planes, " +
                 std::to_string(cv::countNonZero(on_surface)) + " of 4096 px on them");
}
BENCHMARK(BM_BoundingSurfaces)->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();

// What every random scene draw of Sweet Home 3D chairs and tables of the train split pays to
// know which models it may draw (scene/model_split.hpp).
void BM_ModelSplit(benchmark::State& state) {
  CatalogOptions sweethome3d;
  sweethome3d.source = "sweethome3d";
  const std::unique_ptr<ObjectCatalog> catalog = makeCatalog(sweethome3d);
  std::vector<std::string> ids = catalog->idsInCategory("chair");
  const std::vector<std::string> tables = catalog->idsInCategory("table");
  ids.insert(ids.end(), tables.begin(), tables.end());
  std::size_t kept = 0;
  for (auto _ : state) kept = idsInSplit(*catalog, ids, ModelSplit::kTrain).size();
  state.SetLabel(std::to_string(kept) + " of " + std::to_string(ids.size()) + " ids kept");
}
BENCHMARK(BM_ModelSplit)->Unit(benchmark::kMicrosecond)->MinTime(1.0)->UseRealTime();

void BM_Reset(benchmark::State& state) {
  const Setup setup = setupFor(state);
  std::unique_ptr<Environment> env;
  try {
    env = makeEnvironment(setup);
    env->reset(0, setup.reset);  // warms the library's cache
  } catch (const std::exception& error) {
    state.SkipWithError(error.what());
    return;
  }
  std::uint64_t seed = 1;
  for (auto _ : state) {
    try {
      const StepResult result = env->reset(seed++, setup.reset);
      benchmark::DoNotOptimize(result.info.occlusion.total_pixels);
    } catch (const SceneGenerationError&) {
      // Rare (a few seeds in a thousand for three identical chairs): every draw came out
      // unoccluded. Timed like any other reset; the environment keeps its last episode.
    }
  }
  state.SetItemsProcessed(state.iterations());
  labelFor(state);
}

// The occlusion gradient of the start view (analytic: from the current buffers; finite
// differences: four renders at +/- h). Compare with BM_Step (one render) in the same run.
void gradientBenchmark(benchmark::State& state, const char* method) {
  const Setup setup = setupFor(state);
  std::unique_ptr<Environment> env;
  std::unique_ptr<OcclusionGradient> gradient;
  try {
    env = makeEnvironment(setup);
    env->reset(1, setup.reset);
    gradient = makeOcclusionGradient(method);
  } catch (const std::exception& error) {
    state.SkipWithError(error.what());
    return;
  }
  for (auto _ : state) {
    const GradientResult result = gradient->compute(*env);
    benchmark::DoNotOptimize(result.gradient);
  }
  state.SetItemsProcessed(state.iterations());
  labelFor(state);
}

void BM_AnalyticGradient(benchmark::State& state) {
  gradientBenchmark(state, "analytic");
}
void BM_FiniteDifferenceGradient(benchmark::State& state) {
  gradientBenchmark(state, "finite_difference");
}

// Arguments: image size [px], scene kind, LOD on (1). Wall-clock time, as for the steps.
void gradientArguments(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"size", "scene", "lod"});
  for (int kind : {kEmbedded, kOakChairs}) benchmark->Args({256, kind, 1});
  benchmark->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();
}

// Arguments: image size [px], scene kind, LOD on (1) or off (0).
void sceneArguments(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"size", "scene", "lod"});
  for (int kind : {kEmbedded, kOakChairs}) {
    for (int lod : {1, 0}) {
      for (int size : {128, 256, 512}) benchmark->Args({size, kind, lod});
    }
  }
  // Wall-clock time: llvmpipe renders on its own threads, which CPU time would not count.
  benchmark->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();
}

// Arguments: image size [px], LOD triangle budget per object (0 = full meshes).
void budgetArguments(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"size", "budget"});
  for (int size : {128, 256}) {
    for (int budget : {3000, 4000, 5000, 6000, 8000, 0}) benchmark->Args({size, budget});
  }
  benchmark->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();
}

// N environments on their own threads (arguments envs, size, scene 0 = embedded, 1 = the PPO
// trainer's scenes: Sweet Home 3D chairs and tables of the train split): every environment
// steps in a random direction (seeded); one that ended resets in the next round while the others
// step, as Gymnasium's vector environments do. Items = steps and resets of all environments, so
// items/s is the aggregate step rate.
void BM_VectorStep(benchmark::State& state) {
  const int count = static_cast<int>(state.range(0));
  const bool training_scenes = state.range(2) == 1;
  EnvironmentOptions options;
  if (training_scenes) {
    SceneSet scenes;
    scenes.source = "sweethome3d";
    scenes.categories = {"chair", "table"};
    scenes.model_split = "train";
    options = environmentOptionsFor(scenes);
  }
  options.width = options.height = static_cast<int>(state.range(1));
  auto library = training_scenes ? std::make_shared<ObjectLibrary>(makeCatalog(options.catalog),
                                                                   options.lod_triangle_budget)
                                 : sharedLibrary(kEmbedded, options.lod_triangle_budget);
  std::unique_ptr<VectorEnvironment> envs;
  std::vector<VectorRequest> requests(count);
  std::uint64_t next_seed = 1;
  try {
    envs = std::make_unique<VectorEnvironment>(
        count, [&](int) { return std::make_unique<Environment>(options, library); });
    for (auto& request : requests) request = VectorRequest::resetTo(next_seed++);
    envs->run(requests);
  } catch (const std::exception& error) {
    state.SkipWithError(error.what());
    return;
  }
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (auto _ : state) {
    for (int i = 0; i < count; ++i) {
      const StepResult& last = envs->result(i);
      const double a = angle(random);
      requests[i] = last.terminated || last.truncated
                        ? VectorRequest::resetTo(next_seed++)
                        : VectorRequest::stepBy({std::cos(a), std::sin(a)});
    }
    envs->run(requests);
  }
  state.SetItemsProcessed(state.iterations() * count);
  state.SetLabel(std::to_string(count) + " envs " + (training_scenes ? "training" : "embedded") +
                 " " + std::to_string(state.range(1)) + "px");
}

void vectorArguments(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"envs", "size", "scene"});
  for (int scene : {0, 1}) {
    for (int size : {128, 256}) {
      for (int envs : {1, 2}) benchmark->Args({envs, size, scene});
    }
  }
  benchmark->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
}

BENCHMARK(BM_Step)->Apply(sceneArguments);
BENCHMARK(BM_StepLodBudget)->Apply(budgetArguments);
BENCHMARK(BM_StepWorld)->Apply(worldArguments);
BENCHMARK(BM_Reset)->Apply(sceneArguments);
BENCHMARK(BM_AnalyticGradient)->Apply(gradientArguments);
BENCHMARK(BM_FiniteDifferenceGradient)->Apply(gradientArguments);
BENCHMARK(BM_VectorStep)->Apply(vectorArguments);

}  // namespace
}  // namespace occlusion_env

BENCHMARK_MAIN();
