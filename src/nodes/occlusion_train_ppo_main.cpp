// occlusion_train_ppo: trains a PPO policy (learning/ppo.hpp) on N in-process simulators or on
// simulators reached over ROS; resumable (re-run the same command).
//   occlusion_train_ppo --out runs/policy_un --reward union --envs 2
//   occlusion_train_ppo --out runs/policy_un --envs ros:/sim0,/sim1   (launch/simulators.launch)
#include <ros/ros.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/package_paths.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/eval/progress.hpp"
#include "occlusion_env/eval/subprocess.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/policy.hpp"
#include "occlusion_env/learning/ppo.hpp"
#include "occlusion_env/learning/training.hpp"
#include "occlusion_env/ros/environment_client.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

using occlusion_env::OptionSpec;
using occlusion_env::OptionTable;

/// The tool's own options; PPO's come from ppoOptionTable() and policyConfigTable().
struct CommandLine {
  occlusion_env::learning::PpoOptions ppo;
  std::string run_dir;
  std::string envs = "2";
  std::string source = "sweethome3d";
  std::vector<std::string> categories{"chair", "table"};
  int resolution = 256;
  int max_steps = 50;
  std::optional<std::string> world;         // unset: void, or random with randomize
  std::optional<std::string> depth_sensor;  // unset: ideal, or random with randomize
  bool randomize = false;
  std::vector<std::string> mean_length_policies;

  CommandLine() { ppo.backbone_path = occlusion_env::learning::defaultModelPath(); }
};

void addEnvironmentArguments(OptionTable<CommandLine>& table) {
  using C = CommandLine;
  table.add("out", &C::run_dir, OptionSpec("RUN_DIR: logs, checkpoints and policy.pt"))
      .add("envs", &C::envs,
           OptionSpec("N in-process simulators, each on its own thread, or ros:NS,NS,... the "
                      "simulators under these ROS namespaces (launch/simulators.launch), which "
                      "must be set up alike: reward_normalization as --reward; one whose "
                      "occlusion_sim/model_split is not train is refused"))
      .add("source", &C::source,
           OptionSpec("in-process object source").choices({"sweethome3d", "embedded", "folder"}))
      .add("categories", &C::categories, OptionSpec("in-process categories (\"any\" = all)"))
      .add("resolution", &C::resolution,
           OptionSpec("in-process image size (as the evaluation)").unit("px").range(64, 1024))
      .add("max_steps", &C::max_steps,
           OptionSpec("episode length before truncation").range(1, 100000));
  addSceneRandomizationOptions(table, &C::world, &C::depth_sensor, &C::randomize, "in-process: ");
}

void addRecipeArguments(OptionTable<CommandLine>& table) {
  table
      .addChoice(
          "actor_init",
          [](const CommandLine& c) { return c.ppo.actor_from_escape ? "escape" : "random"; },
          [](CommandLine& c, const std::string& init) {
            c.ppo.actor_from_escape = init == "escape";
          },
          OptionSpec("the actor's start: the network's escape head, or random weights")
              .choices({"escape", "random"}))
      .add("mean_length", &CommandLine::mean_length_policies,
           OptionSpec("instead: print the mean length of each policy's mean action (and of its "
                      "backbone's escape head) at the start views of 30 validation scenes and "
                      "exit (a free-length mean that grows outruns its noise)"));
}

const OptionTable<CommandLine>& argumentTable() {
  static const OptionTable<CommandLine> table = [] {
    OptionTable<CommandLine> made;
    addEnvironmentArguments(made);
    addRecipeArguments(made);
    return made;
  }();
  return table;
}

/// The rules between the flags, and --envs's form.
void checkCommandLine(const CommandLine& cl) {
  using namespace occlusion_env;
  if (cl.run_dir.empty() && cl.mean_length_policies.empty()) {
    throw CLI::ValidationError("--out is required");
  }
  const bool over_ros = cl.envs.rfind("ros:", 0) == 0;
  if (over_ros && (cl.world || cl.depth_sensor || cl.randomize)) {
    throw CLI::ValidationError(
        "--world, --depth-sensor and --randomize are for in-process simulators: set the "
        "simulators' world, depth_sensor and randomize_camera parameters instead");
  }
  try {
    if (over_ros) {
      tools::splitList("--envs", cl.envs.substr(4));
    } else {
      tools::parseInteger("--envs", cl.envs, 1, 64);
    }
  } catch (const tools::ArgumentError& error) {
    throw CLI::ValidationError(error.what());
  }
}

// The mean length of each policy's mean action, and of its backbone's escape head, at the start
// views of validation scenes 900100..900129 (Sweet Home 3D chairs and tables, train split).
int printMeanLengths(const std::vector<std::string>& paths) {
  using namespace occlusion_env;
  SceneSet scenes;
  scenes.source = "sweethome3d";
  scenes.categories = {"chair", "table"};
  scenes.model_split = "train";
  Environment environment(environmentOptionsFor(scenes));
  for (const std::string& path : paths) {
    // At a start view (no move yet, elevation 0) the rig inputs are zero, so each agent's action
    // is its network's raw output: the policy's mean, the backbone's escape head.
    auto policy = std::make_shared<learning::LoadedPolicy>(learning::loadPolicy(path));
    auto backbone = std::make_shared<learning::LoadedModel>();
    backbone->network = policy->network->backbone();
    learning::PolicyAgent policy_agent(policy);
    learning::NetworkDirectionAgent escape_agent(backbone, learning::DirectionHead::kEscape);
    double policy_sum = 0.0, escape_sum = 0.0;
    constexpr int kScenes = 30;
    for (int k = 0; k < kScenes; ++k) {
      const StepResult start = environment.reset(kFirstValidationSeed + 100 + k);
      policy_agent.reset(0);
      const Action mean = policy_agent.act(rigObservationOf(start));
      const Action escape = escape_agent.act(rigObservationOf(start));
      policy_sum += std::hypot(mean.d_azimuth_rad, mean.d_elevation_rad);
      escape_sum += std::hypot(escape.d_azimuth_rad, escape.d_elevation_rad);
    }
    std::cout << path << ": mean action length " << std::fixed << std::setprecision(2)
              << policy_sum / kScenes << " (its backbone's escape head: " << escape_sum / kScenes
              << ") over " << kScenes << " validation start views\n";
  }
  return 0;
}

/// The environments to train on: how many, how each is made, and in words.
struct Environments {
  int count = 0;
  occlusion_env::VectorEnvironment::Factory factory;
  std::string where;
};

/// The simulators under the ROS namespaces of `--envs ros:NS,NS,...`.
Environments rosEnvironments(const std::string& envs, int argc, char** argv) {
  using namespace occlusion_env;
  const std::vector<std::string> namespaces = tools::splitList("--envs", envs.substr(4));
  // Ctrl-C ends the process at once (the run resumes from its last checkpoint).
  ros::init(argc, argv, "occlusion_train_ppo",
            ros::init_options::AnonymousName | ros::init_options::NoSigintHandler);
  Environments environments;
  environments.count = static_cast<int>(namespaces.size());
  environments.factory = [namespaces](int i) {
    // Held out means held out: a simulator that may draw test-split models is refused.
    if (!requireTrainSplit(namespaces[i])) {
      std::cerr << "occlusion_train_ppo: WARNING: " << namespaces[i]
                << "/occlusion_sim/model_split is not set: cannot check that it draws only "
                   "train-split models\n";
    }
    auto client = std::make_unique<EnvironmentClient>(
        ros::NodeHandle(ros::NodeHandle(namespaces[i]), "occlusion"));
    client->connect();
    return std::unique_ptr<EnvironmentInterface>(std::move(client));
  };
  environments.where = "simulators under " + envs.substr(4);
  return environments;
}

/// `--envs N` in-process simulators on training scenes of the train split.
Environments inProcessEnvironments(const CommandLine& cl) {
  using namespace occlusion_env;
  Environments environments;
  environments.count = static_cast<int>(tools::parseInteger("--envs", cl.envs, 1, 64));
  SceneSet training;
  training.name = "ppo_training";
  training.source = cl.source;
  training.categories = cl.categories;
  if (training.categories == std::vector<std::string>{"any"}) training.categories.clear();
  training.model_split = "train";  // test-split models are never trained on
  EnvironmentOptions options = environmentOptionsFor(training);
  options.width = options.height = cl.resolution;
  options.max_steps = cl.max_steps;
  options.reward.normalization = parseRewardNormalization(cl.ppo.reward);
  applySceneRandomization(options, cl.world, cl.depth_sensor, cl.randomize);
  options.validate();
  auto library =
      std::make_shared<ObjectLibrary>(makeCatalog(options.catalog), options.lod_triangle_budget);
  environments.factory = [options, library](int) {
    return std::unique_ptr<EnvironmentInterface>(std::make_unique<Environment>(options, library));
  };
  environments.where = std::to_string(environments.count) + " in-process simulators (" + cl.source +
                       ", " + std::to_string(cl.resolution) + " px, train split, world " +
                       options.world.world + ", depth sensor " + options.sensor.depth_sensor +
                       (cl.randomize ? ", camera drawn per scene)" : ")");
  return environments;
}

int train(const CommandLine& cl, int argc, char** argv) {
  using namespace occlusion_env;
  if (learning::referenceBlasLoaded()) {
    std::cerr << "occlusion_train_ppo: WARNING: libtorch runs on the reference BLAS ("
              << learning::loadedBlasLibrary() << "): install libopenblas0-openmp.\n";
  }
  const Environments environments = cl.envs.rfind("ros:", 0) == 0
                                        ? rosEnvironments(cl.envs, argc, argv)
                                        : inProcessEnvironments(cl);
  std::cerr << "occlusion_train_ppo: " << cl.ppo.total_steps << " steps on " << environments.where
            << ", reward " << cl.ppo.reward << ", backbone " << cl.ppo.backbone_path << " -> "
            << cl.run_dir << "\n";
  eval::ProgressBar bar(std::cerr, static_cast<int>(cl.ppo.total_steps), "ppo");
  learning::PpoCallbacks callbacks;
  callbacks.on_start = [&bar](std::int64_t resumed_steps) {
    bar.resumeFrom(static_cast<int>(resumed_steps));  // a resumed run's ETA from its own rate
  };
  callbacks.on_update = [&](const learning::PpoUpdate& u) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(0) << u.steps_per_second << " steps/s, "
         << std::setprecision(1) << "steps/episode " << u.mean_episode_steps << ", success "
         << std::setprecision(0) << 100.0 * u.success_rate << " %";
    bar.update(static_cast<int>(std::min<std::int64_t>(u.env_steps, cl.ppo.total_steps)),
               text.str());
  };
  learning::trainPpo(cl.ppo, environments.count, environments.factory, ResetOptions{}, cl.run_dir,
                     callbacks);
  bar.finish();
  const std::string script = packageShareDirectory() + "/scripts/plot_ppo.py";
  if (eval::runProgram({"/usr/bin/python3", script, cl.run_dir}, "", "") != 0) {
    std::cerr << "occlusion_train_ppo: plotting the curves failed (python3-matplotlib?)\n";
  }
  std::cout << "occlusion_train_ppo: done; the policy is " << cl.run_dir << "/policy.pt\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  CommandLine cl;
  CLI::App app(
      "Trains a PPO policy (actor and critic on the pretrained multi-task network's encoder) on "
      "training\nscenes (seeds drawn below 900,000: validation scenes are 900,000-999,999 and "
      "test scenes from\n1,000,000; models of the train split). Every update goes to "
      "RUN_DIR/updates.csv, every episode\nto RUN_DIR/training_episodes.csv; checkpoints every few "
      "updates "
      "(re-run the same command to resume);\nRUN_DIR/policy.pt (+ .json) is the final policy "
      "(agent `policy`, ~model_path).\nDefaults: ours; --paper sets the paper's Table 2 recipe.",
      "occlusion_train_ppo");
  tools::addOptionFlags(app, argumentTable(), cl);
  tools::addOptionFlags(app, learning::policyConfigTable(), cl.ppo.policy);
  app.add_flag_callback(
         "--paper", [&cl] { learning::applyPaperRecipe(cl.ppo); },
         "the paper's Table 2 recipe: actor random, no rig inputs, lambda 1, minibatch 200, "
         "target-kl 0, max-grad-norm 0 (other flags refine it)")
      ->trigger_on_parse();
  tools::addOptionFlags(app, learning::ppoOptionTable(), cl.ppo);
  app.callback([&cl] { checkCommandLine(cl); });
  return tools::parseAndRun(app, argc, argv, [&] {
    if (!cl.mean_length_policies.empty()) return printMeanLengths(cl.mean_length_policies);
    return train(cl, argc, argv);
  });
}
