// occlusion_agents: runs agents of the registry on N seeded scenes, in process, and prints the
// steps each needs to an unoccluded view (the paper's Table 4 protocol).
//   occlusion_agents --scenes 50
//   occlusion_agents --scenes 50 --source sweethome3d --category chair --category table
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/tools/arguments.hpp"

namespace {

constexpr const char* kUsage = R"(Usage: occlusion_agents [options]
Runs agents on the same seeded scenes (start azimuth 0) and prints, per agent, the mean and
standard deviation of the steps to an unoccluded view (a failure counts as --max-steps), the
number of failures and the success rate.

Options:
  --agents A,B,...    agents by name (default: every competing agent; --help lists them)
  --scenes N          number of scenes, seeds first-seed .. first-seed + N - 1 (default 50)
  --first-seed N      (default 0)
  --max-steps N       steps per episode (default 50)
  --source S          embedded | sweethome3d | folder (default embedded)
  --path P            a .sh3f file or folder (sweethome3d), the root (folder); repeatable
  --category C        draw objects of this category only; repeatable
  --model-split S     all | train | test: draw only models of this split (default all)
  --model PATH        model file for the agents that need one (default: each one's shipped model)
  --size N            image width and height [px] (default 256)
  --gradient M        the simulator's gradient: analytic | finite_difference (default analytic)
  --agents-markdown   print the registry's agents as the README's Markdown table and exit
  --help              this text

Agents:
)";

[[noreturn]] void fail(const std::string& message) {
  std::cerr << "occlusion_agents: " << message << "\n(--help lists the options)\n";
  std::exit(2);
}

struct Arguments {
  occlusion_env::EnvironmentOptions options;
  std::vector<std::string> agents;  // empty: the registry's competitors
  int scenes = 50;
  int first_seed = 0;
  int max_steps = 50;
  std::string model;  // "" = each agent's shipped model
};

void printUsage(const occlusion_env::AgentRegistry& registry) {
  std::cout << kUsage;
  for (const occlusion_env::AgentEntry& entry : registry.entries()) {
    std::cout << "  " << std::left << std::setw(18) << entry.name << " " << entry.summary
              << (entry.competes ? "" : " (a reference, not a competitor)") << "\n";
  }
}

// The README's table of agents (between its agents-table markers).
void printAgentsMarkdown(const occlusion_env::AgentRegistry& registry) {
  std::cout << "| agent | what it does | needs | paper |\n| --- | --- | --- | --- |\n";
  for (const occlusion_env::AgentEntry& entry : registry.entries()) {
    std::string needs;
    if (entry.needs.occlusion_gradient) needs += "the simulator's gradient service; ";
    if (entry.needs.simulation) needs += "the in-process simulation (a reference); ";
    if (entry.needs.model_file) needs += "a model file; ";
    needs = needs.empty() ? "RGB-D only" : needs.substr(0, needs.size() - 2);
    std::cout << "| `" << entry.name << "` | " << entry.summary << " | " << needs << " | "
              << (entry.paper_label.empty() ? "-" : entry.paper_label) << " |\n";
  }
}

Arguments parse(int argc, char** argv, const occlusion_env::AgentRegistry& registry) {
  Arguments args;
  occlusion_env::tools::ArgumentReader reader(argc, argv);
  try {
    while (reader.next()) {
      const std::string& flag = reader.flag();
      if (flag == "--help" || flag == "-h") {
        printUsage(registry);
        std::exit(0);
      } else if (flag == "--agents-markdown") {
        printAgentsMarkdown(registry);
        std::exit(0);
      } else if (flag == "--agents") {
        args.agents = reader.list();
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
        args.options.gradient_method = reader.text();
      } else if (flag == "--model") {
        args.model = reader.text();
      } else if (flag == "--model-split") {
        args.options.scene.model_split = occlusion_env::parseModelSplit(reader.text());
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

int run(const Arguments& args, const occlusion_env::AgentRegistry& registry) {
  using namespace occlusion_env;
  const std::vector<std::string> names = args.agents.empty() ? registry.competitors() : args.agents;
  Environment environment(args.options);
  std::vector<std::unique_ptr<Agent>> agents;
  for (const std::string& name : names) {
    agents.push_back(registry.make(name, {environment, args.model}));
  }
  std::vector<std::vector<EpisodeRecord>> episodes(names.size());
  EpisodeRunOptions run_options;
  run_options.max_steps = args.max_steps;
  const auto start = std::chrono::steady_clock::now();
  for (int scene = 0; scene < args.scenes; ++scene) {
    EpisodeRequest request;
    request.seed = static_cast<std::uint64_t>(args.first_seed + scene);
    request.scene_set = "occlusion_agents";
    request.reset.start_azimuth_rad = 0.0;
    for (std::size_t a = 0; a < names.size(); ++a) {
      request.agent = names[a];
      EpisodeRecord record = runEpisode(environment, *agents[a], request, run_options);
      if (!record.completed()) throw std::runtime_error(names[a] + ": " + record.message);
      episodes[a].push_back(std::move(record));
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
            << " steps, gradient " << args.options.gradient_method << "\n";
  std::cout << "agent     steps mean +/- std   failures   success\n";
  for (std::size_t a = 0; a < names.size(); ++a) {
    const EpisodeStatistics stats = summarizeEpisodes(episodes[a]);
    const int failures = stats.completed - stats.successes;
    std::cout << std::left << std::setw(9) << names[a] << std::right << std::fixed
              << std::setprecision(1) << std::setw(7) << stats.mean_steps << " +/- " << std::setw(5)
              << (stats.completed > 1 ? stats.sd_steps : 0.0) << "   " << std::setw(4) << failures
              << "/" << stats.completed << "   " << std::setw(6) << 100.0 * stats.successRate()
              << " %\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const occlusion_env::AgentRegistry registry = occlusion_env::learning::learningAgents();
  const Arguments args = parse(argc, argv, registry);
  try {
    return run(args, registry);
  } catch (const std::exception& error) {
    std::cerr << "occlusion_agents: " << error.what() << "\n";
    return 1;
  }
}
