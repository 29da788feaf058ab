// PPO: a short training on two in-process environments runs, logs every update and episode,
// checkpoints, resumes after an interruption, repeats itself with the same seed, and writes a
// policy the agents load; the actor starts as the escape head; policy files are checked.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "common/temporary_dir.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/learning/flat_adam.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/policy.hpp"
#include "occlusion_env/learning/ppo.hpp"

namespace occlusion_env {
namespace learning {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> csvRows(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) rows.push_back(line);
  return rows;
}

// A small untrained multi-task network as the backbone (32 px input).
std::string writeBackbone(const fs::path& dir) {
  fs::create_directories(dir);
  torch::manual_seed(3);
  NetworkConfig config;
  config.input_size = 32;
  MultiTaskUNet network(config);
  const std::string path = (dir / "backbone.pt").string();
  saveModel(network, path, {{"purpose", "ppo_test"}});
  return path;
}

EnvironmentOptions smallEnvironment() {
  EnvironmentOptions options;  // embedded objects
  options.width = options.height = 64;
  options.max_steps = 8;
  return options;
}

VectorEnvironment::Factory inProcess() {
  return [](int) { return std::make_unique<Environment>(smallEnvironment()); };
}

PpoOptions shortRun(const std::string& backbone) {
  PpoOptions options;
  options.backbone_path = backbone;
  options.total_steps = 48;
  options.steps_per_update = 16;  // 8 steps of each of the 2 environments
  options.epochs = 3;
  options.minibatch_size = 8;
  options.threads = 1;
  options.checkpoint_every = 1;
  return options;
}

bool sameParameters(PolicyNetwork& a, PolicyNetwork& b) {
  auto b_parameters = b->named_parameters();
  for (const auto& item : a->named_parameters()) {
    if (!torch::equal(item.value(), b_parameters[item.key()])) return false;
  }
  return true;
}

TEST(PpoTest, ShortTrainingLogsCheckpointsResumesAndRepeatsItself) {
  const fs::path dir = temporaryDir("occlusion_env_ppo");
  const std::string backbone = writeBackbone(dir);
  const PpoOptions options = shortRun(backbone);

  int updates_seen = 0, episodes_seen = 0;
  PpoCallbacks count;
  std::vector<std::int64_t> starts;  // on_start's steps done already, per call of trainPpo
  count.on_start = [&starts](std::int64_t env_steps) { starts.push_back(env_steps); };
  count.on_update = [&](const PpoUpdate& u) {
    ++updates_seen;
    EXPECT_EQ(u.env_steps, 16 * u.update);
    EXPECT_GT(u.steps_per_second, 0.0);
    EXPECT_TRUE(std::isfinite(u.policy_loss) && std::isfinite(u.value_loss));
    EXPECT_GE(u.epochs_run, 1);
  };
  count.on_episode = [&](const PpoEpisode& e) {
    ++episodes_seen;
    EXPECT_LT(e.seed, kFirstValidationSeed) << "training draws no validation or test scene";
    EXPECT_GE(e.steps, 1);
    EXPECT_LE(e.steps, 8);
  };
  const fs::path run = dir / "run";
  PolicyNetwork trained = trainPpo(options, 2, inProcess(), {}, run.string(), count);
  EXPECT_EQ(updates_seen, 3);
  EXPECT_EQ(starts, std::vector<std::int64_t>{0}) << "a new run";
  EXPECT_GE(episodes_seen, 2);
  EXPECT_EQ(csvRows(run / "updates.csv").size(), 3u);
  EXPECT_EQ(csvRows(run / "training_episodes.csv").size(), static_cast<std::size_t>(episodes_seen));
  EXPECT_TRUE(fs::exists(run / "checkpoint.pt"));
  EXPECT_TRUE(fs::exists(run / "checkpoint.json"));
  ASSERT_TRUE(fs::exists(run / "policy.pt"));

  // The same seed on the same machine (one thread): the same policy.
  PolicyNetwork again = trainPpo(options, 2, inProcess(), {}, (dir / "again").string());
  EXPECT_TRUE(sameParameters(trained, again)) << "the same seed gave another policy";

  // Interrupted during its second update (after the first checkpoint), re-run: it resumes from
  // the checkpoint and its logs hold each update once.
  PpoCallbacks interrupt;
  interrupt.on_update = [](const PpoUpdate& u) {
    if (u.update == 2) throw std::runtime_error("interrupted");
  };
  const fs::path interrupted = dir / "interrupted";
  EXPECT_THROW(trainPpo(options, 2, inProcess(), {}, interrupted.string(), interrupt),
               std::runtime_error);
  int resumed_updates = 0;
  std::int64_t resumed_from = -1;
  PpoCallbacks resumed;
  resumed.on_start = [&](std::int64_t env_steps) { resumed_from = env_steps; };
  resumed.on_update = [&](const PpoUpdate& u) {
    EXPECT_EQ(u.update, 2 + resumed_updates);
    ++resumed_updates;
  };
  trainPpo(options, 2, inProcess(), {}, interrupted.string(), resumed);
  EXPECT_EQ(resumed_from, 16) << "the steps of the checkpoint's one update";
  EXPECT_EQ(resumed_updates, 2);
  const auto rows = csvRows(interrupted / "updates.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(rows[i].substr(0, 2), std::to_string(i + 1) + ",");

  // A longer run in the same directory continues it; other options are refused.
  PpoOptions longer = options;
  longer.total_steps = 80;
  updates_seen = 0;
  trainPpo(longer, 2, inProcess(), {}, run.string(), count);
  EXPECT_EQ(updates_seen, 2);
  EXPECT_EQ(starts.back(), 48) << "the finished run's three updates";
  EXPECT_EQ(csvRows(run / "updates.csv").size(), 5u);
  PpoOptions other = options;
  other.clip_epsilon = 0.3;
  EXPECT_THROW(trainPpo(other, 2, inProcess(), {}, run.string()), InvalidArgumentError);
  // A damaged checkpoint is refused by its folder, not as libtorch's error.
  const fs::path damaged = dir / "damaged";
  fs::copy(run, damaged, fs::copy_options::recursive);
  std::ofstream(damaged / "checkpoint.pt", std::ios::trunc) << "cut short";
  try {
    trainPpo(longer, 2, inProcess(), {}, damaged.string());
    ADD_FAILURE() << "resumed from a damaged checkpoint";
  } catch (const InvalidArgumentError& error) {
    EXPECT_NE(std::string(error.what()).find("cannot be read"), std::string::npos) << error.what();
  }

  // The policy runs as an agent (the generic entry, by path), deterministically.
  Environment environment(smallEnvironment());
  const StepResult start = environment.reset(1000000);
  const AgentRegistry registry = learningAgents();
  const auto agent = registry.make("policy", {environment, (run / "policy.pt").string()});
  agent->reset(1);
  const Action first = agent->act(rigObservationOf(start));
  agent->reset(1);
  const Action repeated = agent->act(rigObservationOf(start));
  EXPECT_TRUE(std::isfinite(first.d_azimuth_rad) && std::isfinite(first.d_elevation_rad));
  EXPECT_EQ(first.d_azimuth_rad, repeated.d_azimuth_rad);
  EXPECT_EQ(first.d_elevation_rad, repeated.d_elevation_rad);
  EXPECT_THROW(registry.make("policy", {environment, ""}), InvalidArgumentError)
      << "the generic policy agent needs a model path";
  fs::remove_all(dir);
}

// With overlap (half of the environments render while the other half is encoded), on three
// environments (groups of two and one): every step is booked once, the run repeats itself, and a
// run without overlap neither resumes with it nor is refused when its checkpoint predates the
// option.
TEST(PpoTest, OverlapBooksEveryStepAndRepeatsItself) {
  const fs::path dir = temporaryDir("occlusion_env_ppo_overlap");
  PpoOptions options = shortRun(writeBackbone(dir));
  options.overlap = true;
  options.total_steps = 36;  // two updates of 6 rounds of 3 environments
  std::vector<std::int64_t> update_steps;
  int episode_steps = 0;
  PpoCallbacks count;
  count.on_update = [&](const PpoUpdate& u) { update_steps.push_back(u.env_steps); };
  count.on_episode = [&](const PpoEpisode& e) {
    EXPECT_GE(e.steps, 1);
    EXPECT_LE(e.steps, 8);
    episode_steps += e.steps;
  };
  PolicyNetwork trained = trainPpo(options, 3, inProcess(), {}, (dir / "run").string(), count);
  EXPECT_EQ(update_steps, (std::vector<std::int64_t>{18, 36}));
  EXPECT_GT(episode_steps, 0);
  EXPECT_LE(episode_steps, 36);
  PolicyNetwork again = trainPpo(options, 3, inProcess(), {}, (dir / "again").string());
  EXPECT_TRUE(sameParameters(trained, again)) << "the same seed gave another policy";

  options.overlap = false;
  const fs::path plain = dir / "plain";
  options.total_steps = 18;
  trainPpo(options, 3, inProcess(), {}, plain.string());
  PpoOptions with_overlap = options;
  with_overlap.overlap = true;
  with_overlap.total_steps = 36;
  EXPECT_THROW(trainPpo(with_overlap, 3, inProcess(), {}, plain.string()), InvalidArgumentError);
  // A checkpoint written before the option existed (no "overlap") resumes without overlap.
  nlohmann::json state;
  std::ifstream(plain / "checkpoint.json") >> state;
  state["options"].erase("overlap");
  std::ofstream(plain / "checkpoint.json") << state.dump(2);
  options.total_steps = 36;
  update_steps.clear();
  trainPpo(options, 3, inProcess(), {}, plain.string(), count);
  EXPECT_EQ(update_steps, (std::vector<std::int64_t>{36}));
  fs::remove_all(dir);
}

// With one libtorch thread each environment's thread encodes its own observation and the
// critic's steps run on a thread of their own beside the actor's; with more, the trainer encodes
// the batch and steps both together. Both must give the same update (to float rounding: a batch
// of one and a batch of two run different convolutions), so one update books the same episodes
// and nearly the same losses either way.
TEST(PpoTest, OneLibtorchThreadSpreadsTheWorkAndGivesTheSameUpdate) {
  const fs::path dir = temporaryDir("occlusion_env_ppo_encoders");
  // The shipped network: an untrained one's features hardly tell two scenes apart.
  PpoOptions options = shortRun(defaultModelPath());
  options.total_steps = options.steps_per_update;
  struct Run {
    std::vector<PpoUpdate> updates;
    std::vector<int> episode_steps;
  };
  auto train = [&](int threads, const std::string& name) {
    options.threads = threads;
    Run run;
    PpoCallbacks record;
    record.on_update = [&run](const PpoUpdate& u) { run.updates.push_back(u); };
    record.on_episode = [&run](const PpoEpisode& e) { run.episode_steps.push_back(e.steps); };
    trainPpo(options, 2, inProcess(), {}, (dir / name).string(), record);
    return run;
  };
  const Run on_environment_threads = train(1, "one_thread");
  const Run on_trainer_thread = train(2, "two_threads");
  ASSERT_EQ(on_environment_threads.updates.size(), 1u);
  ASSERT_EQ(on_trainer_thread.updates.size(), 1u);
  EXPECT_EQ(on_environment_threads.episode_steps, on_trainer_thread.episode_steps);
  const PpoUpdate &a = on_environment_threads.updates[0], &b = on_trainer_thread.updates[0];
  EXPECT_NEAR(a.policy_loss, b.policy_loss, 1e-4);
  EXPECT_NEAR(a.value_loss, b.value_loss, 1e-4);
  EXPECT_NEAR(a.mean_episode_reward, b.mean_episode_reward, 1e-4);
  EXPECT_EQ(a.epochs_run, b.epochs_run);
  fs::remove_all(dir);
}

// The last update's sigma of a short run with entropy coefficient `entropy`.
double lastSigma(PpoOptions options, double entropy, const fs::path& run) {
  options.entropy_coefficient = entropy;
  double sigma = 0.0;
  PpoCallbacks callbacks;
  callbacks.on_update = [&sigma](const PpoUpdate& u) { sigma = u.action_std; };
  trainPpo(options, 2, inProcess(), {}, run.string(), callbacks);
  return sigma;
}

TEST(PpoTest, TheEntropyBonusTrainsALearnedSigmaOnly) {
  const fs::path dir = temporaryDir("occlusion_env_ppo_sigma");
  PpoOptions options = shortRun(writeBackbone(dir));
  options.actor_learning_rate = 0.02;  // a few steps show the direction
  options.action_std = options.action_std_end = 0.6;

  // A fixed schedule: the entropy term has no gradient, sigma is the schedule's.
  EXPECT_FLOAT_EQ(lastSigma(options, 10.0, dir / "fixed"), 0.6);

  // A learned sigma starts at action_std; a large bonus widens it, beyond a run without one.
  options.policy.learned_std = true;
  const double without = lastSigma(options, 0.0, dir / "without");
  const double with_bonus = lastSigma(options, 10.0, dir / "with");
  EXPECT_GT(with_bonus, 0.6 * 1.1);
  EXPECT_GT(with_bonus, without);

  // The policy file keeps it (its manifest names learned_std) and loads as an agent's.
  LoadedPolicy loaded = loadPolicy((dir / "with" / "policy.pt").string());
  EXPECT_TRUE(loaded.network->config().learned_std);
  // The file holds sigma after the last update, which the bonus widened once more.
  EXPECT_GT(loaded.network->logStd().exp().mean().item<double>(), with_bonus);
  fs::remove_all(dir);
}

// A small untrained multi-task network (32 px input, seed 5) in eval mode.
MultiTaskUNet smallNetwork() {
  torch::manual_seed(5);
  NetworkConfig config;
  config.input_size = 32;
  MultiTaskUNet network(config);
  network->eval();
  return network;
}

// A policy of `config` on `network`, its actor from the escape head, in eval mode.
PolicyNetwork policyOn(MultiTaskUNet& network, const PolicyConfig& config) {
  PolicyNetwork policy(network->config(), config);
  policy->initialiseFrom(network, /*actor_from_escape=*/true);
  policy->eval();
  return policy;
}

TEST(PpoTest, TheActorStartsAsTheEscapeHead) {
  MultiTaskUNet network = smallNetwork();
  const NetworkConfig& config = network->config();
  PolicyConfig free_mean;
  free_mean.unit_mean = false;
  PolicyNetwork policy = policyOn(network, free_mean);
  torch::NoGradGuard no_grad;
  const torch::Tensor input = torch::randn({3, 4, 32, 32});
  const NetworkOutput out = network->forward(input);
  const torch::Tensor features = policy->features(input);
  EXPECT_TRUE(torch::allclose(features, out.features));
  const torch::Tensor mean =
      policy->actionMean(features, torch::zeros({3, PolicyConfig().rigInputs()}));
  // (d_azimuth, d_elevation) = (cos, sin) of the escape direction.
  EXPECT_TRUE(torch::allclose(mean.select(1, 0), out.escape_direction.select(1, 1)));
  EXPECT_TRUE(torch::allclose(mean.select(1, 1), out.escape_direction.select(1, 0)));
  // With a unit mean the same direction at unit length.
  PolicyConfig unit_config;
  unit_config.unit_mean = true;
  PolicyNetwork unit(config, unit_config);
  unit->initialiseFrom(network, /*actor_from_escape=*/true);
  const torch::Tensor unit_mean =
      unit->actionMean(features, torch::zeros({3, PolicyConfig().rigInputs()}));
  EXPECT_TRUE(torch::allclose(unit_mean.norm(2, 1), torch::ones({3})));
  EXPECT_TRUE(torch::allclose(unit_mean, mean / mean.norm(2, 1, true), 1e-4, 1e-5));

  PolicyNetwork fresh(config, free_mean);
  fresh->initialiseFrom(network, /*actor_from_escape=*/false);
  EXPECT_LT(fresh->actionMean(features, torch::zeros({3, PolicyConfig().rigInputs()}))
                .abs()
                .max()
                .item<float>(),
            0.5f)
      << "a fresh actor starts near the zero mean";
}

TEST(PpoTest, TheDirectionsActionStartsWhereTheEscapeHeadPoints) {
  MultiTaskUNet network = smallNetwork();
  PolicyConfig directions;
  directions.action = "directions";
  directions.directions = 32;
  PolicyNetwork policy = policyOn(network, directions);
  torch::NoGradGuard no_grad;
  const torch::Tensor input = torch::randn({4, 4, 32, 32});
  const NetworkOutput out = network->forward(input);
  const torch::Tensor features = policy->features(input);
  const torch::Tensor rig = torch::zeros({4, directions.rigInputs()});
  const torch::Tensor log_probs = policy->directionLogProbabilities(features, rig);
  ASSERT_EQ(log_probs.sizes(), (std::vector<std::int64_t>{4, 32}));
  EXPECT_TRUE(torch::allclose(log_probs.exp().sum(1), torch::ones({4}), 1e-5, 1e-5));
  // The agent's move (the circular mean) points along the escape head's (cos, sin).
  const torch::Tensor mean = policy->actionMean(features, rig);
  for (int b = 0; b < 4; ++b) {
    const double escape = std::atan2(out.escape_direction[b][0].item<double>(),
                                     out.escape_direction[b][1].item<double>());
    const double chosen = std::atan2(mean[b][1].item<double>(), mean[b][0].item<double>());
    EXPECT_LT(std::abs(std::remainder(chosen - escape, 2.0 * M_PI)), 0.01) << "row " << b;
  }
  // A longer mean sharpens the distribution: larger kappa, lower entropy.
  PolicyConfig sharper = directions;
  sharper.direction_concentration = 4.0 * directions.direction_concentration;
  PolicyNetwork sharp = policyOn(network, sharper);
  const auto entropy = [](const torch::Tensor& lp) { return -(lp.exp() * lp).sum(1); };
  EXPECT_TRUE((entropy(sharp->directionLogProbabilities(features, rig)) < entropy(log_probs))
                  .all()
                  .item<bool>());
  // The Gaussian's options do not apply.
  PolicyConfig wrong = directions;
  wrong.unit_mean = true;
  EXPECT_THROW(wrong.validate(), InvalidArgumentError);
}

TEST(PpoTest, ADirectionsPolicyTrainsWithItsEntropyBonusAndActs) {
  const fs::path dir = temporaryDir("occlusion_env_ppo_directions");
  PpoOptions options = shortRun(writeBackbone(dir));
  options.policy.action = "directions";
  options.policy.directions = 16;
  options.actor_learning_rate = 0.02;
  const auto lastEntropy = [&](double coefficient, const std::string& name) {
    PpoOptions run = options;
    run.entropy_coefficient = coefficient;
    std::vector<PpoUpdate> updates;
    PpoCallbacks callbacks;
    callbacks.on_update = [&](const PpoUpdate& u) { updates.push_back(u); };
    trainPpo(run, 2, inProcess(), {}, (dir / name).string(), callbacks);
    EXPECT_EQ(updates.size(), 3u);
    for (const PpoUpdate& u : updates) {
      EXPECT_TRUE(std::isnan(u.action_std)) << "directions have no sigma";
      EXPECT_GT(u.entropy, 0.0);
      EXPECT_LE(u.entropy, std::log(16.0) + 1e-6);
    }
    return updates.back().entropy;
  };
  // The bonus has a gradient: a large one keeps the distribution broader than none.
  const double without = lastEntropy(0.0, "without");
  const double with_bonus = lastEntropy(10.0, "with");
  EXPECT_GT(with_bonus, without);

  // The policy file names its action and acts as an agent: one unit-or-shorter move.
  LoadedPolicy loaded = loadPolicy((dir / "with" / "policy.pt").string());
  EXPECT_TRUE(loaded.network->config().isDirections());
  EXPECT_EQ(loaded.network->config().directions, 16);
  PolicyAgent agent(std::make_shared<LoadedPolicy>(std::move(loaded)));
  Environment env(smallEnvironment());
  const StepResult start = env.reset(7);
  agent.reset(7);
  const Action move = agent.act(rigObservationOf(start));
  const double length = std::hypot(move.d_azimuth_rad, move.d_elevation_rad);
  EXPECT_GT(length, 0.0);
  EXPECT_LE(length, 1.0 + 1e-5);

  // Sampled: a unit move of the circle, the same again for the same scene seed.
  auto sampled_policy =
      std::make_shared<LoadedPolicy>(loadPolicy((dir / "with" / "policy.pt").string()));
  PolicyAgent sampled(sampled_policy, /*sampled=*/true);
  std::vector<Action> first, again;
  for (std::vector<Action>* moves : {&first, &again}) {
    sampled.reset(7);
    for (int k = 0; k < 6; ++k) moves->push_back(sampled.act(rigObservationOf(start)));
  }
  bool varied = false;
  for (std::size_t k = 0; k < first.size(); ++k) {
    EXPECT_NEAR(std::hypot(first[k].d_azimuth_rad, first[k].d_elevation_rad), 1.0, 1e-5);
    const double angle = std::atan2(first[k].d_elevation_rad, first[k].d_azimuth_rad);
    const double steps = angle / (2.0 * M_PI / 16.0);
    EXPECT_NEAR(steps, std::round(steps), 1e-4) << "one of the 16 moves";
    EXPECT_EQ(first[k].d_azimuth_rad, again[k].d_azimuth_rad);
    EXPECT_EQ(first[k].d_elevation_rad, again[k].d_elevation_rad);
    varied |= first[k].d_azimuth_rad != first[0].d_azimuth_rad ||
              first[k].d_elevation_rad != first[0].d_elevation_rad;
  }
  EXPECT_TRUE(varied) << "six draws of a broad distribution were all the same move";
  fs::remove_all(dir);
}

// FlatAdam takes the steps torch::optim::Adam takes after clip_grad_norm_, clipped or not, from
// gradients that backward() accumulates; its state survives save/load, and it continues from a
// torch::optim::Adam's saved state (checkpoints before it) as that optimiser would.
TEST(PpoTest, FlatAdamStepsAsTorchsAdamAfterClipping) {
  torch::manual_seed(11);
  auto makeMlp = [] {
    torch::manual_seed(12);
    return torch::nn::Sequential(torch::nn::Linear(7, 5), torch::nn::Tanh(),
                                 torch::nn::Linear(5, 2));
  };
  torch::nn::Sequential flat_mlp = makeMlp(), torch_mlp = makeMlp();
  FlatAdam flat(flat_mlp->parameters(), 0.01);
  torch::optim::Adam reference(torch_mlp->parameters(), torch::optim::AdamOptions(0.01));
  const auto lossOf = [](torch::nn::Sequential& mlp, const torch::Tensor& x, double scale) {
    return (mlp->forward(x) * scale).pow(2).mean();
  };
  bool clipped = false, unclipped = false;
  const auto sameParameters = [&](double tolerance) {
    const auto a = flat_mlp->parameters(), b = torch_mlp->parameters();
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!torch::allclose(a[i], b[i], 0.0, tolerance)) return false;
    }
    return true;
  };
  for (int step = 0; step < 30; ++step) {
    const torch::Tensor x = torch::randn({16, 7});
    const double scale = step % 2 == 0 ? 10.0 : 0.1;  // large gradients clipped, small ones not
    flat.zeroGrad();
    lossOf(flat_mlp, x, scale).backward();
    reference.zero_grad();
    lossOf(torch_mlp, x, scale).backward();
    const double norm = torch::nn::utils::clip_grad_norm_(torch_mlp->parameters(), 1.0);
    (norm > 1.0 ? clipped : unclipped) = true;
    flat.step(1.0);
    reference.step();
    ASSERT_TRUE(sameParameters(1e-5)) << "step " << step;
  }
  EXPECT_TRUE(clipped && unclipped);

  // Saved and loaded into a fresh optimiser: the next step is the same.
  std::stringstream flat_bytes, torch_bytes;
  const auto saveTo = [](std::stringstream& bytes, const auto& optimiser) {
    torch::serialize::OutputArchive out;
    optimiser.save(out);
    out.save_to(bytes);
  };
  const auto loadInto = [](std::stringstream& bytes, FlatAdam& optimiser) {
    torch::serialize::InputArchive in;
    in.load_from(bytes);
    optimiser.load(in);
  };
  saveTo(flat_bytes, flat);
  FlatAdam restored(flat_mlp->parameters(), 0.01);
  loadInto(flat_bytes, restored);
  // From torch's Adam's own saved state, too.
  torch::nn::Sequential converted_mlp = makeMlp();
  {
    torch::NoGradGuard no_grad;
    const auto source = torch_mlp->parameters(), target = converted_mlp->parameters();
    for (std::size_t i = 0; i < source.size(); ++i) target[i].copy_(source[i]);
  }
  saveTo(torch_bytes, reference);
  FlatAdam converted(converted_mlp->parameters(), 0.01);
  loadInto(torch_bytes, converted);

  const torch::Tensor x = torch::randn({16, 7});
  restored.zeroGrad();
  lossOf(flat_mlp, x, 0.1).backward();
  restored.step(1.0);
  converted.zeroGrad();
  lossOf(converted_mlp, x, 0.1).backward();
  converted.step(1.0);
  reference.zero_grad();
  lossOf(torch_mlp, x, 0.1).backward();
  torch::nn::utils::clip_grad_norm_(torch_mlp->parameters(), 1.0);
  reference.step();
  EXPECT_TRUE(sameParameters(1e-5)) << "after save and load";
  const auto a = converted_mlp->parameters(), b = torch_mlp->parameters();
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(torch::allclose(a[i], b[i], 0.0, 1e-5)) << "from torch's Adam, parameter " << i;
  }
}

TEST(PpoTest, SampleDirectionInvertsTheCumulativeProbability) {
  const float log_probs[3] = {std::log(0.25f), std::log(0.5f), std::log(0.25f)};
  EXPECT_EQ(sampleDirection(log_probs, 3, 0.0), 0);
  EXPECT_EQ(sampleDirection(log_probs, 3, 0.2), 0);
  EXPECT_EQ(sampleDirection(log_probs, 3, 0.3), 1);
  EXPECT_EQ(sampleDirection(log_probs, 3, 0.74), 1);
  EXPECT_EQ(sampleDirection(log_probs, 3, 0.8), 2);
  EXPECT_EQ(sampleDirection(log_probs, 3, 0.999999), 2);
}

// The simulator, except that every third reset finds no scene (as a seed whose draws give no
// occluded start view does).
class SometimesNoScene : public EnvironmentInterface {
 public:
  StepResult reset(std::uint64_t seed, const ResetOptions& overrides) override {
    if (++resets_ % 3 == 0) {
      throw SceneGenerationError("no scene with occlusion at the start view (test)");
    }
    return env_.reset(seed, overrides);
  }
  StepResult step(const Action& action) override { return env_.step(action); }
  std::string describe() const override { return "sometimes no scene"; }

 private:
  Environment env_{smallEnvironment()};
  int resets_ = 0;
};

TEST(PpoTest, ASeedWithoutASceneIsSkippedNotFatal) {
  const fs::path dir = temporaryDir("occlusion_env_ppo_skip");
  PpoOptions options = shortRun(writeBackbone(dir));
  const VectorEnvironment::Factory sometimes = [](int) {
    return std::make_unique<SometimesNoScene>();
  };
  std::int64_t episodes = 0;
  PpoCallbacks callbacks;
  callbacks.on_episode = [&](const PpoEpisode&) { ++episodes; };
  ASSERT_NO_THROW(trainPpo(options, 2, sometimes, {}, (dir / "run").string(), callbacks));
  EXPECT_GT(episodes, 3) << "resets kept failing every third time, and training went on";
  // A source that never has a scene still stops the run, with the scene error.
  const VectorEnvironment::Factory never = [](int) {
    EnvironmentOptions impossible = smallEnvironment();
    impossible.scene.num_objects = 1;  // nothing to hide: no start view has occlusion
    impossible.max_scene_attempts = 1;
    return std::make_unique<Environment>(impossible);
  };
  EXPECT_THROW(trainPpo(options, 2, never, {}, (dir / "never").string(), {}), SceneGenerationError);
  fs::remove_all(dir);
}

// Memory (issue 28): the rig inputs hold the last m moves, newest first, and nothing before the
// episode made them; a policy with memory trains, says so in its manifest, loads and acts, while
// policies without the field keep the last move alone.
TEST(PpoTest, APolicyWithMemorySeesItsLastMovesTrainsAndActs) {
  MoveHistory history(2);
  std::vector<float> rig(5, -9.0f);
  history.writeRigInput(M_PI / 4.0, rig.data());
  EXPECT_EQ(rig, (std::vector<float>{0, 0, 0, 0, 0.5f})) << "no move yet";
  history.push({1.0, 0.0});
  history.push({0.0, 2.0});
  history.writeRigInput(0.0, rig.data());
  EXPECT_EQ(rig, (std::vector<float>{0, 1, 1, 0, 0})) << "newest first, as unit directions";
  history.push({-3.0, 0.0});
  history.writeRigInput(0.0, rig.data());
  EXPECT_EQ(rig, (std::vector<float>{-1, 0, 0, 1, 0})) << "the oldest forgotten";
  history.clear();
  history.writeRigInput(0.0, rig.data());
  EXPECT_EQ(rig, (std::vector<float>(5, 0.0f))) << "an episode's start forgets every move";
  EXPECT_THROW(MoveHistory(0), InvalidArgumentError);

  EXPECT_EQ(PolicyConfig().rigInputs(), 3);
  EXPECT_FALSE(PolicyConfig().toJson().contains("move_memory"))
      << "a policy without memory keeps the identity of the policies before the option";
  EXPECT_EQ(PolicyConfig::fromJson(nlohmann::json::object()).move_memory, 1);
  PolicyConfig too_long;
  too_long.move_memory = 17;
  EXPECT_THROW(too_long.validate(), InvalidArgumentError);

  const fs::path dir = temporaryDir("occlusion_env_ppo_memory");
  const std::string backbone = writeBackbone(dir);
  PpoOptions options = shortRun(backbone);
  options.policy.move_memory = 3;
  const fs::path run = dir / "run";
  PolicyNetwork trained = trainPpo(options, 2, inProcess(), {}, run.string());
  EXPECT_EQ(trained->config().rigInputs(), 7);
  {
    std::ifstream in(run / "policy.json");
    EXPECT_EQ(nlohmann::json::parse(in).at("policy").at("move_memory"), 3);
  }
  // Its rig term learned from the older moves too (it starts at zero).
  const torch::Tensor older = trained->named_parameters()["actor_rig.weight"].slice(1, 2, 6);
  EXPECT_GT(older.abs().max().item<float>(), 0.0f);
  // Without memory the run is another run: its directory is not resumed with memory.
  PpoOptions without = options;
  without.policy.move_memory = 1;
  EXPECT_THROW(trainPpo(without, 2, inProcess(), {}, run.string()), InvalidArgumentError);

  Environment environment(smallEnvironment());
  const AgentRegistry registry = learningAgents();
  const auto agent = registry.make("policy", {environment, (run / "policy.pt").string()});
  agent->reset(1);
  StepResult result = environment.reset(1000000);
  for (int step = 0; step < 3 && !result.terminated && !result.truncated; ++step) {
    const Action move = agent->act(rigObservationOf(result));
    ASSERT_TRUE(std::isfinite(move.d_azimuth_rad) && std::isfinite(move.d_elevation_rad));
    result = environment.step(move);
  }
  fs::remove_all(dir);
}

TEST(PpoTest, PolicyAndNetworkFilesAreNotMistakenForEachOther) {
  const fs::path dir = temporaryDir("occlusion_env_policy_files");
  const std::string backbone = writeBackbone(dir);
  NetworkConfig config;
  config.input_size = 32;
  PolicyNetwork policy(config, PolicyConfig{});
  const std::string policy_path = (dir / "policy.pt").string();
  savePolicy(policy, policy_path, {});
  EXPECT_NO_THROW(loadPolicy(policy_path));
  const auto expectRefused = [](const std::function<void()>& load, const std::string& words) {
    try {
      load();
      ADD_FAILURE() << "loaded";
    } catch (const InvalidArgumentError& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
    }
  };
  expectRefused([&] { loadPolicy(backbone); }, "not a PPO policy");
  expectRefused([&] { loadModel(policy_path); }, "not a multi-task network");
  expectRefused([&] { loadPolicy((dir / "missing.pt").string()); }, "does not exist");
  {
    std::ifstream in(dir / "policy.json");
    nlohmann::json manifest = nlohmann::json::parse(in);
    manifest["policy"]["hidden"] = 32;
    std::ofstream(dir / "policy.json") << manifest.dump();
  }
  expectRefused([&] { loadPolicy(policy_path); }, "does not match");
  PpoOptions options;
  options.backbone_path = backbone;
  options.gamma = 1.5;
  EXPECT_THROW(options.validate(), InvalidArgumentError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace learning
}  // namespace occlusion_env
