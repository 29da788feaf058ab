// occlusion_soak: drives the core environment for many steps and watches memory and step rate.
//   occlusion_soak --steps 100000 --reset-every 50          (the long soak, BENCHMARKS.md)
//   occlusion_soak --steps 3000 --check                     (the short form `make test` runs)
// Prints, every --report-every steps, the step rate over the last window and the resident set
// size. With --check it exits 1 when memory grew more than --max-growth-mb after warm-up, or when
// the last window's rate fell below --min-rate-ratio of the first's.
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/eval/soak.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

/// The soak's options, its limits and the scenes it runs on.
struct SoakCommandLine {
  occlusion_env::eval::SoakOptions soak;
  occlusion_env::eval::SoakLimits limits;
  occlusion_env::EnvironmentOptions environment;
  int size = 256;  // image width and height [px]
};

/// Runs the soak on the in-process simulator and prints its windows and summary; the exit
/// status (1: a step or reset failed, or with --check a limit was exceeded).
int runInProcessSoak(const SoakCommandLine& cl) {
  using namespace occlusion_env;
  EnvironmentOptions options = cl.environment;
  options.width = options.height = cl.size;
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
  const eval::SoakReport r = eval::runSoak(env, cl.soak, hooks);
  std::cout << std::setprecision(2) << "summary: " << r.steps << " steps, " << r.resets
            << " resets, " << r.seconds << " s (" << r.steps / r.seconds
            << " steps/s incl. resets); RSS after warm-up " << r.baseline_mib << " MiB, at the end "
            << r.end_mib << " MiB (growth " << r.growthMiB() << " MiB, peak " << r.peak_mib
            << " MiB); rate first window " << r.first_rate << "/s, last " << r.last_rate
            << "/s (ratio " << r.rateRatio() << ")\n";
  if (r.failures > 0) return 1;  // reported as they happened
  const std::vector<std::string> problems = eval::soakProblems(r, cl.limits);
  for (const std::string& problem : problems) std::cerr << "occlusion_soak: " << problem << "\n";
  return problems.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  SoakCommandLine cl;
  CLI::App app(
      "Drives the core environment for many steps and watches memory and step rate: every\n"
      "--report-every steps the rate over the last window and the resident set size.",
      "occlusion_soak");
  tools::addOptionFlags(app, eval::soakOptionTable(), cl.soak);
  tools::addOptionFlags(app, eval::soakLimitsTable(), cl.limits);
  app.add_option("--size", cl.size, "image width and height [px] (default 256)")
      ->check(CLI::Range(64, 1024));
  tools::addOptionFlags(app, environmentOptionTable(), cl.environment, {"catalog_source"});
  return tools::parseAndRun(app, argc, argv, [&cl] { return runInProcessSoak(cl); });
}
