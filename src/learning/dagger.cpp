#include "occlusion_env/learning/dagger.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"
#include "occlusion_env/common/workers.hpp"
#include "occlusion_env/dataset/bop_dataset.hpp"
#include "occlusion_env/dataset/scene_writer.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"

namespace occlusion_env {
namespace learning {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kMixtureStreamSalt = 0x6461676765726d78ull;  // the mixture's coin

// FNV-1a (64 bit) of a file's bytes, as 16 hex digits: which model made a dataset.
std::string fileHash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidArgumentError("dagger: cannot read the model " + path);
  std::uint64_t hash = 0xcbf29ce484222325ull;
  std::vector<char> buffer(1 << 16);
  while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      hash = (hash ^ static_cast<unsigned char>(buffer[i])) * 0x100000001b3ull;
    }
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

nlohmann::json manifestFor(const DaggerOptions& options, const ObjectCatalog& catalog) {
  nlohmann::json manifest = dataset::datasetManifest(options.datasetOptions(), catalog);
  manifest["tool"] = "occlusion_dagger";
  manifest["options"] = options.definingJson();
  manifest["frame_moves"] =
      "frame 0: the scene's start view; each next frame: one step of the predicted-escape agent "
      "(the model in options.dagger), or with probability beta the oracle's first step, from the "
      "previous frame; the roll-out ends at an unoccluded view (its last frame) or after "
      "max_steps steps, or with moves_past_clear > 0 that many of the agent's moves after its "
      "first unoccluded view (outside the ended episode), within max_steps";
  return manifest;
}

struct Rollout {
  std::vector<SphericalPose> poses;  // the states visited, the start view first
  int expert_moves = 0;
  bool success = false;
};

// The agent's episode on scene `seed` in the writer's environment.
Rollout rollOut(dataset::SceneWriter& writer, Agent& agent, std::uint64_t seed,
                const DaggerOptions& options) {
  Environment& environment = writer.environment();
  StepResult result = environment.reset(seed);
  writer.oracle().clear(result.info.pose);  // the labels' anchor: the same answers as theirs
  agent.reset(seed);
  RandomSource coin(seed ^ kMixtureStreamSalt);
  Rollout rollout;
  rollout.poses.push_back(result.info.pose);
  int moves_past_clear = 0;
  for (int step = 0; step < options.max_steps && !result.truncated; ++step) {
    if (result.terminated) {
      // The episode ended at an unoccluded view; the camera moves on outside it, as a camera
      // whose stopping rule waits for more views would, and the agent still steers.
      if (moves_past_clear == options.moves_past_clear) break;
      ++moves_past_clear;
      result.info = environment.moveOutsideEpisode(
          agent.act(rigObservationOf(environment.observation(), result.info)));
      rollout.poses.push_back(result.info.pose);
      continue;
    }
    Action action = agent.act(rigObservationOf(result));
    if (options.beta > 0.0 && coin.uniform() < options.beta) {
      const OracleAnswer answer = writer.oracle().query(result.info.pose);
      if (!answer.path.empty()) {
        action = answer.path.front();
        ++rollout.expert_moves;
      }
    }
    result = environment.step(action);
    rollout.poses.push_back(result.info.pose);
  }
  rollout.success = result.terminated;
  return rollout;
}

// The scenes of `dir` not complete yet; counts the complete ones in report.scenes_skipped.
std::vector<int> scenesToDo(const std::string& dir, int scenes, DaggerReport& report) {
  std::vector<int> todo;
  for (int index = 0; index < scenes; ++index) {
    if (fs::exists(fs::path(dataset::sceneFolder(dir, index)) / dataset::kLabelsFile)) {
      ++report.scenes_skipped;
    } else {
      todo.push_back(index);
    }
  }
  return todo;
}

}  // namespace

dataset::DatasetOptions DaggerOptions::defaultData() {
  dataset::DatasetOptions data;
  data.validation_fraction = 0.0;
  return data;
}

const OptionTable<DaggerOptions>& daggerOptionTable() {
  using O = DaggerOptions;
  static const auto table =
      OptionTable<O>()
          .add("model", &O::model, OptionSpec("the agent's network (.pt beside its .json)"))
          .add("scenes", &O::scenes, OptionSpec("roll-outs, one per scene").range(1, 1000000))
          .add("first_seed", &O::first_seed,
               OptionSpec("scene seeds first_seed .. first_seed + scenes - 1 (training seeds, "
                          "below 900,000; not those of the other datasets trained on)"))
          .add("beta", &O::beta,
               OptionSpec("per step, the probability of executing the oracle's move instead of "
                          "the agent's (0: the agent's own states)")
                   .range(0, 1))
          .add("max_steps", &O::max_steps, OptionSpec("moves per roll-out at most").range(1, 1000))
          .add("moves_past_clear", &O::moves_past_clear,
               OptionSpec("the agent's moves recorded after its first unoccluded view (the "
                          "views a camera's stopping rule confirms on), within max_steps")
                   .range(0, 1000))
          .add("threads", &O::threads,
               OptionSpec("worker threads, one environment and network each").range(1, 64));
  return table;
}

void DaggerOptions::validate() const {
  daggerOptionTable().check(*this);
  if (model.empty()) throw InvalidArgumentError("dagger: no model given");
  if (first_seed + static_cast<std::uint64_t>(scenes) > kFirstValidationSeed) {
    throw InvalidArgumentError(
        "DAgger scenes must be training scenes, seeds below " +
        std::to_string(kFirstValidationSeed) + " (validation scenes from there, test scenes from " +
        std::to_string(kFirstTestSeed) + "); first seed " + std::to_string(first_seed) + " + " +
        std::to_string(scenes) + " scenes reaches into them");
  }
  datasetOptions().validate();
}

dataset::DatasetOptions DaggerOptions::datasetOptions() const {
  dataset::DatasetOptions options = data;
  options.scenes = scenes;
  options.first_seed = first_seed;
  options.frames = max_steps + 1;  // at most: the start view and one frame per move
  options.oracle_labels = true;
  options.threads = threads;
  return options;
}

nlohmann::json DaggerOptions::definingJson() const {
  nlohmann::json json = datasetOptions().definingJson();
  json.erase("frames");          // a roll-out's length is the agent's
  json.erase("max_move_steps");  // the moves are the agent's
  json["dagger"] = {{"model", fs::weakly_canonical(model).string()},
                    {"model_fnv1a64", fileHash(model)},
                    {"beta", beta},
                    {"max_steps", max_steps}};
  // Only when set, so that the datasets written before the option still resume.
  if (moves_past_clear > 0) json["dagger"]["moves_past_clear"] = moves_past_clear;
  return json;
}

namespace {

// What the workers of one run share.
struct DaggerRun {
  DaggerRun(const std::string& dir, const DaggerOptions& options, const DaggerProgress& progress)
      : dir(dir), options(options), data(options.datasetOptions()), progress(progress) {}
  const std::string& dir;
  const DaggerOptions& options;
  const dataset::DatasetOptions data;
  EnvironmentOptions environment_options;
  std::shared_ptr<ObjectLibrary> library;
  std::vector<int> todo;  // scene indices
  const DaggerProgress& progress;
  std::mutex mutex;  // guards report and progress
  DaggerReport report;
};

// One worker: its environment and network, the scenes of run.todo that `jobs` gives it.
void work(DaggerRun& run, JobSource& jobs) {
  using Clock = std::chrono::steady_clock;
  dataset::SceneWriter writer(run.environment_options, run.library);
  NetworkDirectionAgent agent(std::make_shared<LoadedModel>(loadModel(run.options.model)),
                              DirectionHead::kEscape);
  while (const std::optional<std::size_t> slot = jobs.next()) {
    const int index = run.todo[*slot];
    const std::uint64_t seed = run.options.first_seed + static_cast<std::uint64_t>(index);
    const Clock::time_point rolled_out_from = Clock::now();
    const Rollout rollout = rollOut(writer, agent, seed, run.options);
    const Clock::time_point written_from = Clock::now();
    writer.writeScene(run.dir, index, seed, rollout.poses, run.data);
    const Clock::time_point end = Clock::now();
    const std::lock_guard<std::mutex> lock(run.mutex);
    DaggerReport& report = run.report;
    ++report.scenes_written;
    report.frames_written += static_cast<int>(rollout.poses.size());
    report.expert_moves += rollout.expert_moves;
    report.successes += rollout.success ? 1 : 0;
    report.rollout_seconds += std::chrono::duration<double>(written_from - rolled_out_from).count();
    report.write_seconds += std::chrono::duration<double>(end - written_from).count();
    if (run.progress) {
      run.progress(report.scenes_written, static_cast<int>(run.todo.size()), report.frames_written);
    }
  }
  const std::lock_guard<std::mutex> lock(run.mutex);
  run.report.oracle_seconds += writer.oracleSeconds();
}

}  // namespace

DaggerReport writeDaggerDataset(const std::string& dir, const DaggerOptions& options,
                                const DaggerProgress& progress) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  DaggerRun run(dir, options, progress);
  run.environment_options = dataset::environmentOptionsFor(run.data);
  run.environment_options.max_steps = options.max_steps;
  run.environment_options.validate();
  loadModel(options.model);  // refuses a missing or corrupt model before any folder is made
  run.library = std::make_shared<ObjectLibrary>(makeCatalog(run.environment_options.catalog),
                                                run.environment_options.lod_triangle_budget);
  const nlohmann::json manifest = manifestFor(options, run.library->catalog());
  dataset::requireResumable(dir, manifest.at("options"));
  fs::create_directories(fs::path(dir) / dataset::kSplitFolder);
  dataset::writeJsonAtomically((fs::path(dir) / dataset::kManifestFile).string(), manifest);

  run.todo = scenesToDo(dir, options.scenes, run.report);
  runWorkers(options.threads, run.todo.size(), [&run](JobSource& jobs) { work(run, jobs); });
  run.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run.report;
}

}  // namespace learning
}  // namespace occlusion_env
