#include "occlusion_env/learning/multitask_unet.hpp"

#include <cmath>
#include <string>

#include "occlusion_env/common/errors.hpp"

namespace occlusion_env {
namespace learning {
namespace {

namespace nn = torch::nn;

// Appends one conv unit to `unit`: conv (3x3, or 3x1 -> 1x3 -> 1x1 when separable) -> ReLU ->
// BatchNorm.
void appendConvUnit(nn::Sequential& unit, int in, int out, const NetworkConfig& config) {
  const int d = config.dilation();
  if (config.separable()) {
    unit->push_back(
        nn::Conv2d(nn::Conv2dOptions(in, out, {3, 1}).padding({d, 0}).dilation({d, 1})));
    unit->push_back(
        nn::Conv2d(nn::Conv2dOptions(out, out, {1, 3}).padding({0, d}).dilation({1, d})));
    unit->push_back(nn::Conv2d(nn::Conv2dOptions(out, out, 1)));
  } else {
    unit->push_back(nn::Conv2d(nn::Conv2dOptions(in, out, 3).padding(d).dilation(d)));
  }
  unit->push_back(nn::ReLU(nn::ReLUOptions(true)));
  unit->push_back(nn::BatchNorm2d(out));
}

nn::Sequential directionHead(int features, int outputs = 2) {
  return nn::Sequential(nn::Linear(features, 64), nn::ReLU(nn::ReLUOptions(true)),
                        nn::Linear(64, outputs));
}

}  // namespace

const OptionTable<NetworkConfig>& networkConfigTable() {
  static const auto table =
      OptionTable<NetworkConfig>()
          .add("variant", &NetworkConfig::variant,
               OptionSpec("the network (Table 3)")
                   .choices({"unet", "r_unet", "sr_unet", "sar_unet"}))
          .add("input_size", &NetworkConfig::input_size,
               OptionSpec("network input size, a multiple of 2^levels (32)")
                   .unit("px")
                   .range(16, 512)
                   .flag("--size"))
          .add("depth_gaps", &NetworkConfig::depth_gaps,
               OptionSpec("how missing depth (a sensor's dropouts) enters: far = as the "
                          "background; filled = from the valid pixels around (network_input.hpp)")
                   .choices({"far", "filled"}))
          .add("bounding_surfaces", &NetworkConfig::bounding_surfaces,
               OptionSpec("how floors and walls enter: kept = as they are; cleared = as the "
                          "void, found in the depth with the camera's intrinsics "
                          "(network_input.hpp; the datasets' from scene_camera.json)")
                   .choices({"kept", "cleared"}))
          .add("depth_reference", &NetworkConfig::depth_reference,
               OptionSpec("what depth is measured against: metres = as the camera reads it; "
                          "radius = relative to the camera's distance from the sphere's centre "
                          "(x 4 m / r), so that a scene scaled with its sphere looks as at 4 m "
                          "(network_input.hpp)")
                   .choices({"metres", "radius"}))
          .add("view_crop", &NetworkConfig::view_crop,
               OptionSpec("the centred fraction of the view's width and height the network sees "
                          "at its input size (1: the whole view; 0.5: the middle, where the "
                          "objects are, at twice the resolution; network_input.hpp)")
                   .range(0.1, 1.0))
          .add("view_field_of_view", &NetworkConfig::view_field_of_view,
               OptionSpec("the angle of view the network sees around the principal point, from "
                          "the camera's intrinsics, at its input size, whatever the camera's own "
                          "(the paper's camera: 1.0472 = 60 deg; beyond a narrower image it sees "
                          "the void); 0 = the view as view_crop says (network_input.hpp)")
                   .unit("rad")
                   .range(0.0, 3.0))
          .add("depth_validity", &NetworkConfig::depth_validity,
               OptionSpec("whether the input shows where depth was read: none = RGB and depth; "
                          "channel = a fifth channel with each network pixel's share of depth "
                          "readings, so that a filled input still shows a sensor's lost edge "
                          "bands (network_input.hpp)")
                   .choices({"none", "channel"}))
          .add("base_channels", &NetworkConfig::base_channels,
               OptionSpec("channels of the first stage").range(1, 64).flag("--base"))
          .add("levels", &NetworkConfig::levels,
               OptionSpec("encoder stages, each halving the size").range(1, 6).flag(""))
          .add("escape_bins", &NetworkConfig::escape_bins,
               OptionSpec("directions of the one-step circle an escape-bins head scores (trained "
                          "by cross-entropy; the predicted-escape agent then takes the best); 0 = "
                          "no such head")
                   .range(0, 360));
  return table;
}

void NetworkConfig::validate() const {
  networkConfigTable().check(*this);
  if (view_field_of_view > 0.0 && view_crop != 1.0) {
    throw InvalidArgumentError("view_crop and view_field_of_view: a network crops the view by one");
  }
  if (input_size % (1 << levels) != 0) {
    throw InvalidArgumentError("input_size must be a multiple of 2^levels = " +
                               std::to_string(1 << levels));
  }
}

InputFormat NetworkConfig::inputFormat() const {
  InputFormat format{input_size, depth_gaps == "filled" ? DepthGaps::kFilled : DepthGaps::kFar,
                     bounding_surfaces == "cleared", depth_reference == "radius"};
  format.view_crop = view_crop;
  format.view_field_of_view = view_field_of_view;
  format.valid_fraction_channel = depth_validity == "channel";
  return format;
}

nlohmann::json NetworkConfig::toJson() const {
  nlohmann::json json = networkConfigTable().toJson(*this);
  // Only with the head or the clearing, so that networks without keep the identity they always
  // had.
  if (escape_bins == 0) json.erase("escape_bins");
  if (bounding_surfaces == "kept") json.erase("bounding_surfaces");
  if (depth_reference == "metres") json.erase("depth_reference");
  if (view_crop == 1.0) json.erase("view_crop");
  if (view_field_of_view == 0.0) json.erase("view_field_of_view");
  if (depth_validity == "none") json.erase("depth_validity");
  return json;
}

NetworkConfig NetworkConfig::fromJson(const nlohmann::json& json) {
  for (const std::string& key : networkConfigTable().keys()) {
    // "far", 0, "kept", "metres", 1, 0 and "none" when absent: recorded before they existed.
    if (key == "depth_gaps" || key == "escape_bins" || key == "bounding_surfaces" ||
        key == "depth_reference" || key == "view_crop" || key == "view_field_of_view" ||
        key == "depth_validity") {
      continue;
    }
    if (!json.contains(key)) throw InvalidArgumentError("network: no " + quoted(key));
  }
  NetworkConfig config;
  networkConfigTable().applyJson(json, config);
  config.validate();
  return config;
}

ConvUnitsImpl::ConvUnitsImpl(int channels, const NetworkConfig& config)
    : residual_(config.residual()) {
  nn::Sequential units;
  appendConvUnit(units, channels, channels, config);
  appendConvUnit(units, channels, channels, config);
  units_ = register_module("units", units);
}

torch::Tensor ConvUnitsImpl::forward(torch::Tensor x) {
  return residual_ ? x + units_->forward(x) : units_->forward(x);
}

MultiTaskUNetImpl::MultiTaskUNetImpl(const NetworkConfig& config) : config_(config) {
  config_.validate();
  const int base = config_.base_channels;
  stem_ = register_module(
      "stem", nn::Conv2d(nn::Conv2dOptions(config_.inputFormat().channels(), base, 3).padding(1)));
  for (int level = 0; level < config_.levels; ++level) {
    const int channels = base << level;
    encoder_units_->push_back(ConvUnits(channels, config_));
    downsamplers_->push_back(
        nn::Conv2d(nn::Conv2dOptions(channels, 2 * channels, 3).stride(2).padding(1)));
  }
  for (int level = config_.levels - 1; level >= 0; --level) {
    const int channels = base << level;
    upsamplers_->push_back(
        nn::ConvTranspose2d(nn::ConvTranspose2dOptions(2 * channels, channels, 2).stride(2)));
    decoder_units_->push_back(ConvUnits(channels, config_));
  }
  register_module("encoder_units", encoder_units_);
  register_module("downsamplers", downsamplers_);
  register_module("upsamplers", upsamplers_);
  register_module("decoder_units", decoder_units_);
  occlusion_head_ = register_module("occlusion_head", nn::Conv2d(nn::Conv2dOptions(base, 1, 1)));
  gradient_head_ = register_module("gradient_head", directionHead(config_.bottleneckChannels()));
  escape_head_ = register_module("escape_head", directionHead(config_.bottleneckChannels()));
  if (config_.escape_bins > 0) {
    escape_bins_head_ = register_module(
        "escape_bins_head", directionHead(config_.bottleneckChannels(), config_.escape_bins));
  }
}

torch::Tensor MultiTaskUNetImpl::encoderFeatures(torch::Tensor input,
                                                 std::vector<torch::Tensor>* skips) {
  torch::Tensor x = torch::relu(stem_->forward(input));
  for (int level = 0; level < config_.levels; ++level) {
    x = encoder_units_[level]->as<ConvUnitsImpl>()->forward(x);
    if (skips) skips->push_back(x);
    x = torch::relu(downsamplers_[level]->as<nn::Conv2dImpl>()->forward(x));
  }
  return x;
}

torch::Tensor MultiTaskUNetImpl::encode(torch::Tensor input) {
  return torch::adaptive_avg_pool2d(encoderFeatures(input, nullptr), {1, 1}).flatten(1);
}

NetworkOutput MultiTaskUNetImpl::forward(torch::Tensor input) {
  std::vector<torch::Tensor> skips;
  torch::Tensor x = encoderFeatures(input, &skips);
  NetworkOutput out;
  out.features = torch::adaptive_avg_pool2d(x, {1, 1}).flatten(1);
  for (int i = 0; i < config_.levels; ++i) {
    const int level = config_.levels - 1 - i;
    x = upsamplers_[i]->as<nn::ConvTranspose2dImpl>()->forward(x) + skips[level];
    x = decoder_units_[i]->as<ConvUnitsImpl>()->forward(x);
  }
  out.occlusion_logits = occlusion_head_->forward(x);
  out.gradient_direction = gradient_head_->forward(out.features);
  out.escape_direction = escape_head_->forward(out.features);
  if (escape_bins_head_) out.escape_logits = escape_bins_head_->forward(out.features);
  return out;
}

double escapeBinAngleRad(int k, int bins) {
  return 2.0 * M_PI * k / bins;
}

torch::Tensor escapeBinAngles(int bins) {
  return torch::arange(bins, torch::kFloat) * (2.0 * M_PI / bins);
}

torch::Tensor escapeBinTargets(const torch::Tensor& labels, int bins, double kappa) {
  const torch::Tensor angles = escapeBinAngles(bins);
  const torch::Tensor label_angles = torch::atan2(labels.select(1, 0), labels.select(1, 1));
  // cos(theta_k - theta) for every label and bin: [B, bins].
  const torch::Tensor cosines = torch::cos(angles.unsqueeze(0) - label_angles.unsqueeze(1));
  return torch::softmax(kappa * cosines, 1);
}

torch::Tensor escapeDirectionFromLogits(const torch::Tensor& logits,
                                        const torch::Tensor& choice_bias) {
  const int64_t bins = logits.size(1);
  const torch::Tensor probabilities = torch::softmax(logits, 1);
  const torch::Tensor best = choice_bias.defined()
                                 ? (torch::log_softmax(logits, 1) + choice_bias).argmax(1, true)
                                 : probabilities.argmax(1, true);  // [B, 1]
  const torch::Tensor neighbours =
      torch::cat({(best + bins - 1) % bins, best, (best + 1) % bins}, 1);  // [B, 3]
  const torch::Tensor weights = probabilities.gather(1, neighbours);
  const torch::Tensor angles = neighbours.to(torch::kFloat) * (2.0 * M_PI / bins);  // theta_k
  const torch::Tensor sin = (weights * torch::sin(angles)).sum(1);
  const torch::Tensor cos = (weights * torch::cos(angles)).sum(1);
  const torch::Tensor direction = torch::stack({sin, cos}, 1);
  return direction / direction.norm(2, 1, true).clamp_min(1e-12);
}

float occlusionLogit(double probability) {
  if (!(probability > 0.0 && probability < 1.0)) {
    throw InvalidArgumentError("an occlusion probability threshold must lie in (0, 1), not " +
                               std::to_string(probability));
  }
  return static_cast<float>(std::log(probability / (1.0 - probability)));
}

}  // namespace learning
}  // namespace occlusion_env
