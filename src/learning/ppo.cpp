#include "occlusion_env/learning/ppo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/text_file.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/learning/flat_adam.hpp"
#include "occlusion_env/learning/inference_encoder.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/network_input.hpp"
#include "occlusion_env/learning/training.hpp"

namespace occlusion_env {
namespace learning {

namespace fs = std::filesystem;

namespace {

void addRunOptions(OptionTable<PpoOptions>& table) {
  using O = PpoOptions;
  table
      .add("backbone_path", &O::backbone_path,
           OptionSpec("the pretrained multi-task network (.pt + .json)").flag("--backbone"))
      .add("actor_from_escape", &O::actor_from_escape,
           OptionSpec("start the actor at the network's escape head").flag(""))
      .add("fine_tune", &O::fine_tune, OptionSpec("train the encoder too (with --backbone-lr)"))
      .add("overlap", &O::overlap,
           OptionSpec("with 2+ environments: half of them render while the trainer runs "
                      "inference for the other half (on one thread; another order of the "
                      "random draws)"))
      .add("backbone_learning_rate", &O::backbone_learning_rate,
           OptionSpec("the encoder's learning rate with --fine-tune")
               .range(1e-9, 1)
               .flag("--backbone-lr"))
      .add("total_steps", &O::total_steps,
           OptionSpec("environment steps in all").range(1, 1e12).flag("--steps"))
      .add("steps_per_update", &O::steps_per_update, OptionSpec("N_u").range(2, 1e6))
      .add("epochs", &O::epochs, OptionSpec("passes per update at most (K)").range(1, 10000))
      .add("minibatch_size", &O::minibatch_size,
           OptionSpec("steps per minibatch").range(2, 1e6).flag("--minibatch"));
}

void addPpoOptions(OptionTable<PpoOptions>& table) {
  using O = PpoOptions;
  table
      .add("actor_learning_rate", &O::actor_learning_rate,
           OptionSpec("Adam learning rate of the actor").range(1e-9, 1).flag("--actor-lr"))
      .add("critic_learning_rate", &O::critic_learning_rate,
           OptionSpec("Adam learning rate of the critic").range(1e-9, 1).flag("--critic-lr"))
      .add("gamma", &O::gamma, OptionSpec("discount").above(0).atMost(1))
      .add("gae_lambda", &O::gae_lambda, OptionSpec("GAE lambda").range(0, 1).flag("--lambda"))
      .add("clip_epsilon", &O::clip_epsilon,
           OptionSpec("surrogate clip epsilon").above(0).below(1).flag("--clip"))
      .add("action_std", &O::action_std,
           OptionSpec("action sigma at the start").above(0).atMost(100).flag("--std"))
      .add("action_std_end", &O::action_std_end,
           OptionSpec("action sigma at the end (linear in steps; not with --learned-std)")
               .above(0)
               .atMost(100)
               .flag("--std-end"))
      .add("entropy_coefficient", &O::entropy_coefficient,
           OptionSpec("entropy bonus coefficient").range(0, 100).flag("--entropy"))
      .add("max_grad_norm", &O::max_grad_norm,
           OptionSpec("gradient norm clip; 0 = none").range(0, 1e6))
      .add("target_kl", &O::target_kl,
           OptionSpec("stop an update's epochs above 1.5 * this; 0 = never").range(0, 100))
      .add("normalize_advantages", &O::normalize_advantages,
           OptionSpec("normalised advantages").negatedFlag("--no-advantage-norm"));
}

void addRecordOptions(OptionTable<PpoOptions>& table) {
  using O = PpoOptions;
  table
      .add("reward", &O::reward,
           OptionSpec("the environments' reward normalisation: union (Agent-UN) | intersection "
                      "(Agent-IN)")
               .choices({"union", "intersection", "none"}))
      .add("seed", &O::seed, OptionSpec("initial weights, actions and training seeds"))
      .add("threads", &O::threads,
           OptionSpec("libtorch threads; 0 = all cores (1: each environment's thread encodes its "
                      "own observation and, with the encoder frozen, the critic steps on a "
                      "thread beside the actor's; two stall when the machine is shared)")
               .range(0, 256))
      .add("checkpoint_every", &O::checkpoint_every,
           OptionSpec("updates between checkpoints").range(1, 1e6));
}

OptionTable<PpoOptions> makePpoTable() {
  OptionTable<PpoOptions> table;
  addRunOptions(table);
  addPpoOptions(table);
  addRecordOptions(table);
  return table;
}

}  // namespace

const OptionTable<PpoOptions>& ppoOptionTable() {
  static const OptionTable<PpoOptions> table = makePpoTable();
  return table;
}

void applyPaperRecipe(PpoOptions& options) {
  options.actor_from_escape = false;
  options.policy.rig_inputs = false;
  options.policy.unit_mean = false;
  options.gae_lambda = 1.0;
  options.minibatch_size = 200;
  options.target_kl = 0.0;
  options.max_grad_norm = 0.0;
}

void PpoOptions::validate() const {
  ppoOptionTable().check(*this);
  policy.validate();
  if (backbone_path.empty()) {
    throw InvalidArgumentError("ppo: a pretrained network (backbone_path) is needed");
  }
}

nlohmann::json PpoOptions::toJson() const {
  nlohmann::json json = ppoOptionTable().toJson(*this);
  json.erase("threads");  // neither changes the result
  json.erase("checkpoint_every");
  json["policy"] = policy.toJson();
  return json;
}

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

constexpr int kMaxSkippedSeeds = 100;  // unusable training seeds in a row before giving up

void reportSkippedSeed(std::uint64_t seed, const std::string& why) {
  std::cerr << "occlusion_train_ppo: skipping training seed " << seed << ": " << why << "\n";
}

// A random stream's state as text (checkpoint.json), and back.
std::string streamText(const std::mt19937_64& stream) {
  std::ostringstream text;
  text << stream;
  return text.str();
}
void readStream(const std::string& text, std::mt19937_64& stream) {
  std::istringstream in(text);
  in >> stream;
}

constexpr double kLogSqrtTwoPi = 0.91893853320467274178;

// Sum over the two action dimensions of log N(action; mean, std^2); std [2], one per axis.
torch::Tensor gaussianLogProbability(const torch::Tensor& action, const torch::Tensor& mean,
                                     const torch::Tensor& std) {
  const torch::Tensor z = (action - mean) / std;
  return (-0.5 * z * z - std.log() - kLogSqrtTwoPi).sum(1);
}

// The entropy of the two-axis Gaussian with sigmas std [2] (a scalar tensor: with a learned
// sigma it carries the gradient of the entropy bonus).
torch::Tensor gaussianEntropy(const torch::Tensor& std) {
  return (0.5 + kLogSqrtTwoPi + std.log()).sum();
}

// The state that a checkpoint keeps besides the parameters and optimisers.
struct Progress {
  int updates = 0;
  std::int64_t env_steps = 0;
  std::int64_t episodes = 0;
  std::mt19937_64 random;  // minibatch order
  // Environment i's scene seeds and action noise: its episodes do not depend on when the other
  // environments' steps end.
  std::vector<std::mt19937_64> environment_random;
};

// Keeps the rows of a CSV whose first column is <= `last` (rows written after the checkpoint
// that a resumed run writes again), or starts it with `header`.
void trimCsv(const fs::path& path, const std::string& header, std::int64_t last) {
  std::vector<std::string> kept{header};
  std::ifstream in(path);
  std::string line;
  if (in && std::getline(in, line)) {
    while (std::getline(in, line)) {
      if (!line.empty() && std::stoll(line.substr(0, line.find(','))) <= last) kept.push_back(line);
    }
  }
  in.close();
  std::string text;
  for (const auto& row : kept) text += row + '\n';
  writeTextFile(path.string(), text);
}

// One row per finished training episode (not the evaluation's EpisodeRecord schema).
constexpr const char* kEpisodesCsv = "training_episodes.csv";
constexpr const char* kEpisodeHeader = "episode,env_steps,environment,seed,reward,steps,success";
constexpr const char* kUpdateHeader =
    "update,env_steps,episodes,action_std,policy_loss,value_loss,entropy,approx_kl,"
    "clip_fraction,explained_variance,epochs_run,mean_episode_reward,mean_episode_steps,"
    "success_rate,steps_per_second,seconds,environment_seconds,inference_seconds,"
    "optimisation_seconds";

// The options that must match for a run to resume (total_steps may grow; threads and the
// checkpoint interval do not change the result).
nlohmann::json resumeKey(const PpoOptions& options) {
  nlohmann::json key = options.toJson();
  key.erase("total_steps");
  return key;
}

// Everything one update's rollout keeps, [T * N] rows in time-major order (row = t * N + i).
struct Rollout {
  torch::Tensor features, inputs, rig, actions, log_probs, values, rewards, dones;
  void allocate(int rows, int feature_size, int rig_inputs, const InputFormat& input,
                bool keep_inputs) {
    features = torch::zeros({rows, feature_size});
    if (keep_inputs) inputs = torch::zeros({rows, input.channels(), input.size, input.size});
    rig = torch::zeros({rows, rig_inputs});
    actions = torch::zeros({rows, 2});
    log_probs = torch::zeros({rows});
    values = torch::zeros({rows});
    rewards = torch::zeros({rows});
    dones = torch::zeros({rows});
  }
};

class PpoTrainer {
 public:
  PpoTrainer(const PpoOptions& options, int count, const VectorEnvironment::Factory& factory,
             const ResetOptions& reset, const std::string& run_dir, const PpoCallbacks& callbacks)
      : options_(options), count_(count), reset_(reset), run_dir_(run_dir), callbacks_(callbacks) {
    options_.validate();
    fs::create_directories(run_dir_);
    LoadedModel pretrained = loadModel(options_.backbone_path);
    input_format_ = pretrained.network->config().inputFormat();
    policy_ = PolicyNetwork(pretrained.network->config(), options_.policy);
    policy_->initialiseFrom(pretrained.network, options_.actor_from_escape);
    if (options_.policy.learned_std) {
      torch::NoGradGuard no_grad;
      policy_->logStd().fill_(std::log(options_.action_std));  // a checkpoint overrides it
    }
    policy_->eval();  // BatchNorm keeps the pretrained statistics, fine-tuned or not
    if (!options_.fine_tune) {
      for (auto& p : policy_->backbone()->parameters()) p.set_requires_grad(false);
    }
    // The heads' few thousand weights each: stepped flat (learning/flat_adam.hpp).
    actor_optimizer_ =
        std::make_unique<FlatAdam>(policy_->actorParameters(), options_.actor_learning_rate);
    critic_optimizer_ =
        std::make_unique<FlatAdam>(policy_->criticParameters(), options_.critic_learning_rate);
    if (options_.fine_tune) {
      backbone_optimizer_ = std::make_unique<torch::optim::Adam>(
          policy_->backbone()->parameters(),
          torch::optim::AdamOptions(options_.backbone_learning_rate));
    }
    progress_.random.seed(options_.seed);
    for (int i = 0; i < count_; ++i) {
      std::seed_seq seed{static_cast<std::uint64_t>(options_.seed), static_cast<std::uint64_t>(i)};
      progress_.environment_random.emplace_back(seed);
    }
    resume();
    // A frozen encoder is the same for the whole run: prepared once for inference.
    if (!options_.fine_tune) {
      frozen_encoder_ = std::make_unique<InferenceEncoder>(*policy_->backbone());
    }

    inputs_ =
        torch::zeros({count_, input_format_.channels(), input_format_.size, input_format_.size});
    rig_ = torch::zeros({count_, options_.policy.rigInputs()});
    move_histories_.assign(count_, MoveHistory(options_.policy.move_memory));
    scratch_.resize(count_);
    episodes_.resize(count_);
    features_ = torch::zeros({count_, policy_->backbone()->config().bottleneckChannels()});
    // One libtorch thread (the default): each environment's thread encodes its own observation
    // right after its step, so the two cores encode at once (a batch of one on one thread costs
    // what a batch of two does per frame, measured). With more threads, libtorch's own pool
    // does it on the trainer's thread, as one batch.
    encode_on_environment_threads_ = options_.threads == 1;
    environments_ = std::make_unique<VectorEnvironment>(
        count_, factory, [this](int i, const StepResult& result) { observe(i, result); });
  }

  PolicyNetwork run() {
    const int steps_per_env = (options_.steps_per_update + count_ - 1) / count_;
    const int feature_size = policy_->backbone()->config().bottleneckChannels();
    Rollout rollout;
    rollout.allocate(steps_per_env * count_, feature_size, options_.policy.rigInputs(),
                     input_format_, options_.fine_tune);
    for (int i = 0; i < count_; ++i) environments_->start(i, resetRequest(i));
    waitFor({0, count_});
    encodeInto({0, count_});

    const auto start = Clock::now();
    const std::int64_t start_steps = progress_.env_steps;
    if (callbacks_.on_start) callbacks_.on_start(start_steps);
    while (progress_.env_steps < options_.total_steps) {
      const torch::Tensor std = actionStd();
      ended_.clear();
      environment_seconds_ = inference_seconds_ = 0.0;
      collectRollout(steps_per_env, std, rollout);
      torch::Tensor last_values;
      {
        torch::NoGradGuard no_grad;
        last_values = policy_->value(features_, rig_);
      }
      const auto optimisation_start = Clock::now();
      setLibtorchThreads(options_.threads);
      PpoUpdate update = optimise(rollout, last_values, steps_per_env, std);
      update.optimisation_seconds = secondsSince(optimisation_start);
      update.environment_seconds = environment_seconds_;
      update.inference_seconds = inference_seconds_;
      ++progress_.updates;
      update.update = progress_.updates;
      update.env_steps = progress_.env_steps;
      update.episodes = progress_.episodes;
      // Directions have no sigma: the column is empty (NaN).
      update.action_std = options_.policy.isDirections() ? std::numeric_limits<double>::quiet_NaN()
                                                         : std.mean().item<double>();
      summariseEpisodes(update);
      update.seconds = secondsSince(start);
      update.steps_per_second = (progress_.env_steps - start_steps) / update.seconds;
      appendUpdate(update);
      if (callbacks_.on_update) callbacks_.on_update(update);
      if (progress_.updates % options_.checkpoint_every == 0) checkpoint();
    }
    checkpoint();
    nlohmann::json info = {{"trained_with", options_.toJson()},
                           {"env_steps", progress_.env_steps},
                           {"episodes", progress_.episodes},
                           {"updates", progress_.updates}};
    savePolicy(policy_, (fs::path(run_dir_) / "policy.pt").string(), info);
    return policy_;
  }

 private:
  // A contiguous range of environments that step together: [first, last).
  struct Group {
    int first = 0, last = 0;
  };

  // With overlap two groups (one for a single environment): while one group's environments
  // render, the trainer runs inference for the other, so the cores are not idle in turn.
  // Without: one group of all, stepped and encoded together.
  static std::vector<Group> groupsOf(int count, bool overlap) {
    if (count == 1 || !overlap) return {{0, count}};
    const int half = (count + 1) / 2;
    return {{0, half}, {half, count}};
  }

  // steps_per_env rounds of every environment into `rollout`. A group acts (samples its actions
  // and starts its steps), then the other group's last steps are waited for and read: the
  // inference of one group overlaps the rendering of the other. With two groups, inference runs
  // on one libtorch thread (the other cores render); the update gets options_.threads again.
  void collectRollout(int steps_per_env, const torch::Tensor& std, Rollout& rollout) {
    if (encode_on_environment_threads_ && !options_.overlap) {
      collectApart(steps_per_env, std, rollout);
      return;
    }
    const std::vector<Group> groups = groupsOf(count_, options_.overlap);
    if (groups.size() == 1) {
      for (int t = 0; t < steps_per_env; ++t) {
        act(t, groups[0], std, rollout);
        finishStep(t, groups[0], rollout);
      }
      return;
    }
    torch::set_num_threads(1);
    const Group &first = groups[0], &second = groups[1];
    for (int t = 0; t < steps_per_env; ++t) {
      act(t, first, std, rollout);
      if (t > 0) finishStep(t - 1, second, rollout);  // while the first group renders
      act(t, second, std, rollout);
      finishStep(t, first, rollout);  // while the second group renders
    }
    finishStep(steps_per_env - 1, second, rollout);
  }

  // Each environment's thread collects its own steps_per_env rows without waiting for the
  // others: it chooses its action from its features (encoded on the same thread, in observe()),
  // steps, books the step and, when the episode has ended, resets at once. A reset or a slow
  // step no longer holds the other environments back. The ended episodes are logged afterwards
  // in the order of the rounds they ended in, then of the environments: the order, step counts
  // and indices the rollout in rounds gives.
  void collectApart(int steps_per_env, const torch::Tensor& std, Rollout& rollout) {
    const std::int64_t first_step = progress_.env_steps;
    struct Ended {
      int round;
      PpoEpisode episode;
    };
    std::vector<std::vector<Ended>> ended(count_);
    std::vector<double> inference_seconds(count_, 0.0);
    const auto start = Clock::now();
    environments_->runOnEach([&](int i, EnvironmentInterface& environment) {
      torch::NoGradGuard no_grad;  // grad mode is per thread
      for (int t = 0; t < steps_per_env; ++t) {
        chooseActions(t, {i, i + 1}, std, rollout, inference_seconds[i]);
        const StepResult result = environment.step(move_histories_[i].last());
        observe(i, result);
        if (bookStep(t, i, result, rollout)) {
          ended[i].push_back({t, episodes_[i]});
          resetApart(i, environment);
        }
      }
    });
    // Each thread's inference is part of its round; the threads ran side by side.
    double inference = 0.0;
    for (const double seconds : inference_seconds) inference += seconds / count_;
    inference_seconds_ += inference;
    environment_seconds_ += secondsSince(start) - inference;
    std::vector<Ended> in_order;  // by round, then environment (stable: environments in turn)
    for (const auto& episodes : ended)
      in_order.insert(in_order.end(), episodes.begin(), episodes.end());
    std::stable_sort(in_order.begin(), in_order.end(),
                     [](const Ended& a, const Ended& b) { return a.round < b.round; });
    for (const Ended& e : in_order) {
      endEpisode(e.episode, first_step + std::int64_t(e.round + 1) * count_);
    }
    progress_.env_steps = first_step + std::int64_t(steps_per_env) * count_;
  }

  // On environment i's thread: a new episode, skipping seeds without a scene as waitFor() does.
  void resetApart(int i, EnvironmentInterface& environment) {
    for (int skipped = 0;; ++skipped) {
      const VectorRequest request = resetRequest(i);
      try {
        observe(i, environment.reset(request.seed, request.reset));
        return;
      } catch (const SceneGenerationError& error) {
        if (skipped >= kMaxSkippedSeeds) throw;
        reportSkippedSeed(request.seed, "environment " + std::to_string(i) + ": " + error.what());
      }
    }
  }

  // Samples the actions of `group` from the current features, stores row t of its environments
  // and starts their steps.
  void act(int t, const Group& group, const torch::Tensor& std, Rollout& rollout) {
    chooseActions(t, group, std, rollout, inference_seconds_);
    for (int i = group.first; i < group.last; ++i) {
      environments_->start(i, VectorRequest::stepBy(move_histories_[i].last()));
    }
  }

  // Samples the actions of `group` from the current features (each environment's noise from its
  // own stream), stores row t of its environments and their moves in move_histories_. Adds the
  // networks' time to `inference_seconds`.
  void chooseActions(int t, const Group& group, const torch::Tensor& std, Rollout& rollout,
                     double& inference_seconds) {
    const int n = group.last - group.first;
    const torch::Tensor features = features_.slice(0, group.first, group.last);
    const torch::Tensor rig = rig_.slice(0, group.first, group.last);
    torch::Tensor mean, log_probs, values;
    {
      const auto start = Clock::now();
      torch::NoGradGuard no_grad;
      if (options_.policy.isDirections()) {
        log_probs = policy_->directionLogProbabilities(features, rig);
      } else {
        mean = policy_->actionMean(features, rig);
      }
      values = policy_->value(features, rig);
      inference_seconds += secondsSince(start);
    }
    // A Gaussian's action is the move; a direction's is stored as its index k (the move u_k).
    torch::Tensor actions = torch::zeros({n, 2});
    torch::Tensor moves = actions;
    torch::Tensor action_log_probs;
    if (options_.policy.isDirections()) {
      moves = torch::empty({n, 2});
      action_log_probs = torch::empty({n});
      log_probs = log_probs.contiguous();
      auto vectors = policy_->directionVectors().accessor<float, 2>();
      auto out = actions.accessor<float, 2>();
      auto move = moves.accessor<float, 2>();
      auto chosen_log_prob = action_log_probs.accessor<float, 1>();
      std::uniform_real_distribution<double> uniform(0.0, 1.0);
      const int count = static_cast<int>(log_probs.size(1));
      for (int i = 0; i < n; ++i) {
        const float* row = log_probs.data_ptr<float>() + static_cast<std::ptrdiff_t>(i) * count;
        const int k =
            sampleDirection(row, count, uniform(progress_.environment_random[group.first + i]));
        out[i][0] = static_cast<float>(k);
        move[i][0] = vectors[k][0];
        move[i][1] = vectors[k][1];
        chosen_log_prob[i] = row[k];
      }
    } else {
      std::normal_distribution<float> noise(0.0f, 1.0f);
      auto in = mean.accessor<float, 2>();
      auto sigma = std.accessor<float, 1>();
      auto out = actions.accessor<float, 2>();
      for (int i = 0; i < n; ++i) {
        std::mt19937_64& random = progress_.environment_random[group.first + i];
        for (int k = 0; k < 2; ++k) out[i][k] = in[i][k] + sigma[k] * noise(random);
      }
      action_log_probs = gaussianLogProbability(actions, mean, std);
    }
    const auto rows = torch::indexing::Slice(t * count_ + group.first, t * count_ + group.last);
    rollout.features.index_put_({rows}, features);
    if (options_.fine_tune) {
      rollout.inputs.index_put_({rows}, inputs_.slice(0, group.first, group.last));
    }
    rollout.rig.index_put_({rows}, rig);
    rollout.actions.index_put_({rows}, actions);
    rollout.log_probs.index_put_({rows}, action_log_probs);
    rollout.values.index_put_({rows}, values);
    auto chosen = moves.accessor<float, 2>();
    for (int i = group.first; i < group.last; ++i) {
      move_histories_[i].push({chosen[i - group.first][0], chosen[i - group.first][1]});
    }
  }

  // Waits for the steps `group` started in round t, encodes what they show, books rewards and
  // ended episodes (bootstrapping truncations), and resets the ended environments.
  void finishStep(int t, const Group& group, Rollout& rollout) {
    waitFor(group);
    progress_.env_steps += group.last - group.first;
    encodeInto(group);
    bool any_ended = false;
    for (int i = group.first; i < group.last; ++i) {
      if (bookStep(t, i, environments_->result(i), rollout)) {
        endEpisode(episodes_[i], progress_.env_steps);
        environments_->start(i, resetRequest(i));
        any_ended = true;
      }
    }
    if (any_ended) {
      waitFor(group);
      encodeInto(group);
    }
  }

  // Books environment i's step of round t (its reward, bootstrapping a truncation, and whether
  // the episode ended) into the rollout and its episode; true when the episode has ended.
  bool bookStep(int t, int i, const StepResult& result, Rollout& rollout) {
    double reward = result.reward;
    PpoEpisode& episode = episodes_[i];
    episode.reward += result.reward;
    ++episode.steps;
    const bool ended = result.terminated || result.truncated;
    if (result.truncated && !result.terminated) {
      // Time ran out, not the task: bootstrap with the value of where the episode stopped.
      torch::NoGradGuard no_grad;
      reward +=
          options_.gamma *
          policy_->value(features_.slice(0, i, i + 1), rig_.slice(0, i, i + 1)).item<double>();
    }
    rollout.rewards.data_ptr<float>()[t * count_ + i] = static_cast<float>(reward);
    rollout.dones.data_ptr<float>()[t * count_ + i] = ended ? 1.0f : 0.0f;
    if (ended) episode.success = result.terminated;
    return ended;
  }

  // Logs an ended episode as the run's next, ended at `env_steps`.
  void endEpisode(PpoEpisode episode, std::int64_t env_steps) {
    episode.index = ++progress_.episodes;
    episode.env_steps = env_steps;
    appendEpisode(episode);
    ended_.push_back(episode);
    if (callbacks_.on_episode) callbacks_.on_episode(episode);
  }

  // Waits until every environment of `group` has answered. A training seed whose scene draws
  // give no occluded start view (Environment::reset's SceneGenerationError, rare) is skipped for
  // the next seed of the stream, as a data loader skips an unreadable sample, instead of ending a
  // long run.
  void waitFor(const Group& group) {
    const auto start = Clock::now();
    for (int i = group.first; i < group.last; ++i) {
      for (int skipped = 0;; ++skipped) {
        try {
          environments_->wait(i);
          break;
        } catch (const SceneGenerationError& error) {
          if (skipped >= kMaxSkippedSeeds) throw;
          reportSkippedSeed(episodes_[i].seed, error.what());  // names the environment
          environments_->start(i, resetRequest(i));
        }
      }
    }
    environment_seconds_ += secondsSince(start);
  }

  // The sigmas [2] this update's rollout samples with: the learned ones, or the schedule's.
  torch::Tensor actionStd() {
    if (options_.policy.learned_std) return policy_->logStd().detach().exp();
    const double done = std::min(1.0, double(progress_.env_steps) / double(options_.total_steps));
    return torch::full(
        {2}, options_.action_std + (options_.action_std_end - options_.action_std) * done);
  }

  std::uint64_t nextSeed(int i) {
    return std::uniform_int_distribution<std::uint64_t>(
        0, kFirstValidationSeed - 1)(progress_.environment_random[i]);
  }

  VectorRequest resetRequest(int i) {
    move_histories_[i].clear();
    episodes_[i] = PpoEpisode{};
    episodes_[i].environment = i;
    episodes_[i].seed = nextSeed(i);
    return VectorRequest::resetTo(episodes_[i].seed, reset_);
  }

  // On environment i's thread: its observation into batch row i.
  void observe(int i, const StepResult& result) {
    const std::size_t plane = static_cast<std::size_t>(input_format_.channels()) *
                              input_format_.size * input_format_.size;
    writeNetworkInput(result.observation->rgb, result.observation->depth, result.info.intrinsics,
                      input_format_.atRadius(cameraRadius(result.info.world_from_optical)),
                      scratch_[i], inputs_.data_ptr<float>() + i * plane);
    move_histories_[i].writeRigInput(result.info.pose.elevation_rad,
                                     rig_.data_ptr<float>() + i * options_.policy.rigInputs());
    if (encode_on_environment_threads_) {
      torch::NoGradGuard no_grad;  // grad mode is per thread
      features_.slice(0, i, i + 1).copy_(featuresOf(inputs_.slice(0, i, i + 1)));
    }
  }

  // The encoder's features of `inputs`, without gradient: the frozen encoder's snapshot, or the
  // encoder being fine-tuned.
  torch::Tensor featuresOf(const torch::Tensor& inputs) {
    return frozen_encoder_ ? frozen_encoder_->encode(inputs) : policy_->features(inputs);
  }

  // The encoder's features of the observations of environments [first, last). With overlap and
  // a fine-tuned encoder a single observation goes in twice: libtorch 1.13 runs batches of one
  // through its slower native convolutions (im2col + BLAS), larger ones through oneDNN.
  torch::Tensor encode(int first, int last) {
    const auto start = Clock::now();
    torch::NoGradGuard no_grad;
    const torch::Tensor inputs = inputs_.slice(0, first, last);
    torch::Tensor features = options_.overlap && last - first == 1 && !frozen_encoder_
                                 ? policy_->features(inputs.repeat({2, 1, 1, 1})).slice(0, 0, 1)
                                 : featuresOf(inputs);
    inference_seconds_ += secondsSince(start);
    return features;
  }

  // The features of `group`'s observations, unless their own threads encoded them.
  void encodeInto(const Group& group) {
    if (encode_on_environment_threads_) return;
    features_.slice(0, group.first, group.last).copy_(encode(group.first, group.last));
  }

  // Generalised advantage estimates over each environment's time line of the rollout.
  torch::Tensor advantagesOf(const Rollout& rollout, const torch::Tensor& last_values,
                             int steps_per_env) const {
    torch::Tensor advantages = torch::zeros({steps_per_env * count_});
    auto values = rollout.values.accessor<float, 1>();
    auto rewards = rollout.rewards.accessor<float, 1>();
    auto dones = rollout.dones.accessor<float, 1>();
    auto last = last_values.accessor<float, 1>();
    auto out = advantages.accessor<float, 1>();
    for (int i = 0; i < count_; ++i) {
      double gae = 0.0;
      for (int t = steps_per_env - 1; t >= 0; --t) {
        const int row = t * count_ + i;
        const double next_value =
            dones[row] > 0.5f ? 0.0 : (t + 1 < steps_per_env ? values[row + count_] : last[i]);
        const double delta = rewards[row] + options_.gamma * next_value - values[row];
        gae = delta + (dones[row] > 0.5f ? 0.0 : options_.gamma * options_.gae_lambda * gae);
        out[row] = static_cast<float>(gae);
      }
    }
    return advantages;
  }

  // What one minibatch's step reports: the approximate KL, the fraction clipped, the losses.
  struct MinibatchFigures {
    double kl = 0.0, clip_fraction = 0.0, policy_loss = 0.0, value_loss = 0.0, entropy = 0.0;
  };

  // What a minibatch step trains. With the encoder frozen, actor and critic share no parameter
  // and each one's gradient comes from its own loss alone, so the two steps are independent: the
  // same arithmetic whether they run together or apart.
  enum class Part { kAll, kActor, kCritic };

  // One gradient step of `part` (kAll: actor, critic and, when fine-tuned, the backbone) on the
  // rows `index`; the figures of the parts it trained.
  MinibatchFigures optimiseMinibatch(Rollout& rollout, const torch::Tensor& advantages,
                                     const torch::Tensor& returns, const torch::Tensor& index,
                                     const torch::Tensor& rollout_std, Part part) {
    const bool actor = part != Part::kCritic, critic = part != Part::kActor;
    const torch::Tensor features = options_.fine_tune
                                       ? policy_->features(rollout.inputs.index_select(0, index))
                                       : rollout.features.index_select(0, index);
    const torch::Tensor rig = rollout.rig.index_select(0, index);
    torch::Tensor policy_loss, value_loss, log_ratio, ratio, entropy;
    if (actor) {
      // A learned sigma is the one being trained (with the entropy bonus's gradient); a
      // scheduled one stays the rollout's.
      const torch::Tensor std = options_.policy.learned_std ? policy_->logStd().exp() : rollout_std;
      const torch::Tensor actions = rollout.actions.index_select(0, index);
      torch::Tensor log_prob;
      if (options_.policy.isDirections()) {
        const torch::Tensor log_probs = policy_->directionLogProbabilities(features, rig);
        log_prob =
            log_probs.gather(1, actions.select(1, 0).to(torch::kLong).unsqueeze(1)).squeeze(1);
        entropy = -(log_probs.exp() * log_probs).sum(1).mean();
      } else {
        log_prob = gaussianLogProbability(actions, policy_->actionMean(features, rig), std);
        entropy = gaussianEntropy(std);
      }
      log_ratio = log_prob - rollout.log_probs.index_select(0, index);
      ratio = log_ratio.exp();
      const torch::Tensor advantage = advantages.index_select(0, index);
      const torch::Tensor surrogate = torch::min(
          ratio * advantage,
          ratio.clamp(1.0 - options_.clip_epsilon, 1.0 + options_.clip_epsilon) * advantage);
      policy_loss = -surrogate.mean() - options_.entropy_coefficient * entropy;
    }
    if (critic) {
      const torch::Tensor value_error =
          policy_->value(features, rig) - returns.index_select(0, index);
      value_loss = 0.5 * (value_error * value_error).mean();
    }

    if (actor) actor_optimizer_->zeroGrad();
    if (critic) critic_optimizer_->zeroGrad();
    if (backbone_optimizer_) backbone_optimizer_->zero_grad();
    (actor && critic ? policy_loss + value_loss : actor ? policy_loss : value_loss).backward();
    // Each part's gradient is clipped to the norm on its own, then stepped.
    if (actor) actor_optimizer_->step(options_.max_grad_norm);
    if (critic) critic_optimizer_->step(options_.max_grad_norm);
    if (backbone_optimizer_) {
      if (options_.max_grad_norm > 0) {
        torch::nn::utils::clip_grad_norm_(policy_->backbone()->parameters(),
                                          options_.max_grad_norm);
      }
      backbone_optimizer_->step();
    }

    torch::NoGradGuard no_grad;
    MinibatchFigures figures;
    if (actor) {
      figures.kl = ((ratio - 1.0) - log_ratio).mean().item<double>();
      figures.clip_fraction =
          ((ratio - 1.0).abs() > options_.clip_epsilon).to(torch::kFloat).mean().item<double>();
      figures.policy_loss = policy_loss.item<double>();
      figures.entropy = entropy.item<double>();
    }
    if (critic) figures.value_loss = value_loss.item<double>();
    return figures;
  }

  // One epoch's minibatches (the rows of `order` [rows], in turn) of `part`, their figures in
  // order.
  std::vector<MinibatchFigures> optimiseEpoch(Rollout& rollout, const torch::Tensor& advantages,
                                              const torch::Tensor& returns,
                                              const torch::Tensor& order, int minibatch,
                                              const torch::Tensor& std, Part part) {
    std::vector<MinibatchFigures> figures;
    for (int64_t first = 0; first + minibatch <= order.size(0); first += minibatch) {
      const torch::Tensor index = order.slice(0, first, first + minibatch);
      figures.push_back(optimiseMinibatch(rollout, advantages, returns, index, std, part));
    }
    return figures;
  }

  // PPO's epochs over the rollout in shuffled minibatches (stopped early past 1.5 target_kl).
  PpoUpdate optimise(Rollout& rollout, const torch::Tensor& last_values, int steps_per_env,
                     const torch::Tensor& std) {
    const int rows = steps_per_env * count_;
    torch::Tensor advantages = advantagesOf(rollout, last_values, steps_per_env);
    const torch::Tensor returns = advantages + rollout.values;
    if (options_.normalize_advantages) {
      advantages = (advantages - advantages.mean()) / (advantages.std() + 1e-8);
    }

    PpoUpdate update;
    std::vector<int64_t> order(rows);
    std::iota(order.begin(), order.end(), 0);
    const int minibatch = std::min(options_.minibatch_size, rows);
    MinibatchFigures sum;
    int batches = 0;
    // With the encoder frozen and one libtorch thread, the critic's steps run on a second thread
    // while this one runs the actor's: both cores work, and the arithmetic is the same.
    const bool actor_and_critic_apart = !options_.fine_tune && options_.threads == 1;
    for (int epoch = 0; epoch < options_.epochs; ++epoch) {
      std::shuffle(order.begin(), order.end(), progress_.random);
      const torch::Tensor epoch_order = torch::tensor(order, torch::kLong);  // minibatches slice it
      std::vector<MinibatchFigures> epoch_figures;
      if (actor_and_critic_apart) {
        std::vector<MinibatchFigures> critic_figures;
        std::exception_ptr critic_error;
        std::thread critic_thread([&] {
          try {
            critic_figures = optimiseEpoch(rollout, advantages, returns, epoch_order, minibatch,
                                           std, Part::kCritic);
          } catch (...) {
            critic_error = std::current_exception();
          }
        });
        try {
          epoch_figures = optimiseEpoch(rollout, advantages, returns, epoch_order, minibatch, std,
                                        Part::kActor);
        } catch (...) {
          critic_thread.join();
          throw;
        }
        critic_thread.join();
        if (critic_error) std::rethrow_exception(critic_error);
        for (std::size_t b = 0; b < epoch_figures.size(); ++b) {
          epoch_figures[b].value_loss = critic_figures[b].value_loss;
        }
      } else {
        epoch_figures =
            optimiseEpoch(rollout, advantages, returns, epoch_order, minibatch, std, Part::kAll);
      }
      double epoch_kl = 0.0;
      int epoch_batches = 0;
      for (const MinibatchFigures& figures : epoch_figures) {
        epoch_kl += figures.kl;
        ++epoch_batches;
        sum.kl += figures.kl;
        sum.clip_fraction += figures.clip_fraction;
        sum.policy_loss += figures.policy_loss;
        sum.value_loss += figures.value_loss;
        sum.entropy += figures.entropy;
        ++batches;
      }
      update.epochs_run = epoch + 1;
      if (options_.target_kl > 0 && epoch_batches > 0 &&
          epoch_kl / epoch_batches > 1.5 * options_.target_kl) {
        break;
      }
    }
    update.policy_loss = sum.policy_loss / std::max(1, batches);
    update.value_loss = sum.value_loss / std::max(1, batches);
    update.approx_kl = sum.kl / std::max(1, batches);
    // The Gaussian's at the rollout's sigma; the directions' over the update's minibatches.
    update.entropy = options_.policy.isDirections() ? sum.entropy / std::max(1, batches)
                                                    : gaussianEntropy(std).item<double>();
    update.clip_fraction = sum.clip_fraction / std::max(1, batches);
    const double return_variance = returns.var().item<double>();
    update.explained_variance =
        return_variance > 0
            ? 1.0 - (returns - rollout.values).var().item<double>() / return_variance
            : std::numeric_limits<double>::quiet_NaN();
    return update;
  }

  void summariseEpisodes(PpoUpdate& update) const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    update.mean_episode_reward = update.mean_episode_steps = update.success_rate = nan;
    if (ended_.empty()) return;
    double reward = 0.0, steps = 0.0, successes = 0.0;
    for (const auto& e : ended_) {
      reward += e.reward;
      steps += e.steps;
      successes += e.success ? 1.0 : 0.0;
    }
    update.mean_episode_reward = reward / ended_.size();
    update.mean_episode_steps = steps / ended_.size();
    update.success_rate = successes / ended_.size();
  }

  void appendEpisode(const PpoEpisode& e) {
    std::ostringstream out;
    out << e.index << ',' << e.env_steps << ',' << e.environment << ',' << e.seed << ',' << e.reward
        << ',' << e.steps << ',' << (e.success ? 1 : 0) << '\n';
    appendTextFile((fs::path(run_dir_) / kEpisodesCsv).string(), out.str());
  }

  void appendUpdate(const PpoUpdate& u) {
    std::ostringstream out;
    out << u.update << ',' << u.env_steps << ',' << u.episodes << ',' << u.action_std << ','
        << u.policy_loss << ',' << u.value_loss << ',' << u.entropy << ',' << u.approx_kl << ','
        << u.clip_fraction << ',' << u.explained_variance << ',' << u.epochs_run << ','
        << u.mean_episode_reward << ',' << u.mean_episode_steps << ',' << u.success_rate << ','
        << u.steps_per_second << ',' << u.seconds << ',' << u.environment_seconds << ','
        << u.inference_seconds << ',' << u.optimisation_seconds << '\n';
    appendTextFile((fs::path(run_dir_) / "updates.csv").string(), out.str());
  }

  void checkpoint() {
    const fs::path dir(run_dir_);
    torch::serialize::OutputArchive archive, model, actor, critic, backbone;
    policy_->save(model);
    actor_optimizer_->save(actor);
    critic_optimizer_->save(critic);
    archive.write("policy", model);
    archive.write("actor_optimizer", actor);
    archive.write("critic_optimizer", critic);
    if (backbone_optimizer_) {
      backbone_optimizer_->save(backbone);
      archive.write("backbone_optimizer", backbone);
    }
    archive.save_to((dir / "checkpoint.pt.tmp").string());
    nlohmann::json environment_random = nlohmann::json::array();
    for (const auto& stream : progress_.environment_random) {
      environment_random.push_back(streamText(stream));
    }
    const nlohmann::json state = {
        {"options", resumeKey(options_)},         {"updates", progress_.updates},
        {"env_steps", progress_.env_steps},       {"episodes", progress_.episodes},
        {"random", streamText(progress_.random)}, {"environment_random", environment_random}};
    {
      std::ofstream out(dir / "checkpoint.json.tmp");
      out << state.dump(2) << '\n';
      if (!out) throw std::runtime_error("cannot write " + (dir / "checkpoint.json.tmp").string());
    }
    fs::rename(dir / "checkpoint.pt.tmp", dir / "checkpoint.pt");
    fs::rename(dir / "checkpoint.json.tmp", dir / "checkpoint.json");
  }

  void resume() {
    const fs::path dir(run_dir_);
    if (!fs::exists(dir / "checkpoint.pt") || !fs::exists(dir / "checkpoint.json")) {
      trimCsv(dir / kEpisodesCsv, kEpisodeHeader, 0);
      trimCsv(dir / "updates.csv", kUpdateHeader, 0);
      return;
    }
    readCheckpoint(run_dir_, [&] {
      std::ifstream in(dir / "checkpoint.json");
      const nlohmann::json state = nlohmann::json::parse(in);
      nlohmann::json stored = state.at("options");
      // Checkpoints from before the overlap option collected without overlap.
      if (!stored.contains("overlap")) stored["overlap"] = false;
      if (stored != resumeKey(options_)) {
        throw InvalidArgumentError("the checkpoint in " + run_dir_ +
                                   " was made with other options (" + stored.dump() +
                                   "): use another run directory or the same options");
      }
      torch::serialize::InputArchive archive, model, actor, critic;
      archive.load_from((dir / "checkpoint.pt").string());
      archive.read("policy", model);
      archive.read("actor_optimizer", actor);
      archive.read("critic_optimizer", critic);
      readParameters(*policy_, model, (dir / "checkpoint.pt").string(), "the policy being trained");
      actor_optimizer_->load(actor);
      critic_optimizer_->load(critic);
      if (backbone_optimizer_) {
        torch::serialize::InputArchive backbone;
        archive.read("backbone_optimizer", backbone);
        backbone_optimizer_->load(backbone);
      }
      progress_.updates = state.at("updates").get<int>();
      progress_.env_steps = state.at("env_steps").get<std::int64_t>();
      progress_.episodes = state.at("episodes").get<std::int64_t>();
      readStream(state.at("random").get<std::string>(), progress_.random);
      // Checkpoints from before the environments had streams of their own, or of another count of
      // environments, keep the streams the seed gives.
      const nlohmann::json& streams = state.value("environment_random", nlohmann::json::array());
      if (streams.size() == progress_.environment_random.size()) {
        for (std::size_t i = 0; i < streams.size(); ++i) {
          readStream(streams[i].get<std::string>(), progress_.environment_random[i]);
        }
      }
    });
    trimCsv(dir / kEpisodesCsv, kEpisodeHeader, progress_.episodes);
    trimCsv(dir / "updates.csv", kUpdateHeader, progress_.updates);
  }

  PpoOptions options_;
  int count_;
  ResetOptions reset_;
  std::string run_dir_;
  PpoCallbacks callbacks_;
  InputFormat input_format_;  // the pretrained network's
  PolicyNetwork policy_{nullptr};
  std::unique_ptr<FlatAdam> actor_optimizer_, critic_optimizer_;
  std::unique_ptr<torch::optim::Adam> backbone_optimizer_;  // when fine-tuned
  Progress progress_;
  torch::Tensor inputs_, rig_;  // the current observations, row i = environment i
  torch::Tensor features_;      // the encoder's features of inputs_, row i = environment i
  std::unique_ptr<InferenceEncoder> frozen_encoder_;  // unless the encoder is fine-tuned
  bool encode_on_environment_threads_ = false;  // observe() fills features_ (one libtorch thread)
  // Environment i's moves this episode: its rig input; the newest is what it steps by next.
  std::vector<MoveHistory> move_histories_;
  std::vector<InputScratch> scratch_;
  std::vector<PpoEpisode> episodes_;  // in flight, per environment
  std::vector<PpoEpisode> ended_;     // in this update
  std::unique_ptr<VectorEnvironment> environments_;
  double environment_seconds_ = 0.0, inference_seconds_ = 0.0;  // in the current update
};

}  // namespace

PolicyNetwork trainPpo(const PpoOptions& options, int environment_count,
                       const VectorEnvironment::Factory& factory, const ResetOptions& reset,
                       const std::string& run_dir, const PpoCallbacks& callbacks) {
  setLibtorchThreads(options.threads);
  torch::manual_seed(options.seed);
  PpoTrainer trainer(options, environment_count, factory, reset, run_dir, callbacks);
  return trainer.run();
}

}  // namespace learning
}  // namespace occlusion_env
