// PPO on simulators reached over ROS (test/ros/ppo_training.test): the vectorised environment of
// EnvironmentClients trains a few updates, logs and checkpoints, and both simulators did work.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/policy.hpp"
#include "occlusion_env/learning/ppo.hpp"
#include "occlusion_env/ros/environment_client.hpp"

namespace occlusion_env {
namespace {

namespace fs = std::filesystem;

TEST(PpoOverRos, TrainsAFewUpdatesOnTwoSimulators) {
  std::string namespaces_text;
  ASSERT_TRUE(ros::NodeHandle("~").getParam("namespaces", namespaces_text));
  std::vector<std::string> namespaces;
  std::stringstream list(namespaces_text);
  for (std::string item; std::getline(list, item, ',');) namespaces.push_back(item);
  ASSERT_EQ(namespaces.size(), 2u);

  const fs::path dir =
      fs::temp_directory_path() / ("occlusion_env_ppo_ros_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  learning::NetworkConfig config;
  config.input_size = 32;
  learning::MultiTaskUNet network(config);
  const std::string backbone = (dir / "backbone.pt").string();
  learning::saveModel(network, backbone, {});

  learning::PpoOptions options;
  options.backbone_path = backbone;
  options.total_steps = 48;
  options.steps_per_update = 16;
  options.epochs = 2;
  options.minibatch_size = 8;
  options.threads = 1;
  std::vector<std::string> described(namespaces.size());
  const auto factory = [&](int i) {
    EXPECT_TRUE(requireTrainSplit(namespaces[i])) << "the launch file sets model_split";
    EnvironmentClientOptions client_options;
    client_options.service_timeout_s = 30.0;
    auto client = std::make_unique<EnvironmentClient>(
        ros::NodeHandle(ros::NodeHandle(namespaces[i]), "occlusion"), client_options);
    client->connect();
    described[i] = client->describe();
    return std::unique_ptr<EnvironmentInterface>(std::move(client));
  };
  int updates = 0;
  learning::PpoCallbacks callbacks;
  callbacks.on_update = [&](const learning::PpoUpdate& u) {
    ++updates;
    EXPECT_EQ(u.env_steps, 16 * u.update);
  };
  const fs::path run = dir / "run";
  ResetOptions reset;
  learning::trainPpo(options, 2, factory, reset, run.string(), callbacks);
  EXPECT_EQ(updates, 3);
  // simulators.launch sets them up as a trainer needs: no gradient service (PPO must not use it).
  for (const auto& ns : namespaces) {
    EXPECT_FALSE(ros::service::exists(ns + "/occlusion/get_occlusion_gradient", false)) << ns;
    std::string reward;
    EXPECT_TRUE(ros::param::get(ns + "/occlusion_sim/reward_normalization", reward));
    EXPECT_EQ(reward, "intersection");  // as the test's launch file asks
  }
  EXPECT_NE(described[0].find("/sim0/occlusion/reset"), std::string::npos) << described[0];
  EXPECT_NE(described[1].find("/sim1/occlusion/reset"), std::string::npos) << described[1];
  // Every update was logged, the run checkpointed and its policy loads.
  std::ifstream log(run / "updates.csv");
  int lines = 0;
  for (std::string line; std::getline(log, line);) ++lines;
  EXPECT_EQ(lines, 4);
  EXPECT_TRUE(fs::exists(run / "checkpoint.pt"));
  EXPECT_NO_THROW(learning::loadPolicy((run / "policy.pt").string()));
  fs::remove_all(dir);
}

TEST(PpoOverRos, ASimulatorThatMayDrawTestModelsIsRefused) {
  ros::param::set("/all_models/occlusion_sim/model_split", "all");
  EXPECT_THROW(requireTrainSplit("/all_models"), InvalidArgumentError);
  EXPECT_FALSE(requireTrainSplit("/no_simulator_here"));
}

}  // namespace
}  // namespace occlusion_env

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "ppo_training_test");
  ros::NodeHandle node;
  return RUN_ALL_TESTS();
}
