// occlusion_learning_bench: the costs of the learning library's hot paths (Google Benchmark),
// on one libtorch thread as the trainer and the agents run them.
//   .build_ws/devel/lib/occlusion_env/occlusion_learning_bench
// BM_Encode: the shipped network's encoder on one 64 px frame, through MultiTaskUNet::encode
// (path:0) or InferenceEncoder (path:1); threads:2 runs two callers at once, as two environments'
// threads do in the PPO trainer. BM_HeadsOptimiserStep: clipping and one Adam step of a PPO
// actor's parameters with torch::optim::Adam + clip_grad_norm_ (flat:0) or FlatAdam (flat:1).
#include <benchmark/benchmark.h>

#include <torch/torch.h>

#include <memory>
#include <mutex>

#include "occlusion_env/learning/flat_adam.hpp"
#include "occlusion_env/learning/inference_encoder.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/model_file.hpp"
#include "occlusion_env/learning/policy.hpp"

namespace occlusion_env {
namespace learning {
namespace {

// The shipped network and its inference encoder, loaded once for all benchmarks.
struct Shipped {
  LoadedModel model;
  std::unique_ptr<InferenceEncoder> encoder;
};
Shipped& shipped() {
  static std::once_flag once;
  static Shipped loaded;
  std::call_once(once, [] {
    torch::set_num_threads(1);
    loaded.model = loadModel(defaultModelPath());
    loaded.model.network->eval();
    loaded.encoder = std::make_unique<InferenceEncoder>(*loaded.model.network);
  });
  return loaded;
}

void BM_Encode(benchmark::State& state) {
  Shipped& model = shipped();
  const bool inference_encoder = state.range(0) == 1;
  const int size = model.model.network->config().input_size;
  const torch::Tensor input = torch::rand({1, 4, size, size});
  torch::NoGradGuard no_grad;
  for (auto _ : state) {
    torch::Tensor features =
        inference_encoder ? model.encoder->encode(input) : model.model.network->encode(input);
    benchmark::DoNotOptimize(features.data_ptr<float>());
  }
}
BENCHMARK(BM_Encode)
    ->ArgName("path")
    ->Arg(0)
    ->Arg(1)
    ->Threads(1)
    ->Threads(2)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0)
    ->UseRealTime();

void BM_HeadsOptimiserStep(benchmark::State& state) {
  torch::set_num_threads(1);
  const bool flat = state.range(0) == 1;
  PolicyNetwork policy(NetworkConfig{}, PolicyConfig{});
  std::vector<torch::Tensor> parameters = policy->actorParameters();
  std::unique_ptr<FlatAdam> flat_adam;
  std::unique_ptr<torch::optim::Adam> adam;
  if (flat) {
    flat_adam = std::make_unique<FlatAdam>(parameters, 3e-4);
  } else {
    adam = std::make_unique<torch::optim::Adam>(parameters, torch::optim::AdamOptions(3e-4));
  }
  torch::manual_seed(1);
  std::vector<torch::Tensor> gradients;
  for (const auto& p : parameters) gradients.push_back(torch::randn_like(p));
  for (auto _ : state) {
    state.PauseTiming();  // the gradients as backward() would leave them
    {
      torch::NoGradGuard no_grad;
      for (std::size_t i = 0; i < parameters.size(); ++i) {
        torch::Tensor& grad = parameters[i].mutable_grad();
        if (grad.defined()) {
          grad.copy_(gradients[i]);
        } else {
          grad = gradients[i].clone();
        }
      }
    }
    state.ResumeTiming();
    if (flat) {
      flat_adam->step(0.5);
    } else {
      torch::nn::utils::clip_grad_norm_(parameters, 0.5);
      adam->step();
    }
  }
}
BENCHMARK(BM_HeadsOptimiserStep)
    ->ArgName("flat")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(1.0);

}  // namespace
}  // namespace learning
}  // namespace occlusion_env

BENCHMARK_MAIN();
