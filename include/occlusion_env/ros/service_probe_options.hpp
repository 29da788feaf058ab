// The options of the two nodes that probe a running simulator through its services:
// occlusion_service_bench (what the service adds to a step) and occlusion_service_soak (memory
// and rate over many steps). Both read them from their private parameters.
#pragma once

#include <string>

#include "occlusion_env/common/option_table.hpp"
#include "occlusion_env/ros/names.hpp"

namespace occlusion_env {

struct ServiceBenchOptions {
  int steps = 500;          // timed steps on each side
  int seed = 1;             // the scene of every episode
  double timeout_s = 60.0;  // wait this long for the simulator's services
  std::string simulator = std::string("/") + names::kSimulatorNode;  // its parameters: options
};

struct ServiceSoakOptions {
  int steps = 20000;            // steps through the services
  int reset_every = 50;         // steps per episode at most
  int report_every = 2000;      // steps per line of the report
  int warmup = 1000;            // steps before the memory baseline is taken
  bool check = false;           // exit 1 on failures, memory growth or rate decay beyond the limits
  double max_growth_mib = 5.0;  // check: memory growth after warm-up at most [MiB]
  double min_rate_ratio = 0.7;  // check: the last window's rate at least this part of the first's
  std::string simulator = std::string("/") + names::kSimulatorNode;  // whose memory is watched
};

/// occlusion_service_bench's parameters (names relative to its private namespace).
const OptionTable<ServiceBenchOptions>& serviceBenchOptionTable();

/// occlusion_service_soak's parameters (names relative to its private namespace).
const OptionTable<ServiceSoakOptions>& serviceSoakOptionTable();

}  // namespace occlusion_env
