#include "occlusion_env/learning/learned_agents.hpp"

#include <cmath>

#include <torch/utils.h>  // torch::set_num_threads

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/package_paths.hpp"
#include "occlusion_env/learning/policy.hpp"

namespace occlusion_env {
namespace learning {
namespace {

// How much the escape-bins agent prefers bins along its last move: lambda of the bias
// lambda * cos(theta_k - theta_last) added to the bins' log-probabilities when choosing one.
// Without it the agent flips between equally likely modes from one step to the next
// (doc/TRAINING.md, "An escape head that chooses"); 1 was chosen on validation scenes among 1, 2
// and 3.
constexpr double kLastMoveBias = 1.0;

// The choice bias [1, bins] of escapeDirectionFromLogits for the rig's last move, from the bins'
// angles [1, bins]; undefined (no bias) after a reset.
torch::Tensor lastMoveBias(const torch::Tensor& bin_angles, const Action& last_move) {
  if (last_move.d_azimuth_rad == 0.0 && last_move.d_elevation_rad == 0.0) return {};
  const double last = std::atan2(last_move.d_elevation_rad, last_move.d_azimuth_rad);
  return kLastMoveBias * torch::cos(bin_angles - last);
}

}  // namespace

NetworkDirectionAgent::NetworkDirectionAgent(std::shared_ptr<LoadedModel> model, DirectionHead head)
    : model_(std::move(model)), head_(head) {
  if (!model_ || !model_->network) throw InvalidArgumentError("network agent: no model");
  encoder_ = std::make_unique<InferenceEncoder>(*model_->network);
  input_format_ = model_->network->config().inputFormat();
  input_ = torch::empty({1, input_format_.channels(), input_format_.size, input_format_.size});
  const int bins = model_->network->config().escape_bins;
  if (bins > 0) bin_angles_ = escapeBinAngles(bins).view({1, bins});
}

void NetworkDirectionAgent::reset(std::uint64_t) {
  elevation_limit_ = ElevationLimitTracker();
  recent_views_ = RevisitGuard();
}

Action NetworkDirectionAgent::act(const RigObservation& observation) {
  elevation_limit_.observe(observation);
  recent_views_.observe(observation);
  writeNetworkInput(observation.rgb, observation.depth, observation.intrinsics,
                    input_format_.atRadius(cameraRadius(observation.world_from_optical)), scratch_,
                    input_.data_ptr<float>());
  torch::InferenceMode inference;
  // The encoder and one head: the decoder's occlusion map is not needed to move.
  auto& network = model_->network;
  const torch::Tensor features = encoder_->encode(input_);
  // A network with an escape-bins head escapes along its best bin, not the regression's mean.
  const torch::Tensor direction =
      head_ == DirectionHead::kGradient ? network->gradientHead()->forward(features)
      : network->escapeBinsHead()
          ? escapeDirectionFromLogits(network->escapeBinsHead()->forward(features),
                                      lastMoveBias(bin_angles_, observation.last_action))
          : network->escapeHead()->forward(features);
  const float sin = direction[0][0].item<float>(), cos = direction[0][1].item<float>();
  if (!std::isfinite(sin) || !std::isfinite(cos) || (sin == 0.0f && cos == 0.0f)) {
    throw std::runtime_error("the network predicted no direction");
  }
  // theta = atan2(d_elevation, d_azimuth): (d_azimuth, d_elevation) = (cos, sin)
  const Action predicted{cos, sin};
  if (head_ == DirectionHead::kGradient) return predicted;  // the paper's agent, as it was
  // Ours: along a floor that stopped the rig, and aside from a view it has just left.
  return elevation_limit_.alongTheLimit(
      recent_views_.awayFromRecentViews(elevation_limit_.alongTheLimit(predicted)));
}

std::string defaultModelPath() {
  return packageShareDirectory() + "/models/multitask_unet64.pt";
}

std::string escapeModelPath() {
  return packageShareDirectory() + "/models/multitask_unet64_escape.pt";
}

std::string cameraModelPath() {
  return packageShareDirectory() + "/models/multitask_unet64_camera.pt";
}

std::string bridgeModelPath() {
  return packageShareDirectory() + "/models/multitask_unet128_bridge_fov60.pt";
}

AgentEntry modelAgentEntry(const std::string& name, const std::string& summary,
                           const std::string& paper_label, const std::string& default_model_path,
                           std::function<std::unique_ptr<Agent>(const std::string&)> make) {
  AgentEntry entry;
  entry.name = name;
  entry.summary = summary;
  entry.needs.model_file = true;
  entry.paper_label = paper_label;
  entry.default_model_path = default_model_path;
  entry.make = [make = std::move(make)](const AgentCapabilities& capabilities) {
    return make(capabilities.model_path);
  };
  return entry;
}

namespace {

AgentEntry networkEntry(const std::string& name, const std::string& summary,
                        const std::string& paper_label, const std::string& default_model_path,
                        DirectionHead head) {
  return modelAgentEntry(name, summary, paper_label, default_model_path,
                         [head](const std::string& path) {
                           return std::make_unique<NetworkDirectionAgent>(
                               std::make_shared<LoadedModel>(loadModel(path)), head);
                         });
}

}  // namespace

AgentEntry predictedGradientAgentEntry() {
  return networkEntry("predicted_gradient",
                      "a unit move along the descent direction the multi-task network predicts "
                      "from the RGB-D image alone",
                      "Pred. Grad", defaultModelPath(), DirectionHead::kGradient);
}

AgentEntry predictedEscapeAgentEntry() {
  return networkEntry("predicted_escape",
                      "a unit move along the escape direction (the oracle's first step) the "
                      "multi-task network, fine-tuned on the agent's own states (DAgger), "
                      "predicts from the RGB-D image alone (with an "
                      "escape-bins head: its best bin, leaning towards the last move); along a "
                      "floor that stopped the rig, aside from a view it has just left",
                      "", escapeModelPath(), DirectionHead::kEscape);
}

AgentRegistry learningAgents() {
  AgentRegistry registry = coreAgents();
  registry.add(predictedGradientAgentEntry());
  registry.add(predictedEscapeAgentEntry());
  registry.add(policyUnAgentEntry());
  registry.add(policyInAgentEntry());
  registry.add(policyAgentEntry());
  registry.add(policySampledAgentEntry());
  return registry;
}

void setInferenceThreadsForWorkers(int workers) {
  if (workers > 1) torch::set_num_threads(1);
}

}  // namespace learning
}  // namespace occlusion_env
