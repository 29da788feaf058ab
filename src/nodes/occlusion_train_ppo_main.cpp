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
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_train_ppo --out RUN_DIR [options]
Trains a PPO policy (actor and critic on the pretrained multi-task network's encoder) on training
scenes (seeds drawn below 900,000: validation scenes are 900,000-999,999 and test scenes from
1,000,000; models of the train split). Every update goes to RUN_DIR/updates.csv,
every episode to RUN_DIR/training_episodes.csv; checkpoints every few updates (re-run the same command to
resume); RUN_DIR/policy.pt (+ .json) is the final policy (agent `policy`, ~model_path).

Environments:
  --envs N | ros:NS,NS,...  N in-process simulators, each on its own thread (default 2), or the
                         simulators under these ROS namespaces (launch/simulators.launch), which
                         must be set up alike: reward_normalization as --reward; one whose
                         occlusion_sim/model_split is not train is refused
  --source S             in-process object source: sweethome3d | embedded (default sweethome3d)
  --categories A,B       in-process categories (default chair,table; "any" = all)
  --resolution N         in-process image size [px] (default 256, as the evaluation)
  --reward R             union (Agent-UN) | intersection (Agent-IN) (default union)
  --max-steps N          episode length before truncation (default 50)

Policy and PPO (defaults: ours; --paper sets the paper's Table 2 recipe):
  --backbone MODEL       pretrained multi-task network (default: the shipped model)
  --actor-init I         escape (the network's escape head) | random (default escape)
  --no-rig               the heads see the image features only (no last move, no elevation)
  --unit-mean            scale the mean action to unit length (default: free length, as the
                         paper; doc/PPO.md compares them)
  --fine-tune            train the encoder too (--backbone-lr, default 1e-5)
  --steps N              environment steps in all (default 50000)
  --steps-per-update N   N_u (default 200)
  --epochs K             passes per update at most (default 80)
  --minibatch N          (default 50)
  --actor-lr X --critic-lr X   (default 3e-4, 1e-3)
  --gamma X --lambda X   discount and GAE lambda (default 0.99, 0.95)
  --clip X               surrogate clip epsilon (default 0.2)
  --std X --std-end X    action sigma at the start and the end, linear (default 0.6, 0.6)
  --entropy X            entropy bonus coefficient (default 0)
  --max-grad-norm X      (default 0.5; 0 = none)
  --target-kl X          stop an update's epochs above 1.5 * X (default 0.02; 0 = never)
  --no-advantage-norm    raw advantages
  --paper                actor random, no rig inputs, lambda 1, minibatch 200,
                         target-kl 0, max-grad-norm 0 (put it before flags that refine it)
  --seed S               (default 1)
  --threads N            libtorch threads (default: all cores)
  --checkpoint-every N   updates (default 10)
  --mean-length P,...    instead: print the mean length of each policy's mean action (and of
                         its backbone's escape head) at the start views of 30 validation scenes
                         and exit (a free-length mean that grows outruns its noise)
  --help                 this text
)";

struct CommandLine {
  occlusion_env::learning::PpoOptions ppo;
  std::vector<std::string> mean_length_policies;
  std::string run_dir;
  std::string envs = "2";
  std::string source = "sweethome3d";
  std::vector<std::string> categories{"chair", "table"};
  int resolution = 256;
  int max_steps = 50;
};

CommandLine parse(int argc, char** argv) {
  using occlusion_env::tools::ArgumentReader;
  CommandLine cl;
  auto& ppo = cl.ppo;
  ppo.backbone_path = occlusion_env::learning::defaultModelPath();
  ArgumentReader reader(argc, argv);
  while (reader.next()) {
    const std::string& flag = reader.flag();
    if (flag == "--help" || flag == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else if (flag == "--out") {
      cl.run_dir = reader.text();
    } else if (flag == "--envs") {
      cl.envs = reader.text();
    } else if (flag == "--source") {
      cl.source = reader.text();
    } else if (flag == "--categories") {
      cl.categories = reader.list();
      if (cl.categories == std::vector<std::string>{"any"}) cl.categories.clear();
    } else if (flag == "--resolution") {
      cl.resolution = static_cast<int>(reader.integer(64, 1024));
    } else if (flag == "--reward") {
      ppo.reward = reader.text();
    } else if (flag == "--max-steps") {
      cl.max_steps = static_cast<int>(reader.integer(1, 100000));
    } else if (flag == "--backbone") {
      ppo.backbone_path = reader.text();
    } else if (flag == "--actor-init") {
      const std::string init = reader.text();
      if (init != "escape" && init != "random") {
        throw occlusion_env::tools::ArgumentError("--actor-init: escape or random, got " + init);
      }
      ppo.actor_from_escape = init == "escape";
    } else if (flag == "--no-rig") {
      ppo.policy.rig_inputs = false;
    } else if (flag == "--unit-mean") {
      ppo.policy.unit_mean = true;
    } else if (flag == "--fine-tune") {
      ppo.fine_tune = true;
    } else if (flag == "--backbone-lr") {
      ppo.backbone_learning_rate = reader.number(1e-9, 1.0);
    } else if (flag == "--steps") {
      ppo.total_steps = reader.integer(1, 1000000000000LL);
    } else if (flag == "--steps-per-update") {
      ppo.steps_per_update = static_cast<int>(reader.integer(2, 1000000));
    } else if (flag == "--epochs") {
      ppo.epochs = static_cast<int>(reader.integer(1, 10000));
    } else if (flag == "--minibatch") {
      ppo.minibatch_size = static_cast<int>(reader.integer(2, 1000000));
    } else if (flag == "--actor-lr") {
      ppo.actor_learning_rate = reader.number(1e-9, 1.0);
    } else if (flag == "--critic-lr") {
      ppo.critic_learning_rate = reader.number(1e-9, 1.0);
    } else if (flag == "--gamma") {
      ppo.gamma = reader.number(1e-6, 1.0);
    } else if (flag == "--lambda") {
      ppo.gae_lambda = reader.number(0.0, 1.0);
    } else if (flag == "--clip") {
      ppo.clip_epsilon = reader.number(1e-6, 0.999);
    } else if (flag == "--std") {
      ppo.action_std = reader.number(1e-6, 100.0);
    } else if (flag == "--std-end") {
      ppo.action_std_end = reader.number(1e-6, 100.0);
    } else if (flag == "--entropy") {
      ppo.entropy_coefficient = reader.number(0.0, 100.0);
    } else if (flag == "--max-grad-norm") {
      ppo.max_grad_norm = reader.number(0.0, 1e6);
    } else if (flag == "--target-kl") {
      ppo.target_kl = reader.number(0.0, 100.0);
    } else if (flag == "--no-advantage-norm") {
      ppo.normalize_advantages = false;
    } else if (flag == "--paper") {
      ppo.actor_from_escape = false;
      ppo.policy.rig_inputs = false;
      ppo.policy.unit_mean = false;
      ppo.gae_lambda = 1.0;
      ppo.minibatch_size = 200;
      ppo.target_kl = 0.0;
      ppo.max_grad_norm = 0.0;
    } else if (flag == "--seed") {
      ppo.seed = reader.unsignedInteger();
    } else if (flag == "--threads") {
      ppo.threads = static_cast<int>(reader.integer(0, 256));
    } else if (flag == "--mean-length") {
      cl.mean_length_policies = reader.list();
    } else if (flag == "--checkpoint-every") {
      ppo.checkpoint_every = static_cast<int>(reader.integer(1, 1000000));
    } else {
      reader.unknown();
    }
  }
  if (cl.run_dir.empty() && cl.mean_length_policies.empty()) {
    throw occlusion_env::tools::ArgumentError("--out is required");
  }
  return cl;
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
      const Action mean = policy_agent.act(*start.observation, start.info);
      const Action escape = escape_agent.act(*start.observation, start.info);
      policy_sum += std::hypot(mean.d_azimuth_rad, mean.d_elevation_rad);
      escape_sum += std::hypot(escape.d_azimuth_rad, escape.d_elevation_rad);
    }
    std::cout << path << ": mean action length " << std::fixed << std::setprecision(2)
              << policy_sum / kScenes << " (its backbone's escape head: " << escape_sum / kScenes
              << ") over " << kScenes << " validation start views\n";
  }
  return 0;
}

// The environments PPO trains on: how many, how each is made (on its own thread), and where.
struct TrainingEnvironments {
  int count = 0;
  occlusion_env::VectorEnvironment::Factory factory;
  std::string where;
};

// The simulators under the ROS namespaces of `list` (NS,NS,...), each through an
// EnvironmentClient; initialises ROS.
TrainingEnvironments rosSimulators(const std::string& list, int argc, char** argv) {
  using namespace occlusion_env;
  const std::vector<std::string> namespaces = tools::splitList("--envs", list);
  // Ctrl-C ends the process at once (the run resumes from its last checkpoint).
  ros::init(argc, argv, "occlusion_train_ppo",
            ros::init_options::AnonymousName | ros::init_options::NoSigintHandler);
  TrainingEnvironments envs;
  envs.count = static_cast<int>(namespaces.size());
  envs.factory = [namespaces](int i) {
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
  envs.where = "simulators under " + list;
  return envs;
}

// --envs N in-process simulators on training scenes of the train split, sharing one library.
TrainingEnvironments inProcessSimulators(const CommandLine& cl) {
  using namespace occlusion_env;
  TrainingEnvironments envs;
  envs.count = static_cast<int>(tools::parseInteger("--envs", cl.envs, 1, 64));
  SceneSet training;
  training.name = "ppo_training";
  training.source = cl.source;
  training.categories = cl.categories;
  training.model_split = "train";  // test-split models are never trained on
  EnvironmentOptions options = environmentOptionsFor(training);
  options.width = options.height = cl.resolution;
  options.max_steps = cl.max_steps;
  options.reward.normalization = parseRewardNormalization(cl.ppo.reward);
  options.validate();
  auto library =
      std::make_shared<ObjectLibrary>(makeCatalog(options.catalog), options.lod_triangle_budget);
  envs.factory = [options, library](int) {
    return std::unique_ptr<EnvironmentInterface>(std::make_unique<Environment>(options, library));
  };
  envs.where = std::to_string(envs.count) + " in-process simulators (" + cl.source + ", " +
               std::to_string(cl.resolution) + " px, train split)";
  return envs;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  CommandLine cl;
  try {
    cl = parse(argc, argv);
  } catch (const tools::ArgumentError& error) {
    std::cerr << "occlusion_train_ppo: " << error.what() << "\n" << kUsage;
    return 2;
  }
  try {
    if (!cl.mean_length_policies.empty()) return printMeanLengths(cl.mean_length_policies);
    if (learning::referenceBlasLoaded()) {
      std::cerr << "occlusion_train_ppo: WARNING: libtorch runs on the reference BLAS ("
                << learning::loadedBlasLibrary() << "): install libopenblas0-openmp.\n";
    }
    const TrainingEnvironments envs = cl.envs.rfind("ros:", 0) == 0
                                          ? rosSimulators(cl.envs.substr(4), argc, argv)
                                          : inProcessSimulators(cl);
    std::cerr << "occlusion_train_ppo: " << cl.ppo.total_steps << " steps on " << envs.where
              << ", reward " << cl.ppo.reward << ", backbone " << cl.ppo.backbone_path << " -> "
              << cl.run_dir << "\n";
    eval::ProgressBar bar(std::cerr, static_cast<int>(cl.ppo.total_steps), "ppo");
    learning::PpoCallbacks callbacks;
    callbacks.on_update = [&](const learning::PpoUpdate& u) {
      std::ostringstream text;
      text << std::fixed << std::setprecision(0) << u.steps_per_second << " steps/s, "
           << std::setprecision(1) << "steps/episode " << u.mean_episode_steps << ", success "
           << std::setprecision(0) << 100.0 * u.success_rate << " %";
      bar.update(static_cast<int>(std::min<std::int64_t>(u.env_steps, cl.ppo.total_steps)),
                 text.str());
    };
    learning::trainPpo(cl.ppo, envs.count, envs.factory, ResetOptions{}, cl.run_dir, callbacks);
    bar.finish();
    const std::string script = packageShareDirectory() + "/scripts/plot_ppo.py";
    if (eval::runProgram({"/usr/bin/python3", script, cl.run_dir}, "", "") != 0) {
      std::cerr << "occlusion_train_ppo: plotting the curves failed (python3-matplotlib?)\n";
    }
    std::cout << "occlusion_train_ppo: done; the policy is " << cl.run_dir << "/policy.pt\n";
  } catch (const std::exception& error) {
    std::cerr << "\nocclusion_train_ppo: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
