// occlusion_oracle: the oracle's answer (fewest steps to an unoccluded view, first direction) on
// the scenes of a scene set, its cost per query, and, with --compare, how often a finer lattice
// gives another step count (the check behind the default spacing; doc/ORACLE.md), and, with
// --follow-error, how many steps an agent needs whose every move is the oracle's first move off
// by a random angle (how precise an escape head must be; doc/ORACLE.md).
//   occlusion_oracle --scenes config/scenes/test_embedded.yaml --limit 20 --compare 0.25
//   occlusion_oracle --scenes config/scenes/validation_sweethome3d_200.yaml --follow-error 30
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "occlusion_env/agents/oracle.hpp"
#include "occlusion_env/common/statistics.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

using occlusion_env::mean;
using occlusion_env::median;
using occlusion_env::OptionSpec;
using occlusion_env::OptionTable;

/// The tool's own options; the oracle's come from oracleOptionTable().
struct Arguments {
  occlusion_env::OracleOptions oracle;
  std::string scenes_path;
  int limit = 0;  // 0: every scene
  int size = 128;
  std::optional<double> compare;  // a second lattice spacing [steps]
  // [deg] standard deviation of the error added to each followed move; unset: no episodes
  std::optional<double> follow_error_deg;
};

const OptionTable<Arguments>& argumentTable() {
  static const auto table =
      OptionTable<Arguments>()
          .add("scenes", &Arguments::scenes_path,
               OptionSpec("a scene set (config/scenes/*.yaml); required"))
          .add("limit", &Arguments::limit,
               OptionSpec("only the first N scenes; 0 = all").range(0, 1000000))
          .add("size", &Arguments::size,
               OptionSpec("image width and height").unit("px").range(64, 1024))
          .add("compare", &Arguments::compare,
               OptionSpec("also run a second oracle with this spacing and count differing answers")
                   .unit("steps")
                   .above(0)
                   .atMost(1))
          .add("follow_error", &Arguments::follow_error_deg,
               OptionSpec("also run each scene's episode with every move the oracle's first move "
                          "from the current view turned by a normal error of this standard "
                          "deviation (drawn from the scene's seed), failures at max_steps")
                   .unit("deg")
                   .range(0, 180));
  return table;
}

/// What the queries cost and answered, for the summary line.
struct Tally {
  std::vector<double> seconds, renders, steps, followed_steps;
  int differing = 0, compared = 0;
};

void printSummary(const Arguments& args, const occlusion_env::SceneSet& set, const Tally& tally) {
  const double mean_steps = mean(tally.steps);
  std::cerr << "occlusion_oracle: " << set.seeds.size() << " scenes of " << set.name << " at "
            << args.size << " px, spacing " << args.oracle.lattice_spacing_steps << " steps: mean "
            << std::fixed << std::setprecision(2) << mean_steps << " steps, median "
            << median(tally.seconds) << " s and " << median(tally.renders) << " renders per query";
  if (args.compare) {
    std::cerr << "; spacing " << *args.compare << " differs on " << tally.differing << " of "
              << tally.compared;
  }
  if (args.follow_error_deg) {
    const double mean_followed = mean(tally.followed_steps);
    std::cerr << "; followed with a " << *args.follow_error_deg << " deg error: mean "
              << mean_followed << " steps (" << mean_followed / mean_steps << "x the oracle's)";
  }
  std::cerr << "\n";
}

int run(const Arguments& args) {
  using namespace occlusion_env;
  SceneSet set = loadSceneSet(args.scenes_path);
  if (args.limit > 0 && static_cast<std::size_t>(args.limit) < set.seeds.size()) {
    set.seeds.resize(args.limit);
  }
  EnvironmentOptions options = environmentOptionsFor(set);
  options.width = options.height = args.size;
  Environment environment(options);
  OcclusionOracle oracle(environment, args.oracle);
  OracleOptions finer_options = args.oracle;
  finer_options.lattice_spacing_steps = args.compare.value_or(args.oracle.lattice_spacing_steps);
  OcclusionOracle finer(environment, finer_options);
  Tally tally;
  std::cout << "seed,steps,first_direction_rad,renders,seconds"
            << (args.compare ? ",steps_compared" : "")
            << (args.follow_error_deg ? ",steps_followed" : "") << "\n";
  for (const std::uint64_t seed : set.seeds) {
    const StepResult start = environment.reset(seed, resetOptionsFor(set));
    oracle.clear();
    const auto begin = std::chrono::steady_clock::now();
    const OracleAnswer answer = oracle.query(start.info.pose);
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    tally.seconds.push_back(elapsed);
    tally.renders.push_back(answer.poses_rendered);
    tally.steps.push_back(answer.steps);
    std::cout << seed << ',' << answer.steps << ',' << std::setprecision(6)
              << answer.firstDirectionRad() << ',' << answer.poses_rendered << ',' << elapsed;
    if (args.compare) {
      finer.clear();
      const OracleAnswer other = finer.query(start.info.pose);
      ++tally.compared;
      tally.differing += other.steps != answer.steps;
      std::cout << ',' << other.steps;
    }
    if (args.follow_error_deg) {
      const int followed = followOracleWithError(environment, oracle, start,
                                                 *args.follow_error_deg * M_PI / 180.0, seed);
      tally.followed_steps.push_back(followed);
      std::cout << ',' << followed;
    }
    std::cout << "\n";
  }
  printSummary(args, set, tally);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  Arguments args;
  CLI::App app(
      "Runs the oracle at each scene's start view and prints its step count, first direction and "
      "cost.",
      "occlusion_oracle");
  tools::addOptionFlags(app, argumentTable(), args, {"scenes", "limit", "size"});
  tools::addOptionFlags(app, oracleOptionTable(), args.oracle, {"lattice_spacing_steps"});
  tools::addOptionFlags(app, argumentTable(), args, {"compare", "follow_error"});
  app.callback([&args] {
    if (args.scenes_path.empty()) throw CLI::ValidationError("--scenes is required");
  });
  return tools::parseAndRun(app, argc, argv, [&args] { return run(args); });
}
