#include "occlusion_env/ros/service_probe_options.hpp"

namespace occlusion_env {

const OptionTable<ServiceBenchOptions>& serviceBenchOptionTable() {
  using Options = ServiceBenchOptions;
  static const auto table =
      OptionTable<Options>()
          .add("steps", &Options::steps, OptionSpec("timed steps on each side").atLeast(2))
          .add("seed", &Options::seed, OptionSpec("scene seed of every episode").atLeast(0))
          .add("timeout", &Options::timeout_s,
               OptionSpec("wait this long for the simulator's services").unit("s").above(0))
          .add("simulator", &Options::simulator,
               OptionSpec("the simulator node, whose parameters give the in-process options"));
  return table;
}

const OptionTable<ServiceSoakOptions>& serviceSoakOptionTable() {
  using Options = ServiceSoakOptions;
  static const auto table =
      OptionTable<Options>()
          .include(eval::soakOptionTable(), [](Options& o) -> eval::SoakOptions& { return o.soak; })
          .include(eval::soakLimitsTable(),
                   [](Options& o) -> eval::SoakLimits& { return o.limits; })
          .add("simulator", &Options::simulator,
               OptionSpec("the simulator node, whose memory is watched (same machine)"));
  return table;
}

}  // namespace occlusion_env
