// occlusion_agents: runs the random and the gradient agent on N seeded scenes, in process, and
// prints the steps each needs to an unoccluded view (the paper's Table 4 protocol).
//   occlusion_agents --scenes 50
//   occlusion_agents --scenes 50 --source sweethome3d --category chair --category table
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/core/agent.hpp"
#include "occlusion_env/core/errors.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_agents [options]
Runs the random and the gradient agent on the same seeded scenes (start azimuth 0) and prints,
per agent, the mean and standard deviation of the steps to an unoccluded view (a failure counts
as --max-steps), the number of failures and the success rate.

Options:
  --scenes N          number of scenes, seeds first-seed .. first-seed + N - 1 (default 50)
  --first-seed N      (default 0)
  --max-steps N       steps per episode (default 50)
  --source S          embedded | sweethome3d | folder (default embedded)
  --path P            a .sh3f file or folder (sweethome3d), the root (folder); repeatable
  --category C        draw objects of this category only; repeatable
  --size N            image width and height [px] (default 256)
  --gradient M        analytic | finite_difference (default analytic)
  --help              this text
)";

[[noreturn]] void fail(const std::string& message) {
  std::cerr << "occlusion_agents: " << message << "\n(--help lists the options)\n";
  std::exit(2);
}

struct Arguments {
  occlusion_env::EnvironmentOptions options;
  int scenes = 50;
  int first_seed = 0;
  int max_steps = 50;
  std::string gradient = "analytic";
};

Arguments parse(int argc, char** argv) {
  Arguments args;
  occlusion_env::tools::ArgumentReader reader(argc, argv);
  try {
    while (reader.next()) {
      const std::string& flag = reader.flag();
      if (flag == "--help" || flag == "-h") {
        std::cout << kUsage;
        std::exit(0);
      } else if (flag == "--scenes") {
        args.scenes = static_cast<int>(reader.integer(1, 1000000));
      } else if (flag == "--first-seed") {
        args.first_seed = static_cast<int>(reader.integer(0, 1000000));
      } else if (flag == "--max-steps") {
        args.max_steps = static_cast<int>(reader.integer(1, 1000000));
      } else if (flag == "--source") {
        args.options.catalog.source = reader.text();
      } else if (flag == "--path") {
        args.options.catalog.paths.push_back(reader.text());
      } else if (flag == "--category") {
        args.options.scene.categories.push_back(reader.text());
      } else if (flag == "--size") {
        args.options.width = args.options.height = static_cast<int>(reader.integer(64, 1000000));
      } else if (flag == "--gradient") {
        args.gradient = reader.text();
      } else {
        reader.unknown();
      }
    }
  } catch (const occlusion_env::tools::ArgumentError& error) {
    fail(error.what());
  }
  args.options.max_steps = args.max_steps;
  return args;
}

struct Tally {
  std::vector<double> steps;  // failures counted at max_steps
  int failures = 0;
  int random_moves = 0;  // gradient agent: moves made at random on an invalid gradient
  int total_moves = 0;
};

int run(const Arguments& args) {
  using namespace occlusion_env;
  Environment env(args.options);
  std::unique_ptr<OcclusionGradient> gradient = makeOcclusionGradient(args.gradient);
  RandomAgent random_agent;
  GradientAgent gradient_agent(gradientSourceFor(env, *gradient));
  Agent* agents[] = {&random_agent, &gradient_agent};
  Tally tallies[2];
  ResetOptions reset;
  reset.start_azimuth_rad = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (int scene = 0; scene < args.scenes; ++scene) {
    const std::uint64_t seed = static_cast<std::uint64_t>(args.first_seed + scene);
    for (int a = 0; a < 2; ++a) {
      const EpisodeResult episode = runEpisode(env, *agents[a], seed, reset, args.max_steps);
      tallies[a].steps.push_back(episode.success ? episode.steps : args.max_steps);
      tallies[a].failures += !episode.success;
      tallies[a].total_moves += episode.steps;
      if (agents[a] == &gradient_agent) tallies[a].random_moves += gradient_agent.randomMoves();
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "\rscene " << scene + 1 << "/" << args.scenes << ", " << std::fixed
              << std::setprecision(1) << elapsed << " s" << std::flush;
  }
  std::cerr << "\n";

  std::cout << "source " << args.options.catalog.source << ", " << args.scenes << " scenes (seeds "
            << args.first_seed << ".." << args.first_seed + args.scenes - 1
            << "), start azimuth 0, " << args.options.width << " px, max " << args.max_steps
            << " steps, gradient " << gradient->name() << "\n";
  std::cout << "agent     steps mean +/- std   failures   success\n";
  for (int a = 0; a < 2; ++a) {
    const Tally& tally = tallies[a];
    double mean = 0.0, squares = 0.0;
    for (double steps : tally.steps) mean += steps / tally.steps.size();
    for (double steps : tally.steps) squares += (steps - mean) * (steps - mean);
    const double stddev =
        tally.steps.size() > 1 ? std::sqrt(squares / (tally.steps.size() - 1)) : 0.0;
    const int n = static_cast<int>(tally.steps.size());
    std::cout << std::left << std::setw(9) << agents[a]->name() << std::right << std::fixed
              << std::setprecision(1) << std::setw(7) << mean << " +/- " << std::setw(5) << stddev
              << "   " << std::setw(4) << tally.failures << "/" << n << "   " << std::setw(6)
              << 100.0 * (n - tally.failures) / n << " %";
    if (agents[a] == &gradient_agent) {
      std::cout << "   (" << tally.random_moves << " of " << tally.total_moves
                << " moves random on an invalid gradient)";
    }
    std::cout << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const Arguments args = parse(argc, argv);
  try {
    return run(args);
  } catch (const std::exception& error) {
    std::cerr << "occlusion_agents: " << error.what() << "\n";
    return 1;
  }
}
