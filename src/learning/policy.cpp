#include "occlusion_env/learning/policy.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/package_paths.hpp"
#include "occlusion_env/common/text_file.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"

namespace occlusion_env {
namespace learning {

namespace nn = torch::nn;

const OptionTable<PolicyConfig>& policyConfigTable() {
  static const auto table =
      OptionTable<PolicyConfig>()
          .add("hidden", &PolicyConfig::hidden,
               OptionSpec("width of the actor body's and the critic's hidden layers")
                   .range(1, 4096)
                   .flag(""))
          .add("rig_inputs", &PolicyConfig::rig_inputs,
               OptionSpec(
                   "the heads see the last moves (--move-memory) and the elevation besides the "
                   "image features")
                   .negatedFlag("--no-rig"))
          .add("move_memory", &PolicyConfig::move_memory,
               OptionSpec("how many of the rig's last moves the heads see, newest first (1: the "
                          "last move alone)")
                   .range(1, 16))
          .add("unit_mean", &PolicyConfig::unit_mean,
               OptionSpec("scale the mean action to unit length (false: free length, as the "
                          "paper; doc/PPO.md compares them)"))
          .add("learned_std", &PolicyConfig::learned_std,
               OptionSpec("sigma a trained parameter starting at --std, so that the entropy bonus "
                          "has a gradient (false: the --std -> --std-end schedule)"))
          .add("action", &PolicyConfig::action,
               OptionSpec("the action distribution: a Gaussian about the mean action (the "
                          "paper's), or a categorical over --directions unit moves whose "
                          "logits start from the mean action (doc/PPO.md)")
                   .choices({"gaussian", "directions"}))
          .add("directions", &PolicyConfig::directions,
               OptionSpec("with --action directions: unit moves around the circle").range(4, 720))
          .add("direction_concentration", &PolicyConfig::direction_concentration,
               OptionSpec("with --action directions: kappa, the logits' scale on the mean "
                          "action (larger: a sharper start)")
                   .above(0)
                   .atMost(1000));
  return table;
}

void PolicyConfig::validate() const {
  policyConfigTable().check(*this);
  if (isDirections() && (unit_mean || learned_std)) {
    throw InvalidArgumentError(
        "policy: unit_mean and learned_std are the Gaussian's; the directions action has neither");
  }
}

nlohmann::json PolicyConfig::toJson() const {
  nlohmann::json json = policyConfigTable().toJson(*this);
  // Only when set, so that runs and policies from before the option keep their identity.
  if (!learned_std) json.erase("learned_std");
  if (move_memory == 1) json.erase("move_memory");
  if (!isDirections()) {
    for (const char* name : {"action", "directions", "direction_concentration"}) json.erase(name);
  }
  return json;
}

PolicyConfig PolicyConfig::fromJson(const nlohmann::json& json) {
  PolicyConfig config;
  policyConfigTable().applyJson(json, config);
  config.validate();
  return config;
}

PolicyNetworkImpl::PolicyNetworkImpl(const NetworkConfig& backbone, const PolicyConfig& config)
    : config_(config) {
  config_.validate();
  const int features = backbone.bottleneckChannels();
  backbone_ = register_module("backbone", MultiTaskUNet(backbone));
  actor_body_ =
      register_module("actor_body", nn::Sequential(nn::Linear(features, config_.hidden), nn::ReLU(),
                                                   nn::Linear(config_.hidden, 2)));
  const int rig_inputs = config_.rigInputs();
  actor_rig_ = register_module("actor_rig", nn::Linear(rig_inputs, 2));
  critic_ = register_module(
      "critic", nn::Sequential(nn::Linear(features + rig_inputs, config_.hidden), nn::Tanh(),
                               nn::Linear(config_.hidden, config_.hidden), nn::Tanh(),
                               nn::Linear(config_.hidden, 1)));
  if (config_.learned_std) log_std_ = register_parameter("log_std", torch::zeros({2}));
  if (config_.isDirections()) {
    actor_directions_ =
        register_module("actor_directions", nn::Linear(features + rig_inputs, config_.directions));
    const torch::Tensor angle =
        torch::arange(config_.directions, torch::kDouble) * (2.0 * M_PI / config_.directions);
    direction_vectors_ = register_buffer(
        "direction_vectors", torch::stack({angle.cos(), angle.sin()}, 1).to(torch::kFloat));
  }
  torch::NoGradGuard no_grad;
  if (actor_directions_) {  // the logits start as the mean action's alone
    actor_directions_->weight.zero_();
    actor_directions_->bias.zero_();
  }
  // The rig term starts at zero (the actor is the body alone); small last layers so that a fresh
  // actor starts near the zero mean and the critic near zero (the PPO literature's
  // initialisation: 0.01 for the policy's output, 1 for the value's).
  actor_rig_->weight.zero_();
  actor_rig_->bias.zero_();
  auto* actor_out = actor_body_[2]->as<nn::LinearImpl>();
  nn::init::orthogonal_(actor_out->weight, 0.01);
  actor_out->bias.zero_();
  for (int layer : {0, 2, 4}) {
    auto* linear = critic_[layer]->as<nn::LinearImpl>();
    nn::init::orthogonal_(linear->weight, layer == 4 ? 1.0 : std::sqrt(2.0));
    linear->bias.zero_();
  }
}

torch::Tensor PolicyNetworkImpl::features(const torch::Tensor& input) {
  return backbone_->encode(input);
}

torch::Tensor PolicyNetworkImpl::rigOrZero(const torch::Tensor& rig) {
  return config_.rig_inputs ? rig : torch::zeros_like(rig);
}

torch::Tensor PolicyNetworkImpl::rawMean(const torch::Tensor& features, const torch::Tensor& rig) {
  return actor_body_->forward(features) + actor_rig_->forward(rigOrZero(rig));
}

torch::Tensor PolicyNetworkImpl::actionMean(const torch::Tensor& features,
                                            const torch::Tensor& rig) {
  if (config_.isDirections()) {
    return directionLogProbabilities(features, rig).exp().matmul(direction_vectors_);
  }
  const torch::Tensor mean = rawMean(features, rig);
  if (!config_.unit_mean) return mean;
  return mean / mean.norm(2, 1, /*keepdim=*/true).clamp_min(1e-6);
}

torch::Tensor PolicyNetworkImpl::directionLogProbabilities(const torch::Tensor& features,
                                                           const torch::Tensor& rig) {
  if (!config_.isDirections()) {
    throw std::logic_error("policy: the action is not directions");
  }
  const torch::Tensor logits =
      config_.direction_concentration * rawMean(features, rig).matmul(direction_vectors_.t()) +
      actor_directions_->forward(torch::cat({features, rigOrZero(rig)}, 1));
  return torch::log_softmax(logits, 1);
}

torch::Tensor PolicyNetworkImpl::value(const torch::Tensor& features, const torch::Tensor& rig) {
  return critic_->forward(torch::cat({features, rigOrZero(rig)}, 1)).squeeze(1);
}

void PolicyNetworkImpl::initialiseFrom(MultiTaskUNet& network, bool actor_from_escape) {
  if (network->config().toJson() != backbone_->config().toJson()) {
    throw InvalidArgumentError("policy: the pretrained network's configuration " +
                               network->config().toJson().dump() + " is not the backbone's " +
                               backbone_->config().toJson().dump());
  }
  torch::NoGradGuard no_grad;
  auto source = network->named_parameters();
  for (auto& item : backbone_->named_parameters()) item.value().copy_(source[item.key()]);
  auto source_buffers = network->named_buffers();
  for (auto& item : backbone_->named_buffers()) item.value().copy_(source_buffers[item.key()]);
  if (!actor_from_escape) return;
  if (config_.hidden != 64) {
    throw InvalidArgumentError("policy: an actor initialised from the escape head needs hidden 64");
  }
  auto& escape = network->escapeHead();
  auto* in = escape[0]->as<nn::LinearImpl>();
  auto* out = escape[2]->as<nn::LinearImpl>();
  auto* actor_in = actor_body_[0]->as<nn::LinearImpl>();
  auto* actor_out = actor_body_[2]->as<nn::LinearImpl>();
  actor_in->weight.copy_(in->weight);
  actor_in->bias.copy_(in->bias);
  // The escape head gives (sin, cos) of theta = atan2(d_el, d_az): (d_az, d_el) = rows (1, 0).
  const torch::Tensor order = torch::tensor({1, 0}, torch::kLong);
  actor_out->weight.copy_(out->weight.index_select(0, order));
  actor_out->bias.copy_(out->bias.index_select(0, order));
}

torch::Tensor& PolicyNetworkImpl::logStd() {
  if (!config_.learned_std) throw std::logic_error("policy: sigma is not learned (learned_std)");
  return log_std_;
}

std::vector<torch::Tensor> PolicyNetworkImpl::actorParameters() {
  std::vector<torch::Tensor> parameters = actor_body_->parameters();
  for (auto& p : actor_rig_->parameters()) parameters.push_back(p);
  if (actor_directions_) {
    for (auto& p : actor_directions_->parameters()) parameters.push_back(p);
  }
  if (config_.learned_std) parameters.push_back(log_std_);
  return parameters;
}

std::vector<torch::Tensor> PolicyNetworkImpl::criticParameters() {
  return critic_->parameters();
}

int sampleDirection(const float* log_probs, int count, double uniform) {
  int k = 0;
  for (; k + 1 < count; ++k) {
    uniform -= std::exp(log_probs[k]);
    if (uniform < 0.0) break;
  }
  return k;
}

MoveHistory::MoveHistory(int length) : moves_(static_cast<std::size_t>(length)) {
  if (length < 1) throw InvalidArgumentError("move history: needs room for one move at least");
}

void MoveHistory::clear() {
  std::fill(moves_.begin(), moves_.end(), Action{});
  newest_ = 0;
}

void MoveHistory::push(const Action& move) {
  newest_ = (newest_ + 1) % static_cast<int>(moves_.size());
  moves_[newest_] = move;
}

void MoveHistory::writeRigInput(double elevation_rad, float* out) const {
  const int length = static_cast<int>(moves_.size());
  for (int age = 0; age < length; ++age) {
    const Action& move = moves_[(newest_ - age + length) % length];
    const double norm = std::hypot(move.d_azimuth_rad, move.d_elevation_rad);
    out[2 * age] = norm > 0.0 ? static_cast<float>(move.d_azimuth_rad / norm) : 0.0f;
    out[2 * age + 1] = norm > 0.0 ? static_cast<float>(move.d_elevation_rad / norm) : 0.0f;
  }
  out[2 * length] = static_cast<float>(elevation_rad / (M_PI / 2.0));
}

void savePolicy(PolicyNetwork& policy, const std::string& path, const nlohmann::json& info) {
  torch::save(policy, path);
  nlohmann::json manifest = info;
  manifest["kind"] = "ppo_policy";
  manifest["network"] = policy->backbone()->config().toJson();
  manifest["policy"] = policy->config().toJson();
  manifest["file"] = std::filesystem::path(path).filename().string();
  writeTextFile(manifestPathFor(path), manifest.dump(2) + "\n");
}

LoadedPolicy loadPolicy(const std::string& path) {
  LoadedPolicy policy;
  policy.manifest = readManifest(path);
  if (policy.manifest.value("kind", std::string()) != "ppo_policy") {
    throw InvalidArgumentError("model " + path + " is not a PPO policy (its manifest's kind is " +
                               policy.manifest.value("kind", std::string("multitask_unet")) +
                               "; occlusion_train_ppo writes policies)");
  }
  NetworkConfig backbone;
  PolicyConfig config;
  try {
    backbone = NetworkConfig::fromJson(policy.manifest.at("network"));
    config = PolicyConfig::fromJson(policy.manifest.at("policy"));
  } catch (const std::exception& error) {
    throw InvalidArgumentError("policy " + path + ": unreadable manifest " + manifestPathFor(path) +
                               ": " + error.what());
  }
  policy.network = PolicyNetwork(backbone, config);
  loadCheckedParameters(*policy.network, path, "its manifest's policy");
  policy.network->eval();
  return policy;
}

PolicyAgent::PolicyAgent(std::shared_ptr<LoadedPolicy> policy, bool sampled)
    : policy_(std::move(policy)), sampled_(sampled) {
  if (!policy_ || !policy_->network) throw InvalidArgumentError("policy agent: no policy");
  const PolicyConfig& config = policy_->network->config();
  moves_ = MoveHistory(config.move_memory);
  if (sampled_ && !config.isDirections()) {
    if (config.learned_std) {
      const torch::Tensor sigma = policy_->network->logStd().detach().exp();
      for (int axis = 0; axis < 2; ++axis) sigma_[axis] = sigma[axis].item<double>();
    } else {
      const nlohmann::json& trained = policy_->manifest.value("trained_with", nlohmann::json());
      if (!trained.contains("action_std_end")) {
        throw InvalidArgumentError(
            "policy agent: the policy's manifest does not say the sigma its training ended with "
            "(trained_with.action_std_end), so its actions cannot be sampled");
      }
      sigma_[0] = sigma_[1] = trained.at("action_std_end").get<double>();
    }
  }
  encoder_ = std::make_unique<InferenceEncoder>(*policy_->network->backbone());
  input_format_ = policy_->network->backbone()->config().inputFormat();
  input_ = torch::empty({1, input_format_.channels(), input_format_.size, input_format_.size});
  rig_ = torch::zeros({1, config.rigInputs()});
}

void PolicyAgent::reset(std::uint64_t seed) {
  moves_.clear();
  random_.seed(seed);
}

Action PolicyAgent::act(const RigObservation& observation) {
  auto& network = policy_->network;
  writeNetworkInput(observation.rgb, observation.depth, observation.intrinsics,
                    input_format_.atRadius(cameraRadius(observation.world_from_optical)), scratch_,
                    input_.data_ptr<float>());
  moves_.writeRigInput(observation.pose.elevation_rad, rig_.data_ptr<float>());
  torch::InferenceMode inference;
  const torch::Tensor features = encoder_->encode(input_);
  float d_azimuth = 0.0f, d_elevation = 0.0f;
  if (sampled_ && network->config().isDirections()) {
    const torch::Tensor log_probs = network->directionLogProbabilities(features, rig_).contiguous();
    const int k = sampleDirection(log_probs.data_ptr<float>(), static_cast<int>(log_probs.size(1)),
                                  std::uniform_real_distribution<double>(0.0, 1.0)(random_));
    const auto vectors = network->directionVectors().accessor<float, 2>();
    d_azimuth = vectors[k][0];
    d_elevation = vectors[k][1];
  } else {
    const torch::Tensor mean = network->actionMean(features, rig_);
    d_azimuth = mean[0][0].item<float>();
    d_elevation = mean[0][1].item<float>();
    if (sampled_) {
      std::normal_distribution<double> noise(0.0, 1.0);
      d_azimuth += static_cast<float>(sigma_[0] * noise(random_));
      d_elevation += static_cast<float>(sigma_[1] * noise(random_));
    }
  }
  if (!std::isfinite(d_azimuth) || !std::isfinite(d_elevation)) {
    throw std::runtime_error("the policy's action is not finite");
  }
  const Action move{d_azimuth, d_elevation};
  moves_.push(move);
  return move;
}

namespace {

std::string shippedPolicyPath(const std::string& name) {
  return packageShareDirectory() + "/models/" + name + ".pt";
}

AgentEntry policyEntry(const std::string& name, const std::string& summary,
                       const std::string& paper_label, const std::string& default_model_path,
                       bool sampled = false) {
  return modelAgentEntry(name, summary, paper_label, default_model_path,
                         [sampled](const std::string& path) {
                           return std::make_unique<PolicyAgent>(
                               std::make_shared<LoadedPolicy>(loadPolicy(path)), sampled);
                         });
}

}  // namespace

AgentEntry policyUnAgentEntry() {
  return policyEntry("policy_un",
                     "the shipped PPO policy trained with the union-normalised reward (mean "
                     "action), from the RGB-D image and the rig's own last move and elevation",
                     "Agent-UN", shippedPolicyPath("policy_un"));
}

AgentEntry policyInAgentEntry() {
  return policyEntry("policy_in",
                     "the shipped PPO policy trained with the intersection-normalised reward "
                     "(mean action), from the RGB-D image and the rig's own last move and "
                     "elevation",
                     "Agent-IN", shippedPolicyPath("policy_in"));
}

AgentEntry policyAgentEntry() {
  return policyEntry("policy",
                     "any PPO policy written by occlusion_train_ppo, by model path (mean action)",
                     "", "");
}

AgentEntry policySampledAgentEntry() {
  return policyEntry("policy_sampled",
                     "any PPO policy written by occlusion_train_ppo, by model path, its actions "
                     "sampled as in training (seeded by the scene)",
                     "", "", /*sampled=*/true);
}

}  // namespace learning
}  // namespace occlusion_env
