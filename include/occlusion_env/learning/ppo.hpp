// PPO (Section 5.3, Table 2) for the policy of learning/policy.hpp on N environments stepped
// together (env/vector_environment.hpp): in process or simulators reached over ROS.
//
// One update: every environment steps ceil(steps_per_update / N) times with actions drawn from
// N(mean, action_std^2). With one libtorch thread (the default) each environment's thread
// encodes its observation, chooses its action and steps on its own; with more, the environments
// step in rounds and their observations are batched for one encoder pass. Either way each
// environment draws its action noise and scene seeds from its own stream, so both give the same
// episodes. Episodes that end are reset at once with the environment's next training seed
// (< kFirstValidationSeed); a truncated episode's last value is bootstrapped. Then GAE (lambda = 1
// gives the Monte-Carlo returns of the paper's code), normalised advantages and `epochs` passes of
// clipped-surrogate minibatch updates, stopped early when the approximate KL exceeds 1.5 *
// target_kl. Frozen encoder by default: its features are computed once per step and cached; with
// fine_tune the images are kept and re-encoded.
//
// Run directory: training_episodes.csv, updates.csv, checkpoint.pt/.json (every checkpoint_every
// updates and at the end; re-running the same command resumes: the episodes in flight are
// restarted), policy.pt/.json (the final policy, for the agents).
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "occlusion_env/env/vector_environment.hpp"
#include "occlusion_env/learning/policy.hpp"

namespace occlusion_env {
namespace learning {

struct PpoOptions {
  std::string backbone_path;      // the pretrained multi-task network (.pt + .json)
  bool actor_from_escape = true;  // start the actor at the network's escape head
  bool fine_tune = false;         // train the encoder too (with backbone_learning_rate)
  // With 2+ environments, half of them render while the trainer runs inference for the other
  // half, on one libtorch thread (the same algorithm, another order of the random draws); off:
  // all step, then all are encoded as one batch (BENCHMARKS.md, "PPO training").
  bool overlap = false;
  PolicyConfig policy;
  std::string reward = "union";  // what the environments were set up with (recorded only)

  std::int64_t total_steps = 50000;  // environment steps, all environments together
  int steps_per_update = 200;        // N_u
  int epochs = 80;                   // K, the most passes over one update's steps
  int minibatch_size = 50;
  double actor_learning_rate = 3e-4;
  double critic_learning_rate = 1e-3;
  double backbone_learning_rate = 1e-5;
  double gamma = 0.99;
  double gae_lambda = 0.95;
  double clip_epsilon = 0.2;
  double action_std = 0.6;      // sigma at the start
  double action_std_end = 0.6;  // sigma at the end (linear in steps)
  double entropy_coefficient = 0.0;
  double max_grad_norm = 0.5;  // 0 = no clipping
  double target_kl = 0.02;     // 0 = all epochs
  bool normalize_advantages = true;

  std::uint64_t seed = 1;
  // libtorch threads; 0 = the machine's cores. One by default: the networks' work at 64 px is
  // small, and two threads that must meet at every operation stall whenever another process
  // has one of the cores (BENCHMARKS.md, "PPO training").
  int threads = 1;
  int checkpoint_every = 10;  // updates

  /// Throws InvalidArgumentError naming the first bad option (the tables' ranges and choices,
  /// then a backbone is required).
  void validate() const;
  /// What a run records (resume key, policy manifests' "trained_with"): every option by its table
  /// name, the policy as "policy"; threads and checkpoint_every (how, not what) left out.
  nlohmann::json toJson() const;
};

/// The declared options of PpoOptions but the policy (policyConfigTable()), by their manifest
/// names; the flags are occlusion_train_ppo's (actor_from_escape has none: --actor-init there).
const OptionTable<PpoOptions>& ppoOptionTable();

/// The paper's Table 2 recipe where ours differs: actor from random weights, no rig inputs,
/// free-length mean, lambda 1, minibatch 200, no KL stop, no gradient clipping.
void applyPaperRecipe(PpoOptions& options);

struct PpoEpisode {
  std::int64_t index = 0;      // 1-based, over the run
  std::int64_t env_steps = 0;  // when it ended
  int environment = 0;
  std::uint64_t seed = 0;
  double reward = 0.0;  // undiscounted return
  int steps = 0;
  bool success = false;  // terminated (unoccluded), not truncated
};

struct PpoUpdate {
  int update = 0;  // 1-based
  std::int64_t env_steps = 0;
  std::int64_t episodes = 0;
  double action_std = 0.0;
  double policy_loss = 0.0;
  double value_loss = 0.0;
  double entropy = 0.0;
  double approx_kl = 0.0;
  double clip_fraction = 0.0;
  double explained_variance = 0.0;
  int epochs_run = 0;
  double mean_episode_reward = 0.0;  // of the episodes that ended in this update (NaN if none)
  double mean_episode_steps = 0.0;
  double success_rate = 0.0;
  double steps_per_second = 0.0;  // environment steps, including inference and the update
  // Where this update's wall time went [s]: waiting for the environments to step and reset
  // (including the observations' conversion on their threads and, with one libtorch thread,
  // their encoding there too, and the heads' passes there less their mean share, counted as
  // inference; with overlap one half renders while the trainer runs inference for
  // the other, and only the wait that this does not hide counts), the network's forward passes
  // on the trainer's thread while collecting, and the optimisation.
  double environment_seconds = 0.0;
  double inference_seconds = 0.0;
  double optimisation_seconds = 0.0;
  double seconds = 0.0;  // since the run (or its resumption) started
};

struct PpoCallbacks {
  /// Before the first update: the environment steps done already (a resumed run; 0 when new).
  std::function<void(std::int64_t env_steps)> on_start;
  std::function<void(const PpoEpisode&)> on_episode;
  std::function<void(const PpoUpdate&)> on_update;
};

/// Trains in `run_dir` on `environment_count` environments made by `factory` (each on its own
/// thread). `reset` is applied at every reset. Returns the final policy (also in
/// run_dir/policy.pt).
PolicyNetwork trainPpo(const PpoOptions& options, int environment_count,
                       const VectorEnvironment::Factory& factory, const ResetOptions& reset,
                       const std::string& run_dir, const PpoCallbacks& callbacks = {});

}  // namespace learning
}  // namespace occlusion_env
