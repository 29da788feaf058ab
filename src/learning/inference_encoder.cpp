#include "occlusion_env/learning/inference_encoder.hpp"

#include <ATen/ATen.h>
#include <ATen/Parallel.h>

#include <stdexcept>
#include <string>

namespace occlusion_env {
namespace learning {
namespace {

namespace nn = torch::nn;

std::vector<int64_t> pair(const torch::ExpandingArray<2>& values) {
  return {(*values)[0], (*values)[1]};
}

}  // namespace

InferenceEncoder::InferenceEncoder(MultiTaskUNetImpl& network) {
  if (!at::hasMKLDNN() || !at::globalContext().userEnabledMkldnn()) {
    network_ = &network;
    return;
  }
  torch::NoGradGuard no_grad;
  const Step relu;  // a default Step is a ReLU
  addConv(*network.stem_);
  steps_.push_back(relu);
  for (int level = 0; level < network.config_.levels; ++level) {
    const auto& units = *network.encoder_units_[level]->as<ConvUnitsImpl>();
    if (units.residual_) steps_.push_back(residualStep(Step::Kind::kResidualStart));
    addSequential(units.units_);
    if (units.residual_) steps_.push_back(residualStep(Step::Kind::kResidualEnd));
    addConv(*network.downsamplers_[level]->as<nn::Conv2dImpl>());
    steps_.push_back(relu);
  }
}

void InferenceEncoder::addConv(const nn::Conv2dImpl& conv) {
  const auto& options = conv.options;
  const auto* padding = c10::get_if<torch::ExpandingArray<2>>(&options.padding());
  if (!padding || options.groups() != 1 || options.transposed() ||
      !c10::get_if<torch::enumtype::kZeros>(&options.padding_mode())) {
    throw std::logic_error("InferenceEncoder: a convolution it does not know (" +
                           std::string(conv.name()) + ")");
  }
  Step step;
  step.kind = Step::Kind::kConv;
  step.padding = pair(*padding);
  step.stride = pair(options.stride());
  step.dilation = pair(options.dilation());
  step.weight = at::mkldnn_reorder_conv2d_weight(conv.weight.detach().contiguous().to_mkldnn(),
                                                 step.padding, step.stride, step.dilation, 1);
  if (conv.bias.defined()) step.bias = conv.bias.detach().clone();
  steps_.push_back(std::move(step));
}

void InferenceEncoder::addSequential(const nn::Sequential& sequence) {
  for (const auto& module : sequence->children()) {
    if (const auto* conv = module->as<nn::Conv2dImpl>()) {
      addConv(*conv);
    } else if (module->as<nn::ReLUImpl>()) {
      steps_.push_back(Step());  // a ReLU
    } else if (const auto* norm = module->as<nn::BatchNorm2dImpl>()) {
      Step step;
      step.kind = Step::Kind::kNorm;
      step.weight = norm->weight.detach().clone();
      step.bias = norm->bias.detach().clone();
      step.running_mean = norm->running_mean.detach().clone();
      step.running_var = norm->running_var.detach().clone();
      step.eps = norm->options.eps();
      steps_.push_back(std::move(step));
    } else {
      throw std::logic_error("InferenceEncoder: a module it does not know (" + module->name() +
                             ")");
    }
  }
}

torch::Tensor InferenceEncoder::encode(const torch::Tensor& input) const {
  torch::NoGradGuard no_grad;
  if (network_) return network_->encode(input);
  // oneDNN runs on OpenMP, whose thread count is per calling thread: a thread libtorch has not
  // set up yet (an environment's) would use every core for each convolution and contend with the
  // other environments' threads. This gives it libtorch's count (one in training, by default).
  at::internal::lazy_init_num_threads();
  torch::Tensor x = input.to_mkldnn();
  torch::Tensor block_input;  // a residual block's input
  for (const Step& step : steps_) {
    switch (step.kind) {
      case Step::Kind::kConv:
        x = at::mkldnn_convolution(x, step.weight, step.bias, step.padding, step.stride,
                                   step.dilation, 1);
        break;
      case Step::Kind::kRelu:
        x = at::relu(x);
        break;
      case Step::Kind::kNorm:
        x = at::batch_norm(x, step.weight, step.bias, step.running_mean, step.running_var,
                           /*training=*/false, /*momentum=*/0.0, step.eps, /*cudnn_enabled=*/false);
        break;
      case Step::Kind::kResidualStart:
        block_input = x;
        break;
      case Step::Kind::kResidualEnd:
        x = at::add(block_input, x);
        break;
    }
  }
  return at::adaptive_avg_pool2d(x, {1, 1}).to_dense().flatten(1);
}

}  // namespace learning
}  // namespace occlusion_env
