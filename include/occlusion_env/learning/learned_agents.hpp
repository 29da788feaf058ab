// Agents that see only the RGB-D image and move where the multi-task network says: the paper's
// predicted-gradient agent (Pred. Grad) and ours, the predicted-escape agent (the direction of
// the oracle's first step, which does not lead into the local minima that trap the gradient).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "occlusion_env/agents/agent_registry.hpp"
#include "occlusion_env/agents/elevation_limit.hpp"
#include "occlusion_env/agents/revisit_guard.hpp"
#include "occlusion_env/learning/inference_encoder.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/network_input.hpp"

namespace occlusion_env {
namespace learning {

enum class DirectionHead { kGradient, kEscape };

/// Moves one unit step along the direction the network's `head` predicts for the current image.
/// With an escape-bins head the escape direction is the head's best bin, leaning towards the
/// rig's last move (escapeDirectionFromLogits with a bias of cos(theta_k - theta_last)).
/// The escape agent (not the paper's predicted-gradient agent) also reads the rig's own path:
/// where the rig stopped its last move at an elevation limit (a floor: ElevationLimitTracker), a
/// direction further that way turns along the limit, and a move that would land back on one of
/// its last views turns aside (RevisitGuard), so that it neither pushes into a floor nor swings
/// between two views until the step limit. Inference allocates nothing once the first observation
/// has sized its buffers.
class NetworkDirectionAgent : public Agent {
 public:
  NetworkDirectionAgent(std::shared_ptr<LoadedModel> model, DirectionHead head);
  void reset(std::uint64_t seed) override;
  Action act(const RigObservation& observation) override;

 private:
  std::shared_ptr<LoadedModel> model_;
  std::unique_ptr<InferenceEncoder> encoder_;  // the model's encoder, prepared for inference
  DirectionHead head_;
  InputFormat input_format_;  // the model's (its radius set per view)
  InputScratch scratch_;
  torch::Tensor input_;
  torch::Tensor bin_angles_;  // [1, escape_bins] [rad], with an escape-bins head
  ElevationLimitTracker elevation_limit_;
  RevisitGuard recent_views_;
};

/// The shipped model the learned agents use by default in the simulator (models/, doc/AGENTS.md):
/// the network of the paper's tables, trained in the void with perfect depth. The predicted-
/// gradient agent and the PPO policies' backbone.
std::string defaultModelPath();
/// The predicted-escape agent's default network in the simulator: the default model fine-tuned on
/// the agent's own states with the oracle's labels (two DAgger rounds, doc/TRAINING.md, "DAgger").
std::string escapeModelPath();
/// The shipped model for a depth camera: the same weights, reading depth with its dropouts filled
/// (depth_gaps filled, doc/TRAINING.md). The camera bridge's estimate was fine-tuned from it.
std::string cameraModelPath();
/// The camera bridge's default network, whose estimate ends an episode: a 128 px network of a
/// fixed 60 deg of the view that passes the known-answer checks (doc/TRAINING.md, "The
/// known-answer checks against the bridge's stops").
std::string bridgeModelPath();

/// A registry entry for an agent made from a model file: needs.model_file set, `make` given the
/// file's path ("" default_model_path: the agent runs only when a path is given).
AgentEntry modelAgentEntry(const std::string& name, const std::string& summary,
                           const std::string& paper_label, const std::string& default_model_path,
                           std::function<std::unique_ptr<Agent>(const std::string&)> make);

AgentEntry predictedGradientAgentEntry();
AgentEntry predictedEscapeAgentEntry();

/// The core's agents and the learned ones: what the evaluation and the agent node offer.
AgentRegistry learningAgents();

/// For a tool running `workers` worker threads, each with networks of its own: libtorch's threads
/// per inference, one when `workers` > 1 so that the workers do not compete for the cores, its
/// default (one per core) otherwise.
void setInferenceThreadsForWorkers(int workers);

}  // namespace learning
}  // namespace occlusion_env
