// occlusion_step_rate: the C++ step rate of scenes and actions that bench/python_step_rate.py
// also runs through the Python bindings, so the two rates compare the same work.
//   occlusion_step_rate OPTIONS_JSON FIRST_SEED EPISODES STEPS
// Episode e resets with seed FIRST_SEED + e (untimed), then steps with action t =
// (cos(0.3 t), sin(0.3 t)) * step_size until it ends or STEPS steps (timed). Prints
// "steps <n> seconds <s> steps_per_second <r>".
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>

#include "occlusion_env/env/environment.hpp"

int main(int argc, char** argv) {
  using namespace occlusion_env;
  if (argc != 5) {
    std::cerr << "usage: occlusion_step_rate OPTIONS_JSON FIRST_SEED EPISODES STEPS\n";
    return 2;
  }
  try {
    EnvironmentOptions options;
    environmentOptionTable().applyJson(nlohmann::json::parse(argv[1]), options);
    const std::uint64_t first_seed = std::stoull(argv[2]);
    const int episodes = std::stoi(argv[3]), steps = std::stoi(argv[4]);
    Environment environment(options);
    long total_steps = 0;
    std::chrono::duration<double> stepping{0};
    for (int episode = 0; episode < episodes; ++episode) {
      environment.reset(first_seed + episode);
      const auto start = std::chrono::steady_clock::now();
      for (int t = 0; t < steps; ++t) {
        const double s = options.step_size_rad;
        const StepResult result = environment.step({std::cos(0.3 * t) * s, std::sin(0.3 * t) * s});
        ++total_steps;
        if (result.terminated || result.truncated) break;
      }
      stepping += std::chrono::steady_clock::now() - start;
    }
    std::cout << "steps " << total_steps << " seconds " << stepping.count() << " steps_per_second "
              << total_steps / stepping.count() << "\n";
  } catch (const std::exception& error) {
    std::cerr << "occlusion_step_rate: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
