// The PPO policy of Section 5.3 (Agent-UN / Agent-IN): actor and critic heads on the pooled
// encoder features of a pretrained multi-task network (learning/multitask_unet.hpp), a Gaussian
// action on the (azimuth, elevation) plane. Besides the image the heads see what a real rig knows
// of itself: the directions of its last moves and its elevation; never masks, the gradient or the
// scene.
//
// Policy inputs, written once:
//   features [B, C]       the backbone's encode() of the RGB-D input (network_input.hpp)
//   rig      [B, 2m + 1]  for each of the last m = PolicyConfig::move_memory moves, newest first,
//                         (cos, sin) of its direction theta = atan2(d_el, d_az), (0, 0) before
//                         the episode has made it; then the camera's elevation / (pi / 2)
// Actor: mean action (d_azimuth, d_elevation) = body(features) + rig_term(rig) (scaled to unit
// length with unit_mean), where body has
// the escape head's shape (Linear -> ReLU -> Linear) so that it can start as the escape head
// (its (sin, cos) rows swapped into (d_az, d_el)) and rig_term starts at zero. The environment
// normalises every action to one unit step, so only the mean's direction moves the camera.
// Critic: Linear -> Tanh -> Linear -> Tanh -> Linear on [features, rig].
//
// Two action distributions (PolicyConfig::action):
//   gaussian    a 2-D Gaussian about the mean action, sigma scheduled or learned (the paper's);
//   directions  a categorical over K unit moves u_k at angles 2 pi k / K in the (d_azimuth,
//               d_elevation) plane: logits_k = kappa * (u_k . mean action) +
//               correction_k([features, rig]), the correction a Linear layer starting at zero. The
//               environment moves one unit step whatever the action's length, so only a direction
//               is chosen; a short mean (an unsure escape head) gives a broad distribution, a long
//               one a sharp one, and the entropy bonus acts on it. The deterministic action is the
//               distribution's circular mean, sum_k p_k u_k, which at the start points where the
//               escape head does.
#pragma once

#include <torch/torch.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/learning/inference_encoder.hpp"
#include "occlusion_env/learning/multitask_unet.hpp"
#include "occlusion_env/learning/network_input.hpp"

namespace occlusion_env {
namespace learning {

struct PolicyConfig {
  int hidden = 64;         // width of the actor body's and the critic's hidden layers
  bool rig_inputs = true;  // false: the heads see the image features alone (the paper's)
  /// How many of the rig's last moves the heads see (issue 28: memory, so that a policy can tell
  /// it is oscillating); 1 is the last move alone, as policies before the option.
  int move_memory = 1;
  /// The mean action scaled to unit length, so that sigma alone sets how far samples stray from
  /// it (the environment moves one unit step whatever the length: with a free length a policy
  /// can outgrow its noise instead of improving its direction). false (the paper's, and on our
  /// validation scenes the better one, doc/PPO.md): the mean's length is free.
  bool unit_mean = false;
  /// Sigma a trained parameter (log sigma per action axis, starting at PPO's action_std), so that
  /// the entropy bonus has a gradient. false: sigma follows PPO's fixed schedule (action_std to
  /// action_std_end), under which the entropy term changes only the reported loss.
  bool learned_std = false;
  std::string action = "gaussian";       // gaussian | directions (above)
  int directions = 32;                   // K, with action directions
  double direction_concentration = 8.0;  // kappa, with action directions

  bool isDirections() const { return action == "directions"; }
  /// The width of the rig inputs (above): 2 * move_memory + 1.
  int rigInputs() const { return 2 * move_memory + 1; }
  /// Throws InvalidArgumentError naming the first option out of its declared range.
  void validate() const;
  /// Every field by its table name (the "policy" of policy manifests).
  nlohmann::json toJson() const;
  /// Refuses unknown names; a missing field keeps its default (unit_mean: policies from before
  /// the option have the free length, as the default).
  static PolicyConfig fromJson(const nlohmann::json& json);
};

/// The declared fields of PolicyConfig (flags --no-rig, --unit-mean; hidden has none).
const OptionTable<PolicyConfig>& policyConfigTable();

class PolicyNetworkImpl : public torch::nn::Module {
 public:
  PolicyNetworkImpl(const NetworkConfig& backbone, const PolicyConfig& config);

  /// The backbone's pooled encoder features of `input` [B, C, S, S] -> [B, C].
  torch::Tensor features(const torch::Tensor& input);
  /// Mean action [B, 2] = (d_azimuth, d_elevation): the Gaussian's mean, or the directions'
  /// circular mean (what the agent does).
  torch::Tensor actionMean(const torch::Tensor& features, const torch::Tensor& rig);
  /// With action directions: log-probabilities [B, K] of the unit moves directionVectors().
  torch::Tensor directionLogProbabilities(const torch::Tensor& features, const torch::Tensor& rig);
  /// With action directions: the unit moves u_k [K, 2] = (cos, sin) of 2 pi k / K.
  const torch::Tensor& directionVectors() const { return direction_vectors_; }
  /// State value [B].
  torch::Tensor value(const torch::Tensor& features, const torch::Tensor& rig);
  /// log sigma [2] of the action, a trained parameter; only with config().learned_std.
  torch::Tensor& logStd();

  /// Copies `network`'s encoder (all of it, for the features) and, when `actor_from_escape`,
  /// its escape head into the actor body.
  void initialiseFrom(MultiTaskUNet& network, bool actor_from_escape);

  MultiTaskUNet& backbone() { return backbone_; }
  /// The actor body's, the rig term's and, with learned_std, log sigma.
  std::vector<torch::Tensor> actorParameters();
  std::vector<torch::Tensor> criticParameters();
  const PolicyConfig& config() const { return config_; }

 private:
  torch::Tensor rigOrZero(const torch::Tensor& rig);
  /// The body's and rig term's mean, before unit_mean's scaling.
  torch::Tensor rawMean(const torch::Tensor& features, const torch::Tensor& rig);

  PolicyConfig config_;
  MultiTaskUNet backbone_{nullptr};
  torch::nn::Sequential actor_body_{nullptr};
  torch::nn::Linear actor_rig_{nullptr};
  torch::nn::Sequential critic_{nullptr};
  torch::Tensor log_std_;                        // [2], registered with learned_std only
  torch::nn::Linear actor_directions_{nullptr};  // the logits' correction, with directions only
  torch::Tensor direction_vectors_;              // [K, 2], with directions only
};
TORCH_MODULE(PolicyNetwork);

/// The direction k in [0, count) that a uniform draw `uniform` in [0, 1) picks from the
/// log-probabilities `log_probs` (inverse transform sampling).
int sampleDirection(const float* log_probs, int count, double uniform);

/// The rig's last moves, newest first, as the rig inputs show them (the top of this file): a ring
/// of fixed length, so that recording a move allocates nothing.
class MoveHistory {
 public:
  explicit MoveHistory(int length = 1);
  /// Forgets every move (an episode's start).
  void clear();
  /// Records the move just made.
  void push(const Action& move);
  /// The newest move (a zero move before the first).
  const Action& last() const { return moves_[newest_]; }
  /// The rig inputs of one step into `out` (2 * length + 1 floats).
  void writeRigInput(double elevation_rad, float* out) const;

 private:
  std::vector<Action> moves_;  // moves_[newest_] the last, then backwards around the ring
  int newest_ = 0;
};

/// A policy on disk: `<name>.pt` beside `<name>.json` (kind "ppo_policy", the backbone's
/// NetworkConfig, the PolicyConfig, how it was trained, its metrics).
void savePolicy(PolicyNetwork& policy, const std::string& path, const nlohmann::json& info);

struct LoadedPolicy {
  PolicyNetwork network{nullptr};
  nlohmann::json manifest;
};

/// Loads a policy saved by savePolicy(), in eval mode. Throws InvalidArgumentError for a missing,
/// corrupt or mismatched file, or a file that is not a policy.
LoadedPolicy loadPolicy(const std::string& path);

/// Acts with the policy's mean action (deterministic), or with `sampled` an action drawn from its
/// distribution as in training (the directions' categorical; the Gaussian's with its learned
/// sigma, or the sigma its training ended with), from a stream seeded by the scene's seed so that
/// an episode repeats itself. Allocates nothing per step once sized.
class PolicyAgent : public Agent {
 public:
  explicit PolicyAgent(std::shared_ptr<LoadedPolicy> policy, bool sampled = false);
  void reset(std::uint64_t seed) override;
  Action act(const RigObservation& observation) override;

 private:
  std::shared_ptr<LoadedPolicy> policy_;
  std::unique_ptr<InferenceEncoder> encoder_;  // the backbone's, prepared for inference
  bool sampled_;
  double sigma_[2] = {0.0, 0.0};  // the Gaussian's per axis, when sampled
  std::mt19937_64 random_;
  InputFormat input_format_;  // the backbone's (its radius set per view)
  InputScratch scratch_;
  torch::Tensor input_, rig_;
  MoveHistory moves_;
};

/// The shipped policies (models/policy_un.pt, models/policy_in.pt) and the generic entry that
/// runs any policy file given by path.
AgentEntry policyUnAgentEntry();
AgentEntry policyInAgentEntry();
AgentEntry policyAgentEntry();
/// Any policy file by path, its actions sampled (PolicyAgent's `sampled`).
AgentEntry policySampledAgentEntry();

}  // namespace learning
}  // namespace occlusion_env
