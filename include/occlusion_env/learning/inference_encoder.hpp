// The encoder of a trained MultiTaskUNet, prepared once for inference on the CPU: its
// convolution weights reordered into oneDNN's blocked layout when the snapshot is made, so that
// each call runs oneDNN's convolutions on them as they are. libtorch 1.13 runs a batch of one
// through its native convolutions (im2col, then BLAS packing the weights again on every call),
// and oneDNN, where it takes a call, reorders the weights on every call too. Same features as
// MultiTaskUNetImpl::encode() in eval mode, to float rounding (about 1e-6; tested).
//
//   InferenceEncoder encoder(*network);       // after loading; a snapshot of the weights
//   torch::Tensor features = encoder.encode(input);   // [B, C, S, S] -> [B, C], no gradient
//
// A snapshot: make a new one after the network's weights change (an optimiser step, a load).
// Without oneDNN in libtorch it keeps the network and calls its encode() instead.
#pragma once

#include <torch/torch.h>

#include <vector>

#include "occlusion_env/learning/multitask_unet.hpp"

namespace occlusion_env {
namespace learning {

class InferenceEncoder {
 public:
  /// Snapshots `network`'s encoder (eval mode: BatchNorm's running statistics). The network must
  /// outlive the encoder only where oneDNN is missing (then encode() calls it).
  explicit InferenceEncoder(MultiTaskUNetImpl& network);

  /// The pooled bottleneck of `input` ([B, C, S, S], float, contiguous): [B, C], without gradient.
  /// Safe to call from several threads at once.
  torch::Tensor encode(const torch::Tensor& input) const;

  /// True when the snapshot runs on oneDNN (false: the network's own encode()).
  bool usesOneDnn() const { return network_ == nullptr; }

 private:
  // One step of the encoder, in order: a convolution, a ReLU, a BatchNorm, or the start or end
  // of a residual block (x + block(x)).
  struct Step {
    enum class Kind { kConv, kRelu, kNorm, kResidualStart, kResidualEnd };
    Kind kind = Kind::kRelu;
    torch::Tensor weight, bias;               // kConv: reordered weight; kNorm: scale and shift
    torch::Tensor running_mean, running_var;  // kNorm
    double eps = 0.0;                         // kNorm
    std::vector<int64_t> padding, stride, dilation;  // kConv
  };
  static Step residualStep(Step::Kind kind) {
    Step step;
    step.kind = kind;
    return step;
  }
  void addConv(const torch::nn::Conv2dImpl& conv);
  void addSequential(const torch::nn::Sequential& sequence);

  std::vector<Step> steps_;
  MultiTaskUNetImpl* network_ = nullptr;  // set only without oneDNN
};

}  // namespace learning
}  // namespace occlusion_env
