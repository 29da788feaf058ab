// The evaluation report's pieces: links into the output folder, the Table 3 layout and PPO
// section read from the manifests of a source tree, what a scene set's summary says, and the
// bridge's stopping rule as occlusion_eval's options.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/temporary_dir.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/learning/multitask_unet.hpp"
#include "occlusion_env/report/eval_options.hpp"
#include "occlusion_env/report/evaluation_report.hpp"
#include "occlusion_env/report/model_report.hpp"
#include "occlusion_env/report/scene_set_report.hpp"

namespace occlusion_env {
namespace report {
namespace {

namespace fs = std::filesystem;

TEST(Report, LinksToOutputFilesGetThePrefix) {
  const std::string markdown =
      "![plot](sweep.png) [csv](set_episodes.csv) [page](strip.md) [doc](doc/images/x.png) "
      "[web](http://example.org/a.png) [text](notes.txt)";
  EXPECT_EQ(withLinkPrefix(markdown, "doc/evaluation/"),
            "![plot](doc/evaluation/sweep.png) [csv](doc/evaluation/set_episodes.csv) "
            "[page](doc/evaluation/strip.md) [doc](doc/images/x.png) "
            "[web](http://example.org/a.png) [text](notes.txt)");
}

class ManifestTree : public TemporaryDirTest {
 protected:
  void SetUp() override {
    TemporaryDirTest::SetUp();
    fs::create_directories(dir_ / "doc" / "training");
    fs::create_directories(dir_ / "models");
    options_.source_dir = dir_.string();
  }

  static nlohmann::json network(const std::string& variant, int size, double iou) {
    return {{"kind", "multitask_unet"},
            {"file", variant + ".pt"},
            {"epoch", 7},
            {"network", {{"variant", variant}, {"input_size", size}}},
            {"training", {{"epochs", 10}, {"direction_loss", "mse"}}},
            {"run", {{"minutes", 42.0}}},
            {"validation", {{"val_iou", iou}, {"val_pixel_accuracy", 0.99}}}};
  }
  void write(const fs::path& path, const nlohmann::json& json) { std::ofstream(path) << json; }

  EvalOptions options_;
};

TEST_F(ManifestTree, NetworkTableListsTrainedVariantsInPaperOrderThenPaperThenShipped) {
  write(dir_ / "doc" / "training" / "a_sar.json", network("sar_unet", 64, 0.5));
  write(dir_ / "doc" / "training" / "b_unet.json", network("unet", 64, 0.4));
  write(dir_ / "doc" / "training" / "broken.json", "not a manifest");
  write(dir_ / "models" / "shipped64.json", network("r_unet", 64, 0.6));
  const std::string table = networkSection(options_);
  const auto unet = table.find("[b_unet](doc/training/b_unet.png) | unet | 64 | 7 / 10 | 42 min");
  const auto sar = table.find("[a_sar](doc/training/a_sar.png) | sar_unet | 64");
  const auto paper = table.find("| paper: Base UNet |");
  const auto shipped = table.find("| `r_unet` | r_unet | 64 |");
  ASSERT_NE(unet, std::string::npos) << table;
  ASSERT_NE(sar, std::string::npos) << table;
  ASSERT_NE(shipped, std::string::npos) << table;
  ASSERT_NE(paper, std::string::npos) << table;
  EXPECT_LT(unet, sar);
  EXPECT_LT(sar, paper);
  EXPECT_LT(paper, shipped);
  EXPECT_NE(table.find("| 40.00 % |"), std::string::npos) << table;  // b_unet's IoU
}

// The shipped networks' rows say where each was validated, what input it reads, and "-" for a
// head its data had no labels for, not a loss of 0.
TEST_F(ManifestTree, ShippedNetworksSayWhereTheyWereValidated) {
  nlohmann::json trained = network("unet", 128, 0.45);
  trained["file"] = "estimate.pt";
  trained["dataset"] = "data/rooms";
  trained["extra_datasets"] = {"data/more_rooms", "data/void"};
  trained["validation_frames"] = 1811;
  trained["network"]["depth_gaps"] = "filled";
  trained["network"]["view_field_of_view"] = 1.0472;
  trained["validation"]["val_escape_mse"] = 0.0;
  trained["validation"]["val_escape_angle_deg"] = 0.0;
  trained["validation"]["val_gradient_mse"] = 0.29;
  trained["validation"]["val_gradient_angle_deg"] = 24.94;
  write(dir_ / "models" / "estimate.json", trained);
  nlohmann::json derived = trained;
  derived["file"] = "estimate_copy.pt";
  derived["derived_from"] = {{"file", "estimate.pt"}, {"weights", "unchanged"}};
  write(dir_ / "models" / "estimate_copy.json", derived);
  write(dir_ / "models" / "r_unet.json", network("r_unet", 64, 0.6));
  const std::string table = networkSection(options_);
  EXPECT_NE(table.find("| `r_unet` | r_unet | 64 | - | 7 / 10 |"), std::string::npos) << table;
  EXPECT_NE(table.find("| `estimate` | unet | 128 | depth_gaps filled, view_field_of_view 60 deg "
                       "| 7 / 10 | 1811 frames of `data/rooms` and 2 more sets | 45.00 % | "
                       "24.9 deg | - |"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| `estimate_copy` | unet | 128 | depth_gaps filled, view_field_of_view "
                       "60 deg | 7 / 10 | those of `estimate` (the same weights) |"),
            std::string::npos)
      << table;
}

// The table names only what differs from NetworkConfig's defaults: a manifest stating every
// default field shows no input options.
TEST_F(ManifestTree, ShippedNetworksOmitTheNetworksDefaults) {
  nlohmann::json manifest = network("unet", 64, 0.5);
  manifest["network"] = learning::NetworkConfig().toJson();
  write(dir_ / "models" / "defaults.json", manifest);
  const std::string table = networkSection(options_);
  EXPECT_NE(table.find("| `unet` | unet | 64 | - | 7 / 10 |"), std::string::npos) << table;
}

TEST_F(ManifestTree, PolicySectionOnlyWithShippedPolicies) {
  EXPECT_EQ(policySection(options_), "");
  write(dir_ / "models" / "policy_x.json",
        {{"kind", "ppo_policy"},
         {"file", "policy_x.pt"},
         {"env_steps", 1000},
         {"trained_with", {{"reward", "union"}, {"policy", {{"rig_inputs", true}}}}},
         {"training_end", {{"mean_steps", 12.5}, {"success_rate", 0.8}}},
         {"validation", {{"mean_steps", 10.5}, {"std_steps", 3.0}, {"success_rate", 0.9}}}});
  const std::string section = policySection(options_);
  EXPECT_NE(section.find("training_episodes.csv"), std::string::npos);
  EXPECT_NE(section.find("| `policy_x` | union | scratch | yes | 1000 | 12.5 | 80 % | 10.5 +/- 3.0 "
                         "| 90 % |"),
            std::string::npos)
      << section;
  write(dir_ / "models" / "policy_y.json",
        {{"kind", "ppo_policy"},
         {"file", "policy_y.pt"},
         {"env_steps", 1000},
         {"trained_with",
          {{"reward", "union"}, {"policy", {{"rig_inputs", true}, {"move_memory", 4}}}}},
         {"training_end", {{"mean_steps", 12.5}, {"success_rate", 0.8}}},
         {"validation", {{"mean_steps", 10.5}, {"std_steps", 3.0}, {"success_rate", 0.9}}}});
  EXPECT_NE(
      policySection(options_).find("| `policy_y` | union | scratch | yes, the last 4 moves |"),
      std::string::npos)
      << policySection(options_);
}

// A summary of episodes that the camera bridge ended says its successes are the bridge's verdicts
// and where the truth is; one of episodes the simulator ended does not.
TEST_F(ManifestTree, SummaryThroughTheBridgeSaysASuccessIsTheBridgesVerdict) {
  options_.out = dir_.string();
  options_.plots = false;
  std::vector<EpisodeRecord> records(2);
  for (std::size_t i = 0; i < records.size(); ++i) {
    records[i].agent = "predicted_escape";
    records[i].scene_set = "set";
    records[i].scene_seed = 900000 + i;
    records[i].max_steps = 50;
    records[i].steps = 9;
    records[i].end = EpisodeEnd::kSuccess;
    records[i].final_occlusion_px = 0;
  }
  const std::string direct = writeSceneSetSummary(options_, records, "set", "set_episodes.csv");
  EXPECT_EQ(direct.find("bridge's verdict"), std::string::npos) << direct;
  for (EpisodeRecord& record : records) record.occlusion_source = OcclusionSource::kEstimated;
  const std::string bridged =
      writeSceneSetSummary(options_, records, "set_bridge", "set_bridge_episodes.csv");
  EXPECT_NE(bridged.find("a success is the bridge's verdict on its estimate, not the simulator's "
                         "truth; how often the view was truly clear: `set_bridge.md`"),
            std::string::npos)
      << bridged;
  std::ifstream file(dir_ / "set_bridge_summary.md");
  const std::string written((std::istreambuf_iterator<char>(file)),
                            std::istreambuf_iterator<char>());
  EXPECT_EQ(written, bridged);
}

// Through the bridge, the truth per episode: the bridge's verdict beside the simulator's L where
// the episode ended, so that a stop the truth contradicts is found by scene.
TEST_F(ManifestTree, TheBridgesTruthIsWrittenPerEpisode) {
  std::vector<EpisodeRecord> records(3);
  const std::vector<std::int64_t> truth = {0, 3, 120};
  for (std::size_t i = 0; i < records.size(); ++i) {
    records[i].agent = "predicted_escape";
    records[i].scene_seed = 900000 + i;
    records[i].max_steps = 50;
    records[i].steps = 9;
    records[i].end = EpisodeEnd::kSuccess;
    records[i].path = {SphericalPose{0.0, 0.0}, SphericalPose{0.25, -0.5}};
  }
  records[2].end = EpisodeEnd::kUnusableView;
  records[2].steps = 0;
  records[2].path.clear();
  const std::string path = (dir_ / "set_bridge_truth.csv").string();
  writeBridgeTruthCsv(records, truth, 0, path);
  std::ifstream file(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0],
            "agent,scene_seed,start_azimuth_rad,bridge_steps,bridge_says_clear,truly_clear,"
            "truth_occlusion_px,azimuth_rad,elevation_rad,end");
  EXPECT_EQ(lines[1], "predicted_escape,900000,0,9,1,1,0,0.25,-0.5,success");
  EXPECT_EQ(lines[2], "predicted_escape,900001,0,9,1,0,3,0.25,-0.5,success") << "a wrong stop";
  EXPECT_EQ(lines[3], "predicted_escape,900002,0,0,0,0,120,,,unusable_view");
  EXPECT_THROW(writeBridgeTruthCsv(records, {0, 3}, 0, path), InvalidArgumentError);
}

TEST(EvalOptions, TheBridgesStoppingRuleIsTheBridgesDefaultsUnlessGiven) {
  const CameraEnvironmentOptions bridge;
  EvalOptions options;
  EXPECT_EQ(options.bridge.occlusion_threshold_px, bridge.occlusion_threshold_px);
  EXPECT_EQ(options.bridge.confirm_views, bridge.confirm_views);
  evalOptionTable().set(options, "bridge_threshold", 16);
  evalOptionTable().set(options, "bridge_confirm_views", 3);
  EXPECT_EQ(options.bridge.occlusion_threshold_px, 16);
  EXPECT_EQ(options.bridge.confirm_views, 3);
  EXPECT_ANY_THROW(evalOptionTable().set(options, "bridge_confirm_views", 0));
  EXPECT_ANY_THROW(evalOptionTable().set(options, "bridge_threshold", -1));
  EXPECT_EQ(options.bridge.second_occlusion_probability, bridge.second_occlusion_probability);
  evalOptionTable().set(options, "bridge_second_probability", 0.3);
  EXPECT_EQ(options.bridge.second_occlusion_probability, 0.3);
  EXPECT_ANY_THROW(evalOptionTable().set(options, "bridge_second_probability", 1.0));
  // A second opinion joins the bridge's estimate: without --through-bridge it is refused.
  options.scenes = "config/scenes/validation_sweethome3d.yaml";
  evalOptionTable().set(options, "bridge_second_model", std::string("second.pt"));
  EXPECT_THROW(options.resolve(), InvalidArgumentError);
  options.through_bridge = "first.pt";
  EXPECT_NO_THROW(options.resolve());
}

// --field-of-view-range and the other ranges: refused without --randomize, drawn with it.
TEST(EvalOptions, TheCamerasRangesReachTheEnvironmentOnlyWhenDrawn) {
  EvalOptions options;
  options.scenes = "config/scenes/validation_sweethome3d.yaml";
  evalOptionTable().set(options, "field_of_view_range", std::vector<double>{1.5, 1.5});
  EXPECT_THROW(options.resolve(), InvalidArgumentError);
  options.randomize = true;
  options.resolve();
  EnvironmentOptions environment;
  options.applySceneRandomization(environment);
  EXPECT_TRUE(environment.camera_randomization.enabled);
  EXPECT_EQ(environment.camera_randomization.field_of_view_range_rad,
            (std::vector<double>{1.5, 1.5}));
  EXPECT_EQ(environment.world.world, "random");  // and the world and sensor drawn, unset
  evalOptionTable().set(options, "radius_range", std::vector<double>{1.5, 0.5});
  EXPECT_THROW(options.resolve(), InvalidArgumentError);
}

}  // namespace
}  // namespace report
}  // namespace occlusion_env
