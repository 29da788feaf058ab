// The multi-task network of Section 5.1 of the paper (Table 3): a U-Net that predicts the
// occlusion map, with dense heads on its pooled bottleneck for the direction in which occlusion
// falls (the gradient label) and the direction of escape (the oracle's first step).
//
// Encoder: a 3x3 stem to `base` channels, then `levels` stages of channels base * 2^i, each two
// conv units (conv -> ReLU -> BatchNorm) followed by a strided 3x3 conv that halves the size and
// doubles the channels (so the bottleneck has base * 2^levels channels at 1 / 2^levels size).
// Decoder: per level a stride-2 transposed conv, the skip of the same level added, two conv
// units (the units run on the upsampled features: the original code's transposed-conv block
// upsampled its input and left its convs unused). A 1x1 conv gives the occlusion logits.
// Heads: global average pooling of the bottleneck, then Linear -> ReLU -> Linear to (sin, cos).
// Optionally (escape_bins > 0) a third head of the same shape scores escape_bins directions of the
// one-step circle (a classification of the escape direction): where several first steps are
// equally short, the regression's (sin, cos) is their mean, which is none of them; the scores'
// best bin is one of them.
//
// Variants (Table 3): unet; r_unet (the two conv units of a stage are residual); sr_unet
// (residual, each 3x3 conv factorised as 3x1 -> 1x3 -> 1x1); sar_unet (sr_unet with dilation 2 in
// the factorised convs). The -L1 variant is a loss choice (TrainingOptions), not an architecture.
#pragma once

#include <torch/torch.h>

#include <nlohmann/json.hpp>
#include <string>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/learning/network_input.hpp"

namespace occlusion_env {
namespace learning {

struct NetworkConfig {
  std::string variant = "unet";  // unet | r_unet | sr_unet | sar_unet
  int base_channels = 8;
  int levels = 5;
  int input_size = 64;             // [px], a multiple of 2^levels
  std::string depth_gaps = "far";  // far | filled: how missing depth enters (network_input.hpp)
  // kept | cleared: whether floors and walls enter as they are or as the void (network_input.hpp)
  std::string bounding_surfaces = "kept";
  // metres | radius: depth as read, or relative to the camera's radius (network_input.hpp)
  std::string depth_reference = "metres";
  int escape_bins = 0;              // directions scored by the escape-bins head; 0 = no such head
  double view_crop = 1.0;           // the centred fraction of the view's width and height it sees
  double view_field_of_view = 0.0;  // [rad] the angle of view it sees; 0: as view_crop says
  // none | channel: whether each pixel's share of depth readings enters as a fifth channel
  std::string depth_validity = "none";

  bool residual() const { return variant != "unet"; }
  bool separable() const { return variant == "sr_unet" || variant == "sar_unet"; }
  int dilation() const { return variant == "sar_unet" ? 2 : 1; }
  int bottleneckChannels() const { return base_channels << levels; }
  InputFormat inputFormat() const;

  /// Throws InvalidArgumentError naming the bad field: the table's ranges and choices, then
  /// input_size a multiple of 2^levels.
  void validate() const;
  /// Every field by its table name (the "network" of model manifests).
  nlohmann::json toJson() const;
  /// Refuses unknown names and a missing field (every manifest states the whole network), but
  /// depth_gaps, escape_bins, bounding_surfaces, depth_reference, view_crop,
  /// view_field_of_view and depth_validity, which models recorded before they existed lack:
  /// "far", 0, "kept", "metres", 1, 0 and "none".
  static NetworkConfig fromJson(const nlohmann::json& json);
};

/// The declared fields of NetworkConfig (flags --variant, --base, --size; levels has none).
const OptionTable<NetworkConfig>& networkConfigTable();

struct NetworkOutput {
  torch::Tensor occlusion_logits;    // [B, 1, S, S]
  torch::Tensor gradient_direction;  // [B, 2]: (sin, cos) of the descent direction, unnormalised
  torch::Tensor escape_direction;    // [B, 2]: (sin, cos) of the escape direction, unnormalised
  torch::Tensor escape_logits;       // [B, escape_bins], undefined without the escape-bins head
  torch::Tensor features;            // [B, C]: the pooled bottleneck (for policies)
};

// Two conv units of one width (conv -> ReLU -> BatchNorm), residual when the config says so.
class InferenceEncoder;  // learning/inference_encoder.hpp: reads the modules below

class ConvUnitsImpl : public torch::nn::Module {
 public:
  ConvUnitsImpl(int channels, const NetworkConfig& config);
  torch::Tensor forward(torch::Tensor x);

 private:
  friend class InferenceEncoder;
  torch::nn::Sequential units_{nullptr};
  bool residual_ = false;
};
TORCH_MODULE(ConvUnits);

class MultiTaskUNetImpl : public torch::nn::Module {
 public:
  explicit MultiTaskUNetImpl(const NetworkConfig& config);
  /// `input`: [B, C, S, S], C = config().inputFormat().channels() (learning/network_input.hpp).
  NetworkOutput forward(torch::Tensor input);
  /// The pooled bottleneck only (the encoder), [B, C].
  torch::Tensor encode(torch::Tensor input);
  const NetworkConfig& config() const { return config_; }
  /// The direction heads, Linear -> ReLU -> Linear from encode()'s features to (sin, cos): an
  /// agent that only moves needs these and not the decoder. A policy's actor starts as the
  /// escape head.
  torch::nn::Sequential& gradientHead() { return gradient_head_; }
  torch::nn::Sequential& escapeHead() { return escape_head_; }
  /// The escape-bins head (escape_bins logits from encode()'s features); null without one.
  torch::nn::Sequential& escapeBinsHead() { return escape_bins_head_; }

 private:
  friend class InferenceEncoder;
  torch::Tensor encoderFeatures(torch::Tensor input, std::vector<torch::Tensor>* skips);

  NetworkConfig config_;
  torch::nn::Conv2d stem_{nullptr};
  torch::nn::ModuleList encoder_units_, downsamplers_, upsamplers_, decoder_units_;
  torch::nn::Conv2d occlusion_head_{nullptr};
  torch::nn::Sequential gradient_head_{nullptr}, escape_head_{nullptr}, escape_bins_head_{nullptr};
};
TORCH_MODULE(MultiTaskUNet);

/// The direction of bin k of `bins` around the circle: theta_k = 2 pi k / bins, as
/// atan2(d_elevation, d_azimuth) (doc/CONVENTIONS.md).
double escapeBinAngleRad(int k, int bins);
/// Every bin's theta_k [rad], [bins] floats.
torch::Tensor escapeBinAngles(int bins);
/// Soft targets [B, bins] for escape labels [B, 2] (sin, cos): a von Mises bump of concentration
/// `kappa` around each label, sampled at the bins' angles and normalised.
torch::Tensor escapeBinTargets(const torch::Tensor& labels, int bins, double kappa);
/// The direction [B, 2] (sin, cos), unit, that escape logits [B, bins] choose: the best bin,
/// refined by the probability-weighted mean of it and its two neighbours.
/// `choice_bias` [B, bins], when given, is added to the log-probabilities for choosing the bin (not
/// for the refinement).
torch::Tensor escapeDirectionFromLogits(const torch::Tensor& logits,
                                        const torch::Tensor& choice_bias = {});

/// The occlusion logit of a probability threshold, log(p / (1 - p)) in float, as the occlusion
/// map's logits are compared with it; InvalidArgumentError outside (0, 1).
float occlusionLogit(double probability);

}  // namespace learning
}  // namespace occlusion_env
