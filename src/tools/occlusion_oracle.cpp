// occlusion_oracle: the oracle's answer (fewest steps to an unoccluded view, first direction) on
// the scenes of a scene set, its cost per query, and, with --compare, how often a finer lattice
// gives another step count (the check behind the default spacing; doc/ORACLE.md).
//   occlusion_oracle --scenes config/scenes/test_embedded.yaml --limit 20 --compare 0.25
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include "occlusion_env/agents/oracle.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_oracle --scenes FILE [options]
Runs the oracle at each scene's start view and prints its step count, first direction and cost.

Options:
  --scenes FILE      a scene set (config/scenes/*.yaml)
  --limit N          only the first N scenes
  --size N           image width and height [px] (default 128)
  --spacing S        lattice spacing in steps, (0, 1] (default 0.5)
  --compare S        also run a second oracle with spacing S and count differing answers
  --help             this text
)";

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// The oracle's answer from the start view of each scene of the set (at most `limit`), as CSV on
// stdout, with `compare` > 0 beside a second lattice spacing; a summary on stderr.
int runOracle(const std::string& scenes_path, int limit, int size, double spacing, double compare) {
  using namespace occlusion_env;
  try {
    SceneSet set = loadSceneSet(scenes_path);
    if (limit > 0 && static_cast<std::size_t>(limit) < set.seeds.size()) set.seeds.resize(limit);
    EnvironmentOptions options = environmentOptionsFor(set);
    options.width = options.height = size;
    Environment environment(options);
    OracleOptions oracle_options;
    oracle_options.lattice_spacing_steps = spacing;
    OcclusionOracle oracle(environment, oracle_options);
    oracle_options.lattice_spacing_steps = compare > 0.0 ? compare : spacing;
    OcclusionOracle finer(environment, oracle_options);
    std::vector<double> seconds, renders, steps;
    int differing = 0, compared = 0;
    std::cout << "seed,steps,first_direction_rad,renders,seconds"
              << (compare > 0.0 ? ",steps_compared" : "") << "\n";
    for (const std::uint64_t seed : set.seeds) {
      const StepResult start = environment.reset(seed, resetOptionsFor(set));
      oracle.clear();
      const auto begin = std::chrono::steady_clock::now();
      const OracleAnswer answer = oracle.query(start.info.pose);
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
      seconds.push_back(elapsed);
      renders.push_back(answer.poses_rendered);
      steps.push_back(answer.steps);
      std::cout << seed << ',' << answer.steps << ',' << std::setprecision(6)
                << answer.firstDirectionRad() << ',' << answer.poses_rendered << ',' << elapsed;
      if (compare > 0.0) {
        finer.clear();
        const OracleAnswer other = finer.query(start.info.pose);
        ++compared;
        differing += other.steps != answer.steps;
        std::cout << ',' << other.steps;
      }
      std::cout << "\n";
    }
    double mean_steps = 0.0;
    for (const double value : steps) mean_steps += value / steps.size();
    std::cerr << "occlusion_oracle: " << set.seeds.size() << " scenes of " << set.name << " at "
              << size << " px, spacing " << spacing << " steps: mean " << std::fixed
              << std::setprecision(2) << mean_steps << " steps, median " << median(seconds)
              << " s and " << median(renders) << " renders per query";
    if (compare > 0.0) {
      std::cerr << "; spacing " << compare << " differs on " << differing << " of " << compared;
    }
    std::cerr << "\n";
  } catch (const std::exception& error) {
    std::cerr << "occlusion_oracle: " << error.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  std::string scenes_path;
  int limit = 0, size = 128;
  double spacing = 0.5, compare = 0.0;
  try {
    tools::ArgumentReader reader(argc, argv);
    while (reader.next()) {
      const std::string& flag = reader.flag();
      if (flag == "--help" || flag == "-h") {
        std::cout << kUsage;
        return 0;
      } else if (flag == "--scenes") {
        scenes_path = reader.text();
      } else if (flag == "--limit") {
        limit = static_cast<int>(reader.integer(1, 1000000));
      } else if (flag == "--size") {
        size = static_cast<int>(reader.integer(64, 1024));
      } else if (flag == "--spacing") {
        spacing = reader.number(1e-3, 1.0);
      } else if (flag == "--compare") {
        compare = reader.number(1e-3, 1.0);
      } else {
        reader.unknown();
      }
    }
    if (scenes_path.empty()) throw tools::ArgumentError("--scenes is required");
  } catch (const tools::ArgumentError& error) {
    std::cerr << "occlusion_oracle: " << error.what() << "\n" << kUsage;
    return 2;
  }
  return runOracle(scenes_path, limit, size, spacing, compare);
}
