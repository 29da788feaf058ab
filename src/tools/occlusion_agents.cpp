// occlusion_agents: runs agents of the registry on N seeded scenes, in process, and prints the
// steps each needs to an unoccluded view (the paper's Table 4 protocol).
//   occlusion_agents --scenes 50
//   occlusion_agents --scenes 50 --source sweethome3d --category chair --category table
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

using occlusion_env::OptionSpec;
using occlusion_env::OptionTable;

/// The tool's own options; the scenes' come from environmentOptionTable().
struct Arguments {
  occlusion_env::EnvironmentOptions options;
  std::vector<std::string> agents;  // empty: the registry's competitors
  int scenes = 50;
  int first_seed = 0;
  std::string model;  // "" = each agent's shipped model
  int size = 256;
  bool agents_markdown = false;
};

const OptionTable<Arguments>& argumentTable() {
  static const auto table =
      OptionTable<Arguments>()
          .add("agents", &Arguments::agents,
               OptionSpec("agents by name (empty: every competing agent; listed below)"))
          .add("scenes", &Arguments::scenes,
               OptionSpec("number of scenes, seeds first-seed .. first-seed + N - 1")
                   .range(1, 1000000))
          .add("first_seed", &Arguments::first_seed, OptionSpec("the first seed").range(0, 1000000))
          .add("model", &Arguments::model,
               OptionSpec("model file for the agents that need one (\"\": each one's shipped "
                          "model)"))
          .add("size", &Arguments::size,
               OptionSpec("image width and height").unit("px").range(64, 1024))
          .add("agents_markdown", &Arguments::agents_markdown,
               OptionSpec("print the registry's agents as doc/AGENTS.md's Markdown table and exit"));
  return table;
}

/// The registry's agents, one a line, for --help.
std::string agentList(const occlusion_env::AgentRegistry& registry) {
  std::ostringstream text;
  text << "Agents:\n";
  for (const occlusion_env::AgentEntry& entry : registry.entries()) {
    text << "  " << std::left << std::setw(18) << entry.name << " " << entry.summary
         << (entry.competes ? "" : " (a reference, not a competitor)") << "\n";
  }
  return text.str();
}

// doc/AGENTS.md's table of agents (between its agents-table markers).
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

/// Every agent's episodes on every scene, [agent][scene].
std::vector<std::vector<occlusion_env::EpisodeRecord>> runEpisodes(
    const Arguments& args, const occlusion_env::AgentRegistry& registry,
    const std::vector<std::string>& names) {
  using namespace occlusion_env;
  EnvironmentOptions options = args.options;
  options.width = options.height = args.size;
  Environment environment(options);
  std::vector<std::unique_ptr<Agent>> agents;
  for (const std::string& name : names) {
    agents.push_back(registry.make(name, {environment, args.model}));
  }
  std::vector<std::vector<EpisodeRecord>> episodes(names.size());
  EpisodeRunOptions run_options;
  run_options.max_steps = args.options.max_steps;
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
  return episodes;
}

int run(const Arguments& args, const occlusion_env::AgentRegistry& registry) {
  using namespace occlusion_env;
  if (args.agents_markdown) {
    printAgentsMarkdown(registry);
    return 0;
  }
  const std::vector<std::string> names = args.agents.empty() ? registry.competitors() : args.agents;
  const std::vector<std::vector<EpisodeRecord>> episodes = runEpisodes(args, registry, names);
  std::cout << "source " << args.options.catalog.source << ", " << args.scenes << " scenes (seeds "
            << args.first_seed << ".." << args.first_seed + args.scenes - 1
            << "), start azimuth 0, " << args.size << " px, max " << args.options.max_steps
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
  using namespace occlusion_env;
  const AgentRegistry registry = learning::learningAgents();
  Arguments args;
  CLI::App app(
      "Runs agents on the same seeded scenes (start azimuth 0) and prints, per agent, the mean "
      "and\nstandard deviation of the steps to an unoccluded view (a failure counts as "
      "--max-steps), the\nnumber of failures and the success rate.",
      "occlusion_agents");
  tools::addOptionFlags(app, argumentTable(), args, {"agents", "scenes", "first_seed"});
  tools::addOptionFlags(
      app, environmentOptionTable(), args.options,
      {"max_steps", "catalog_source", "catalog_paths", "categories", "model_split"});
  tools::addOptionFlags(app, argumentTable(), args, {"model", "size"});
  tools::addOptionFlags(app, environmentOptionTable(), args.options, {"gradient_method"});
  tools::addOptionFlags(app, argumentTable(), args, {"agents_markdown"});
  app.footer(agentList(registry));
  return tools::parseAndRun(app, argc, argv, [&] { return run(args, registry); });
}
