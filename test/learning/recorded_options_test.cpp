// The options that runs record (model manifests' "training" and "dataset_options", policy
// manifests' "trained_with") are written from the option tables with the keys and structure that
// the shipped manifests hold: each shipped manifest reads back into the structs and is written
// again unchanged, so resumes and --check keep accepting them.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/dataset/generator.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/policy.hpp"
#include "occlusion_env/learning/ppo.hpp"
#include "occlusion_env/learning/training.hpp"

namespace occlusion_env {
namespace learning {
namespace {

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return nlohmann::json::parse(in);
}

// A manifest's "training" read back through the tables.
TrainingOptions trainingOptionsOf(nlohmann::json recorded) {
  TrainingOptions options;
  options.network = NetworkConfig::fromJson(recorded.at("network"));
  recorded.erase("network");
  trainingOptionTable().applyJson(recorded, options);
  return options;
}

TEST(RecordedOptionsTest, ModelManifestsReadBackAndAreWrittenAlike) {
  // A warm restart with the BCE term (every key a run records today)...
  const nlohmann::json warm =
      readJson("doc/training/r_unet_bce1_5000scenes_warm10_64px.json").at("training");
  ASSERT_TRUE(warm.contains("init_from"));
  nlohmann::json warm_expected = warm;
  warm_expected["network"]["depth_gaps"] = "far";  // recorded before the option
  EXPECT_EQ(trainingOptionsOf(warm).toJson(), warm_expected);
  // ...and the shipped model, recorded before bce_weight existed (the paper's loss, 0).
  const nlohmann::json shipped = readJson("models/multitask_unet64.json");
  nlohmann::json expected = shipped.at("training");
  expected["bce_weight"] = 0.0;
  expected["network"]["depth_gaps"] = "far";
  EXPECT_EQ(trainingOptionsOf(shipped.at("training")).toJson(), expected);
  nlohmann::json network = shipped.at("network");
  network["depth_gaps"] = "far";
  EXPECT_EQ(NetworkConfig::fromJson(shipped.at("network")).toJson(), network);
  EXPECT_NO_THROW(loadModel(defaultModelPath()));
}

TEST(RecordedOptionsTest, DatasetOptionsReadBackAndAreWrittenAlike) {
  nlohmann::json recorded = readJson("models/multitask_unet64.json").at("dataset_options");
  const nlohmann::json expected = recorded;
  recorded.erase("model_split");  // always train; the step size is the environment's
  recorded.erase("step_size_rad");
  dataset::DatasetOptions options;
  dataset::datasetOptionTable().applyJson(recorded, options);
  EXPECT_EQ(options.definingJson(), expected);
}

TEST(RecordedOptionsTest, PolicyManifestsReadBackAndAreWrittenAlike) {
  for (const std::string name : {"policy_un", "policy_in"}) {
    const nlohmann::json manifest = readJson("models/" + name + ".json");
    nlohmann::json recorded = manifest.at("trained_with");
    PpoOptions options;
    options.policy = PolicyConfig::fromJson(recorded.at("policy"));
    recorded.erase("policy");
    ppoOptionTable().applyJson(recorded, options);
    nlohmann::json expected = manifest.at("trained_with");
    expected["policy"]["unit_mean"] = false;  // recorded before the option: the free length
    expected["overlap"] = false;              // recorded before the option: no overlap
    EXPECT_EQ(options.toJson(), expected) << name;
    EXPECT_NO_THROW(options.validate()) << name;
    EXPECT_NO_THROW(loadPolicy("models/" + name + ".pt")) << name;
  }
}

TEST(RecordedOptionsTest, UnknownOrMissingFieldsAreRefused) {
  nlohmann::json network = NetworkConfig().toJson();
  network["depth"] = 3;
  EXPECT_THROW(NetworkConfig::fromJson(network), InvalidArgumentError);
  network = NetworkConfig().toJson();
  network.erase("levels");
  EXPECT_THROW(NetworkConfig::fromJson(network), InvalidArgumentError);
  EXPECT_THROW(PolicyConfig::fromJson({{"hidden", 0}, {"rig_inputs", true}}), InvalidArgumentError);
}

TEST(RecordedOptionsTest, ThePaperRecipeChangesOnlyItsOptions) {
  PpoOptions ours;
  ours.backbone_path = "backbone.pt";
  PpoOptions paper = ours;
  applyPaperRecipe(paper);
  EXPECT_NO_THROW(paper.validate());
  nlohmann::json difference = nlohmann::json::diff(ours.toJson(), paper.toJson());
  std::set<std::string> changed;
  for (const nlohmann::json& change : difference) changed.insert(change.at("path"));
  EXPECT_EQ(changed,
            (std::set<std::string>{"/actor_from_escape", "/gae_lambda", "/max_grad_norm",
                                   "/minibatch_size", "/policy/rig_inputs", "/target_kl"}));
}

}  // namespace
}  // namespace learning
}  // namespace occlusion_env
