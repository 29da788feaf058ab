// occlusion_soak: drives the core environment for many steps and watches memory and step rate.
//   occlusion_soak --steps 100000 --reset-every 50          (the long soak, BENCHMARKS.md)
//   occlusion_soak --steps 3000 --check                     (the short form `make test` runs)
// Prints, every --report-every steps, the step rate over the last window and the resident set
// size. With --check it exits 1 when memory grew more than --max-growth-mb after warm-up, or when
// the last window's rate fell below --min-rate-ratio of the first's.
#include <iomanip>
#include <iostream>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/soak.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_soak [options]
  --steps N           total steps (default 100000)
  --reset-every N     reset after this many steps, or when an episode ends (default 50)
  --report-every N    report the rate and memory every N steps (default 5000)
  --warmup N          steps before the memory baseline is taken (default 1000)
  --size N            image width and height [px] (default 256)
  --source S          object source: embedded | sweethome3d | folder (default embedded)
  --check             exit 1 if memory grows or the rate decays beyond the limits below
  --max-growth-mb X   allowed resident-memory growth after warm-up (default 5)
  --min-rate-ratio X  last window's rate / first window's rate at least this (default 0.7)
)";

/// Runs the soak on the in-process simulator and prints its windows and summary; the exit
/// status (1: a step or reset failed, or with `check` a limit was exceeded).
int runInProcessSoak(const occlusion_env::EnvironmentOptions& options,
                     const occlusion_env::eval::SoakOptions& soak, bool check,
                     double max_growth_mib, double min_rate_ratio) {
  using namespace occlusion_env;
  Environment env(options);
  eval::SoakHooks hooks;
  hooks.resident_mib = [] { return eval::residentMiB(); };
  hooks.on_window = [](const eval::SoakWindow& w) {
    std::cout << std::setw(9) << w.step << std::setw(11) << w.resets << std::setw(10)
              << w.steps_per_s << std::setw(10) << w.resident_mib << std::endl;
  };
  hooks.on_failure = [](long step, const std::string& what) {
    std::cerr << "occlusion_soak: step " << step << ": " << what << "\n";
  };
  std::cout << std::fixed << std::setprecision(1) << "    steps   episodes   steps/s   RSS MiB\n";
  const eval::SoakReport r = eval::runSoak(env, soak, hooks);
  const double growth = r.growthMiB();
  std::cout << std::setprecision(2) << "summary: " << r.steps << " steps, " << r.resets
            << " resets, " << r.seconds << " s (" << r.steps / r.seconds
            << " steps/s incl. resets); RSS after warm-up " << r.baseline_mib << " MiB, at the end "
            << r.end_mib << " MiB (growth " << growth << " MiB, peak " << r.peak_mib
            << " MiB); rate first window " << r.first_rate << "/s, last " << r.last_rate
            << "/s (ratio " << r.rateRatio() << ")\n";
  if (r.failures > 0) return 1;  // reported as they happened
  if (check && growth > max_growth_mib) {
    std::cerr << "occlusion_soak: memory grew " << growth << " MiB > " << max_growth_mib << "\n";
    return 1;
  }
  if (check && r.last_rate < min_rate_ratio * r.first_rate) {
    std::cerr << "occlusion_soak: step rate decayed to " << r.rateRatio()
              << " of the first window's\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  long total_steps = 100000, reset_every = 50, report_every = 5000, warmup = 1000;
  double max_growth_mib = 5.0, min_rate_ratio = 0.7;
  bool check = false;
  EnvironmentOptions options;
  try {
    tools::ArgumentReader args(argc, argv);
    constexpr long long kMany = 1'000'000'000'000;
    while (args.next()) {
      const std::string& flag = args.flag();
      if (flag == "--help" || flag == "-h") {
        std::cout << kUsage;
        return 0;
      } else if (flag == "--steps") {
        total_steps = args.integer(1, kMany);
      } else if (flag == "--reset-every") {
        reset_every = args.integer(1, kMany);
      } else if (flag == "--report-every") {
        report_every = args.integer(1, kMany);
      } else if (flag == "--warmup") {
        warmup = args.integer(0, kMany);
      } else if (flag == "--size") {
        options.width = options.height = static_cast<int>(args.integer(1, 1 << 16));
      } else if (flag == "--source") {
        options.catalog.source = args.text();
      } else if (flag == "--check") {
        check = true;
      } else if (flag == "--max-growth-mb") {
        max_growth_mib = args.number(0.0, 1e9);
      } else if (flag == "--min-rate-ratio") {
        min_rate_ratio = args.number(0.0, 1e9);
      } else {
        args.unknown();
      }
    }
    if (total_steps <= warmup || reset_every < 1 || report_every < 1 || warmup < 0) {
      throw std::invalid_argument("need steps > warmup >= 0, reset-every >= 1, report-every >= 1");
    }
  } catch (const std::exception& error) {
    std::cerr << "occlusion_soak: " << error.what() << "\n" << kUsage;
    return 2;
  }

  try {
    eval::SoakOptions soak;
    soak.total_steps = total_steps;
    soak.reset_every = reset_every;
    soak.report_every = report_every;
    soak.warmup = warmup;
    return runInProcessSoak(options, soak, check, max_growth_mib, min_rate_ratio);
  } catch (const std::exception& error) {
    std::cerr << "occlusion_soak: " << error.what() << "\n";
    return 1;
  }
}
