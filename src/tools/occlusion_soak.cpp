// occlusion_soak: drives the core environment for many steps and watches memory and step rate.
//   occlusion_soak --steps 100000 --reset-every 50          (the long soak, BENCHMARKS.md)
//   occlusion_soak --steps 3000 --check                     (the short form `make test` runs)
// Prints, every --report-every steps, the step rate over the last window and the resident set
// size. With --check it exits 1 when memory grew more than --max-growth-mb after warm-up, or when
// the last window's rate fell below --min-rate-ratio of the first's.
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/random.hpp"
#include "occlusion_env/env/environment.hpp"
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

/// Resident set size of this process [MiB], from /proc/self/statm.
double residentMiB() {
  std::ifstream statm("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  statm >> pages_total >> pages_resident;
  return static_cast<double>(pages_resident) * sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0);
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
    Environment env(options);
    RandomSource random(12345);
    std::uint64_t episode = 0;
    long steps_in_episode = 0;
    const auto resetNext = [&] {
      // Seeds whose draws find no occluded start view are skipped, as a training loop would.
      for (int tries = 0; tries < 100; ++tries) {
        try {
          env.reset(episode++);
          steps_in_episode = 0;
          return;
        } catch (const SceneGenerationError&) {
        }
      }
      throw SceneGenerationError("100 consecutive seeds without an occluded start view");
    };
    resetNext();

    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto window_start = start;
    double baseline_mib = residentMiB(), first_rate = 0.0, last_rate = 0.0, peak_mib = 0.0;
    std::cout << std::fixed << std::setprecision(1) << "    steps   episodes   steps/s   RSS MiB\n";
    for (long step = 1; step <= total_steps; ++step) {
      const double angle = random.uniform(-M_PI, M_PI);
      const StepResult result = env.step({std::cos(angle), std::sin(angle)});
      ++steps_in_episode;
      if (result.terminated || result.truncated || steps_in_episode >= reset_every) resetNext();
      if (step == warmup) baseline_mib = residentMiB();
      if (step % report_every == 0 || step == total_steps) {
        const auto now = Clock::now();
        const long window_steps = step % report_every == 0 ? report_every : step % report_every;
        const double rate =
            window_steps / std::chrono::duration<double>(now - window_start).count();
        window_start = now;
        if (first_rate == 0.0) first_rate = rate;
        last_rate = rate;
        const double rss = residentMiB();
        if (step > warmup) peak_mib = std::max(peak_mib, rss);
        std::cout << std::setw(9) << step << std::setw(11) << episode << std::setw(10) << rate
                  << std::setw(10) << rss << std::endl;
      }
    }
    const double end_mib = residentMiB();
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const double growth = end_mib - baseline_mib;
    std::cout << std::setprecision(2) << "summary: " << total_steps << " steps, " << episode
              << " resets, " << seconds << " s (" << total_steps / seconds
              << " steps/s incl. resets); RSS after warm-up " << baseline_mib << " MiB, at the end "
              << end_mib << " MiB (growth " << growth << " MiB, peak " << peak_mib
              << " MiB); rate first window " << first_rate << "/s, last " << last_rate
              << "/s (ratio " << last_rate / first_rate << ")\n";
    if (check && growth > max_growth_mib) {
      std::cerr << "occlusion_soak: memory grew " << growth << " MiB > " << max_growth_mib << "\n";
      return 1;
    }
    if (check && last_rate < min_rate_ratio * first_rate) {
      std::cerr << "occlusion_soak: step rate decayed to " << last_rate / first_rate
                << " of the first window's\n";
      return 1;
    }
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "occlusion_soak: " << error.what() << "\n";
    return 1;
  }
}
