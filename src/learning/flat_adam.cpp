#include "occlusion_env/learning/flat_adam.hpp"

#include <c10/util/string_utils.h>

#include <cmath>
#include <stdexcept>

namespace occlusion_env {
namespace learning {
namespace {

constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kEps = 1e-8;  // torch::optim::AdamOptions'

}  // namespace

FlatAdam::FlatAdam(std::vector<torch::Tensor> parameters, double learning_rate)
    : parameters_(std::move(parameters)), learning_rate_(learning_rate) {
  offsets_.push_back(0);
  for (const torch::Tensor& p : parameters_) {
    if (!p.requires_grad() || p.scalar_type() != torch::kFloat) {
      throw std::invalid_argument("FlatAdam: parameters must be float and require grad");
    }
    offsets_.push_back(offsets_.back() + p.numel());
  }
  const std::int64_t size = offsets_.back();
  gradients_ = torch::zeros({size});
  exp_avg_ = torch::zeros({size});
  exp_avg_sq_ = torch::zeros({size});
  denominator_ = torch::empty({size});
  update_ = torch::empty({size});
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    const auto range = torch::indexing::Slice(offsets_[i], offsets_[i + 1]);
    gradient_views_.push_back(gradients_.index({range}).view_as(parameters_[i]));
    update_views_.push_back(update_.index({range}).view_as(parameters_[i]));
  }
  linkGradients();
}

void FlatAdam::linkGradients() {
  torch::NoGradGuard no_grad;
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    const torch::Tensor& view = gradient_views_[i];
    torch::Tensor& grad = parameters_[i].mutable_grad();
    if (grad.defined() && grad.data_ptr() == view.data_ptr()) continue;
    if (grad.defined()) {
      view.copy_(grad);
    } else {
      view.zero_();
    }
    grad = view;
  }
}

void FlatAdam::zeroGrad() {
  linkGradients();
  gradients_.zero_();
}

void FlatAdam::step(double max_grad_norm) {
  torch::NoGradGuard no_grad;
  linkGradients();  // backward() accumulated into the views, unless someone replaced them
  if (max_grad_norm > 0) {
    const double clip = max_grad_norm / (gradients_.norm().item<double>() + 1e-6);
    if (clip < 1.0) gradients_.mul_(clip);
  }
  ++steps_;
  const double bias_correction1 = 1.0 - std::pow(kBeta1, static_cast<double>(steps_));
  const double bias_correction2 = 1.0 - std::pow(kBeta2, static_cast<double>(steps_));
  exp_avg_.mul_(kBeta1).add_(gradients_, 1.0 - kBeta1);
  exp_avg_sq_.mul_(kBeta2).addcmul_(gradients_, gradients_, 1.0 - kBeta2);
  torch::sqrt_out(denominator_, exp_avg_sq_).div_(std::sqrt(bias_correction2)).add_(kEps);
  torch::div_out(update_, exp_avg_, denominator_).mul_(-learning_rate_ / bias_correction1);
  for (std::size_t i = 0; i < parameters_.size(); ++i) parameters_[i].add_(update_views_[i]);
}

void FlatAdam::save(torch::serialize::OutputArchive& archive) const {
  archive.write("flat_adam_steps", torch::tensor(steps_, torch::kLong));
  archive.write("flat_adam_exp_avg", exp_avg_);
  archive.write("flat_adam_exp_avg_sq", exp_avg_sq_);
}

void FlatAdam::load(torch::serialize::InputArchive& archive) {
  torch::NoGradGuard no_grad;
  torch::Tensor steps, exp_avg, exp_avg_sq;
  if (archive.try_read("flat_adam_steps", steps)) {
    archive.read("flat_adam_exp_avg", exp_avg);
    archive.read("flat_adam_exp_avg_sq", exp_avg_sq);
    if (exp_avg.sizes() != exp_avg_.sizes() || exp_avg_sq.sizes() != exp_avg_sq_.sizes()) {
      throw std::invalid_argument("FlatAdam: the saved state is for other parameters");
    }
    steps_ = steps.item<std::int64_t>();
    exp_avg_.copy_(exp_avg);
    exp_avg_sq_.copy_(exp_avg_sq);
    return;
  }
  // A torch::optim::Adam's state: per parameter, keyed by the parameter it was loaded for.
  torch::optim::Adam adam(parameters_);
  adam.load(archive);
  steps_ = 0;
  exp_avg_.zero_();
  exp_avg_sq_.zero_();
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    const auto found =
        adam.state().find(c10::guts::to_string(parameters_[i].unsafeGetTensorImpl()));
    if (found == adam.state().end()) continue;  // never stepped
    const auto& state = static_cast<const torch::optim::AdamParamState&>(*found->second);
    exp_avg_.slice(0, offsets_[i], offsets_[i + 1]).copy_(state.exp_avg().view(-1));
    exp_avg_sq_.slice(0, offsets_[i], offsets_[i + 1]).copy_(state.exp_avg_sq().view(-1));
    steps_ = state.step();
  }
}

}  // namespace learning
}  // namespace occlusion_env
