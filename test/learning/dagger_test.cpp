// DAgger data (learning/dagger.hpp): a tiny round from an untrained network on two scenes at
// 64 px: the frames are the agent's own states, the labels the oracle's, the trainer reads it
// beside a base dataset, a re-run resumes, and validation and test seeds are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/temporary_dir.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/dataset/bop_dataset.hpp"
#include "occlusion_env/dataset/generator.hpp"
#include "occlusion_env/dataset/scene_writer.hpp"
#include "occlusion_env/learning/dagger.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/training.hpp"

namespace occlusion_env {
namespace learning {
namespace {

namespace fs = std::filesystem;

// An untrained 32 px network saved as a model file in `dir`.
std::string untrainedModel(const fs::path& dir) {
  torch::manual_seed(7);
  NetworkConfig config;
  config.input_size = 32;
  MultiTaskUNet network(config);
  fs::create_directories(dir);
  const std::string path = (dir / "untrained.pt").string();
  saveModel(network, path, {{"note", "untrained, for the DAgger test"}});
  return path;
}

DaggerOptions tinyDagger(const std::string& model) {
  DaggerOptions options;
  options.model = model;
  options.scenes = 2;
  options.first_seed = 500;
  options.max_steps = 4;
  options.threads = 2;
  options.data.size = 64;
  return options;
}

// Scene `index` of `data`, its frames by image id.
std::vector<const dataset::Frame*> sceneFrames(const dataset::BopDataset& data, int index) {
  std::vector<const dataset::Frame*> frames;
  for (const dataset::Frame& frame : data.frames()) {
    if (frame.scene_index == index) frames.push_back(&frame);
  }
  std::sort(frames.begin(), frames.end(), [](const dataset::Frame* a, const dataset::Frame* b) {
    return a->labels.image_id < b->labels.image_id;
  });
  return frames;
}

TEST(DaggerTest, WritesTheAgentsStatesWithTheOraclesLabelsAndResumes) {
  const fs::path model_dir = temporaryDir("occlusion_env_dagger_model");
  const DaggerOptions options = tinyDagger(untrainedModel(model_dir));
  const fs::path dir = temporaryDir("occlusion_env_dagger_data");
  const DaggerReport report = writeDaggerDataset(dir.string(), options);
  EXPECT_EQ(report.scenes_written, 2);
  EXPECT_EQ(report.scenes_skipped, 0);
  EXPECT_EQ(report.expert_moves, 0);  // beta 0: the agent's moves only
  const dataset::BopDataset data(dir.string());
  EXPECT_EQ(data.manifest().at("tool"), "occlusion_dagger");
  EXPECT_EQ(data.manifest().at("options").at("model_split"), "train");
  EXPECT_EQ(static_cast<int>(data.frames().size()), report.frames_written);

  // Scene 0 replayed: each frame is where the agent's previous move took the camera, and one
  // frame's labels are a fresh oracle's answer (anchored at the start view, as the labels are).
  dataset::SceneWriter replay(dataset::environmentOptionsFor(options.datasetOptions()), nullptr);
  Environment& environment = replay.environment();
  StepResult result = environment.reset(options.first_seed);
  NetworkDirectionAgent agent(std::make_shared<LoadedModel>(loadModel(options.model)),
                              DirectionHead::kEscape);
  const std::vector<const dataset::Frame*> frames = sceneFrames(data, 0);
  ASSERT_GE(frames.size(), 1u);
  ASSERT_LE(frames.size(), static_cast<std::size_t>(options.max_steps + 1));
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(frames[k]->labels.image_id, static_cast<int>(k));
    // Near, not equal: the network's sums may run in another order on another thread count.
    EXPECT_NEAR(frames[k]->labels.pose.azimuth_rad, result.info.pose.azimuth_rad, 1e-9);
    EXPECT_NEAR(frames[k]->labels.pose.elevation_rad, result.info.pose.elevation_rad, 1e-9);
    if (k + 1 < frames.size()) result = environment.step(agent.act(rigObservationOf(result)));
  }
  EXPECT_TRUE(frames.size() == static_cast<std::size_t>(options.max_steps + 1) ||
              result.terminated);
  const dataset::FrameLabels& stored = frames.back()->labels;
  OcclusionOracle oracle(environment);
  oracle.clear(environment.reset(options.first_seed).info.pose);
  const OracleAnswer answer = oracle.query(stored.pose);
  ASSERT_TRUE(stored.has_oracle);
  EXPECT_EQ(stored.oracle_steps, answer.steps);
  ASSERT_EQ(stored.escape.has_value(), !answer.path.empty());
  if (stored.escape) {
    EXPECT_NEAR(stored.escape->angle_rad, answer.firstDirectionRad(), 1e-12);
  }

  // The trainer reads it beside a base dataset of other seeds (which holds the validation).
  dataset::DatasetOptions base_options;
  base_options.scenes = 2;
  base_options.frames = 2;
  base_options.size = 64;
  base_options.validation_fraction = 0.5;
  const fs::path base_dir = temporaryDir("occlusion_env_dagger_base");
  dataset::generateDataset(base_dir.string(), base_options);
  const TrainingData both = loadTrainingData({base_dir.string(), dir.string()}, 32);
  EXPECT_EQ(both.train.inputs.size(0), 2 + report.frames_written);
  EXPECT_EQ(both.validation.inputs.size(0), 2);

  // Resumed: complete scenes are kept, a missing one is written again; other options refused.
  const DaggerReport again = writeDaggerDataset(dir.string(), options);
  EXPECT_EQ(again.scenes_written, 0);
  EXPECT_EQ(again.scenes_skipped, 2);
  fs::remove(fs::path(dataset::sceneFolder(dir.string(), 1)) / dataset::kLabelsFile);
  const DaggerReport third = writeDaggerDataset(dir.string(), options);
  EXPECT_EQ(third.scenes_written, 1);
  EXPECT_EQ(third.scenes_skipped, 1);
  EXPECT_EQ(static_cast<int>(dataset::BopDataset(dir.string()).frames().size()),
            report.frames_written);
  DaggerOptions mixed = options;
  mixed.beta = 0.5;
  EXPECT_THROW(writeDaggerDataset(dir.string(), mixed), InvalidArgumentError);
  for (const fs::path& path : {model_dir, dir, base_dir}) fs::remove_all(path);
}

TEST(DaggerTest, RecordsTheAgentsMovesPastTheFirstClearView) {
  // With the oracle steering (beta 1) each roll-out reaches an unoccluded view; with
  // moves_past_clear 2 the agent's next two moves are recorded after it, and no more.
  const fs::path model_dir = temporaryDir("occlusion_env_dagger_past_model");
  DaggerOptions options = tinyDagger(untrainedModel(model_dir));
  options.beta = 1.0;
  options.max_steps = 30;
  options.moves_past_clear = 2;
  const fs::path dir = temporaryDir("occlusion_env_dagger_past_data");
  const DaggerReport report = writeDaggerDataset(dir.string(), options);
  EXPECT_EQ(report.scenes_written, 2);
  const dataset::BopDataset data(dir.string());
  EXPECT_EQ(data.manifest().at("options").at("dagger").at("moves_past_clear"), 2);
  for (int scene = 0; scene < 2; ++scene) {
    const std::vector<const dataset::Frame*> frames = sceneFrames(data, scene);
    std::size_t first_clear = 0;
    while (first_clear < frames.size() && frames[first_clear]->labels.occlusion_px > 0) {
      ++first_clear;
    }
    ASSERT_LT(first_clear, frames.size()) << "scene " << scene << " never clear";
    ASSERT_GE(first_clear, 1u);  // a scene starts occluded
    EXPECT_EQ(frames.size(), first_clear + 3) << "scene " << scene;
    for (std::size_t k = first_clear + 1; k < frames.size(); ++k) {
      // Each recorded view is one move of the camera from the one before.
      const SphericalPose& before = frames[k - 1]->labels.pose;
      const SphericalPose& after = frames[k]->labels.pose;
      EXPECT_GT(std::abs(after.azimuth_rad - before.azimuth_rad) +
                    std::abs(after.elevation_rad - before.elevation_rad),
                1e-6)
          << "scene " << scene << ", frame " << k;
    }
  }
  // Another count of moves past clear is another dataset: refused on resume.
  DaggerOptions other = options;
  other.moves_past_clear = 0;
  EXPECT_THROW(writeDaggerDataset(dir.string(), other), InvalidArgumentError);
  for (const fs::path& path : {model_dir, dir}) fs::remove_all(path);
}

TEST(DaggerTest, RollsOutInARoomThroughADepthSensorModel) {
  // occlusion_dagger --world room --depth-sensor realsense_d435: the agent's states are those of
  // a room seen through the sensor model, and each frame records that setup.
  const fs::path model_dir = temporaryDir("occlusion_env_dagger_room_model");
  DaggerOptions options = tinyDagger(untrainedModel(model_dir));
  options.scenes = 1;
  options.max_steps = 2;
  options.threads = 1;
  options.data.world = "room";
  options.data.depth_sensor = "realsense_d435";
  const fs::path dir = temporaryDir("occlusion_env_dagger_room_data");
  const DaggerReport report = writeDaggerDataset(dir.string(), options);
  ASSERT_EQ(report.scenes_written, 1);
  const dataset::BopDataset data(dir.string());
  EXPECT_EQ(data.manifest().at("options").at("world"), "room");
  EXPECT_EQ(data.manifest().at("options").at("depth_sensor"), "realsense_d435");
  ASSERT_FALSE(data.frames().empty());
  for (const dataset::Frame& frame : data.frames()) {
    ASSERT_TRUE(frame.labels.setup.has_value());
    EXPECT_EQ(frame.labels.setup->world, "room");
    EXPECT_EQ(frame.labels.setup->depth_sensor, "realsense_d435");
  }
  for (const fs::path& path : {model_dir, dir}) fs::remove_all(path);
}

TEST(DaggerTest, RefusesValidationAndTestSeeds) {
  DaggerOptions options = tinyDagger("unused.pt");
  options.first_seed = 899999;  // the second scene would be a validation scene
  EXPECT_THROW(options.validate(), InvalidArgumentError);
  options.first_seed = 950000;
  EXPECT_THROW(options.validate(), InvalidArgumentError);
  options.first_seed = 1000000;
  EXPECT_THROW(options.validate(), InvalidArgumentError);
  options.first_seed = 899998;
  EXPECT_NO_THROW(options.validate());
  options.beta = 1.5;
  EXPECT_THROW(options.validate(), InvalidArgumentError);
}

}  // namespace
}  // namespace learning
}  // namespace occlusion_env
