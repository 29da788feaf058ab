// Adam with gradient clipping for a fixed set of small parameters (a PPO actor's or critic's
// MLP), stepped as one flat vector. torch::optim::Adam and clip_grad_norm_ issue about a dozen
// tensor operations per parameter, and for MLPs of a few thousand weights those operations'
// overhead, not their arithmetic, is the cost (BENCHMARKS.md, "PPO training"). Here the
// gradients are views into one flat buffer that backward() accumulates into, so a step is a
// handful of operations on that buffer and one add per parameter.
//
//   FlatAdam adam(policy->actorParameters(), 3e-4);
//   adam.zeroGrad();  loss.backward();  adam.step(0.5);  // clip to a norm of 0.5, then step
//
// The arithmetic is torch::optim::Adam's (betas 0.9 and 0.999, eps 1e-8, no weight decay) after
// clip_grad_norm_'s scaling, to float rounding (tested against both).
#pragma once

#include <torch/torch.h>

#include <cstdint>
#include <vector>

namespace occlusion_env {
namespace learning {

class FlatAdam {
 public:
  /// The parameters (each of which must require grad) keep their storage; their gradients become
  /// views of the flat buffer, zero.
  FlatAdam(std::vector<torch::Tensor> parameters, double learning_rate);

  /// Zeroes every gradient.
  void zeroGrad();
  /// Scales the gradients so that their joint L2 norm is at most `max_grad_norm` (not when 0),
  /// as clip_grad_norm_ does, then takes one Adam step.
  void step(double max_grad_norm);

  /// The moments and the step count, under `archive`.
  void save(torch::serialize::OutputArchive& archive) const;
  /// What save() wrote, or a torch::optim::Adam's state of the same parameters (the PPO
  /// trainer's checkpoints before FlatAdam).
  void load(torch::serialize::InputArchive& archive);

 private:
  // Makes each parameter's gradient a view of gradients_ again, keeping what it held (another
  // owner may have replaced it).
  void linkGradients();

  std::vector<torch::Tensor> parameters_;
  std::vector<std::int64_t> offsets_;  // parameter i is [offsets_[i], offsets_[i + 1])
  double learning_rate_;
  // Flat, float; the step's denominator and update are kept so that a step allocates nothing.
  torch::Tensor gradients_, exp_avg_, exp_avg_sq_, denominator_, update_;
  // Parameter i's shape over gradients_ and update_, made once.
  std::vector<torch::Tensor> gradient_views_, update_views_;
  std::int64_t steps_ = 0;
};

}  // namespace learning
}  // namespace occlusion_env
