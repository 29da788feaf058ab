#include "occlusion_env/learning/learned_agents.hpp"

#include <cmath>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/package_paths.hpp"
#include "occlusion_env/learning/policy.hpp"

namespace occlusion_env {
namespace learning {

NetworkDirectionAgent::NetworkDirectionAgent(std::shared_ptr<LoadedModel> model, DirectionHead head)
    : model_(std::move(model)), head_(head) {
  if (!model_ || !model_->network) throw InvalidArgumentError("network agent: no model");
  const int size = model_->network->config().input_size;
  input_ = torch::empty({1, 4, size, size});
}

void NetworkDirectionAgent::reset(std::uint64_t) {}

Action NetworkDirectionAgent::act(const RigObservation& observation) {
  writeNetworkInput(observation.rgb, observation.depth, model_->network->config().inputFormat(),
                    scratch_, input_.data_ptr<float>());
  torch::InferenceMode inference;
  // The encoder and one head: the decoder's occlusion map is not needed to move.
  auto& network = model_->network;
  const torch::Tensor direction =
      (head_ == DirectionHead::kGradient ? network->gradientHead() : network->escapeHead())
          ->forward(network->encode(input_));
  const float sin = direction[0][0].item<float>(), cos = direction[0][1].item<float>();
  if (!std::isfinite(sin) || !std::isfinite(cos) || (sin == 0.0f && cos == 0.0f)) {
    throw std::runtime_error("the network predicted no direction");
  }
  return {cos,
          sin};  // theta = atan2(d_elevation, d_azimuth): (d_azimuth, d_elevation) = (cos, sin)
}

std::string defaultModelPath() {
  return packageShareDirectory() + "/models/multitask_unet64.pt";
}

std::string cameraModelPath() {
  return packageShareDirectory() + "/models/multitask_unet64_camera.pt";
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
                        const std::string& paper_label, DirectionHead head) {
  return modelAgentEntry(name, summary, paper_label, defaultModelPath(),
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
                      "Pred. Grad", DirectionHead::kGradient);
}

AgentEntry predictedEscapeAgentEntry() {
  return networkEntry("predicted_escape",
                      "a unit move along the escape direction (the oracle's first step) the "
                      "multi-task network predicts from the RGB-D image alone",
                      "", DirectionHead::kEscape);
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

}  // namespace learning
}  // namespace occlusion_env
