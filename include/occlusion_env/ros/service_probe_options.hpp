// The options of the two nodes that probe a running simulator through its services:
// occlusion_service_bench (what the service adds to a step) and occlusion_service_soak (memory
// and rate over many steps). Both read them from their private parameters.
#pragma once

#include <string>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/eval/soak.hpp"
#include "occlusion_env/ros/names.hpp"

namespace occlusion_env {

struct ServiceBenchOptions {
  int steps = 500;          // timed steps on each side
  int seed = 1;             // the scene of every episode
  double timeout_s = 60.0;  // wait this long for the simulator's services
  std::string simulator = std::string("/") + names::kSimulatorNode;  // its parameters: options
};

struct ServiceSoakOptions {
  eval::SoakOptions soak =
      shorterSoak();        // the soak loop: steps, reset_every, report_every, warmup
  eval::SoakLimits limits;  // check, max_growth_mb, min_rate_ratio
  std::string simulator = std::string("/") + names::kSimulatorNode;  // whose memory is watched

  /// Through the services a step costs more: 20,000 steps, a line every 2,000.
  static eval::SoakOptions shorterSoak() {
    eval::SoakOptions soak;
    soak.total_steps = 20000;
    soak.report_every = 2000;
    return soak;
  }
};

/// occlusion_service_bench's parameters (names relative to its private namespace).
const OptionTable<ServiceBenchOptions>& serviceBenchOptionTable();

/// occlusion_service_soak's parameters (names relative to its private namespace).
const OptionTable<ServiceSoakOptions>& serviceSoakOptionTable();

}  // namespace occlusion_env
