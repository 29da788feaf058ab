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
          .add("steps", &Options::steps, OptionSpec("steps through the services").atLeast(1))
          .add("reset_every", &Options::reset_every,
               OptionSpec("steps per episode at most").atLeast(1))
          .add("report_every", &Options::report_every,
               OptionSpec("steps per line of the report").atLeast(1))
          .add("warmup", &Options::warmup,
               OptionSpec("steps before the memory baseline is taken").atLeast(0))
          .add("check", &Options::check,
               OptionSpec("exit 1 when a request failed, memory grew or the rate decayed beyond "
                          "the limits"))
          .add("max_growth_mb", &Options::max_growth_mib,
               OptionSpec("check: the simulator's memory growth after warm-up at most")
                   .unit("MiB")
                   .atLeast(0))
          .add("min_rate_ratio", &Options::min_rate_ratio,
               OptionSpec("check: the last window's step rate at least this part of the first's")
                   .range(0, 1))
          .add("simulator", &Options::simulator,
               OptionSpec("the simulator node, whose memory is watched (same machine)"));
  return table;
}

}  // namespace occlusion_env
