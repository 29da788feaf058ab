// occlusion_agents: runs agents of the registry on N seeded scenes, in process, and prints the
// steps each needs to an unoccluded view (the paper's Table 4 protocol).
//   occlusion_agents --scenes 50
//   occlusion_agents --scenes 50 --source sweethome3d --category chair --category table
//   occlusion_agents --agents predicted_escape --through-bridge models/multitask_unet64.pt
//       (through the camera bridge's logic in front of the simulator: doc/CAMERA_BRIDGE.md)
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "occlusion_env/agents/core_agents.hpp"
#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/simulated_camera_rig.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/occlusion_estimator.hpp"
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
  // Through the camera bridge's logic (env/camera_environment.hpp) in front of the simulator.
  std::string through_bridge;  // "": directly; else the bridge's network model
  occlusion_env::CameraEnvironmentOptions bridge;
  bool millimetre_depth = false;
};

const OptionTable<Arguments>& argumentTable() {
  static const auto table =
      OptionTable<Arguments>()
          .add("agents", &Arguments::agents,
               OptionSpec("agents by name (empty: every competing agent; listed below)"))
          .add("scenes", &Arguments::scenes,
               OptionSpec("number of scenes, seeds first-seed .. first-seed + N - 1")
                   .range(1, 1000000))
          .add("first_seed", &Arguments::first_seed,
               OptionSpec("the first seed (test scenes: from 1000000 on)").range(0, 2000000000))
          .add("model", &Arguments::model,
               OptionSpec("model file for the agents that need one (\"\": each one's shipped "
                          "model)"))
          .add("size", &Arguments::size,
               OptionSpec("image width and height").unit("px").range(64, 1024))
          .add("through_bridge", &Arguments::through_bridge,
               OptionSpec("\"\": run on the simulator; else run through the camera bridge's "
                          "logic in front of it, this network model estimating the occlusion "
                          "(the simulator's truth scores where each episode ended)"))
          .add("millimetre_depth", &Arguments::millimetre_depth,
               OptionSpec("with --through-bridge: depth rounded to millimetres, as 16UC1 "
                          "cameras send it"))
          .add(
              "agents_markdown", &Arguments::agents_markdown,
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
    if (entry.needs.privileged_observation) needs += "the simulator's masks and true occlusion; ";
    if (entry.needs.model_file) needs += "a model file; ";
    needs = needs.empty() ? "RGB-D only" : needs.substr(0, needs.size() - 2);
    std::cout << "| `" << entry.name << "` | " << entry.summary << " | " << needs << " | "
              << (entry.paper_label.empty() ? "-" : entry.paper_label) << " |\n";
  }
}

/// Where an episode through the bridge ended, by the simulator's truth.
struct Truth {
  std::int64_t occlusion_px = 0;
  bool clear = false;
};

/// The simulator, and with --through-bridge the bridge's logic in front of it: what the agents
/// run on.
class Environments {
 public:
  explicit Environments(const Arguments& args) : simulator_(simulatorOptions(args)) {
    if (args.through_bridge.empty()) return;
    // The estimate reads depth at the sphere the bridge will work on (the simulator's).
    occlusion_env::CameraEnvironmentOptions bridge = args.bridge;
    bridge.radius_m = occlusion_env::BridgedSimulator::sphereRadius(simulator_.options());
    estimator_ = occlusion_env::learning::makeBridgeEstimator(
        std::make_shared<occlusion_env::learning::LoadedModel>(
            occlusion_env::learning::loadModel(args.through_bridge)),
        bridge);
    bridged_ = std::make_unique<occlusion_env::BridgedSimulator>(
        simulator_, args.bridge, estimator_.get(), args.millimetre_depth);
  }

  /// What the agents act on.
  occlusion_env::EnvironmentInterface& agentsEnvironment() {
    return bridged_ ? static_cast<occlusion_env::EnvironmentInterface&>(bridged_->bridge())
                    : simulator_;
  }
  bool throughBridge() const { return bridged_ != nullptr; }
  Truth truth() const { return {bridged_->trueOcclusion(), bridged_->trulyClear()}; }

 private:
  static occlusion_env::EnvironmentOptions simulatorOptions(const Arguments& args) {
    occlusion_env::EnvironmentOptions options = args.options;
    options.width = options.height = args.size;
    return options;
  }

  occlusion_env::Environment simulator_;
  std::unique_ptr<occlusion_env::ViewOcclusionEstimator> estimator_;
  std::unique_ptr<occlusion_env::BridgedSimulator> bridged_;
};

/// Every agent's episodes on every scene, [agent][scene]; with the bridge, the truth where each
/// ended in `truths` ([agent][scene]).
std::vector<std::vector<occlusion_env::EpisodeRecord>> runEpisodes(
    const Arguments& args, const occlusion_env::AgentRegistry& registry,
    const std::vector<std::string>& names, std::vector<std::vector<Truth>>& truths) {
  using namespace occlusion_env;
  Environments environments(args);
  EnvironmentInterface& environment = environments.agentsEnvironment();
  std::vector<std::unique_ptr<Agent>> agents;
  for (const std::string& name : names) {
    agents.push_back(registry.make(name, {environment, args.model}));
  }
  std::vector<std::vector<EpisodeRecord>> episodes(names.size());
  truths.assign(names.size(), {});
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
      if (environments.throughBridge()) truths[a].push_back(environments.truth());
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "\rscene " << scene + 1 << "/" << args.scenes << ", " << std::fixed
              << std::setprecision(1) << elapsed << " s" << std::flush;
  }
  std::cerr << "\n";
  return episodes;
}

/// Through the bridge: how often the agent ended truly clear, and the bridge's verdict agreed.
void printBridgeTable(const std::vector<std::string>& names,
                      const std::vector<std::vector<occlusion_env::EpisodeRecord>>& episodes,
                      const std::vector<std::vector<Truth>>& truths) {
  std::cout << "through the bridge: agent, bridge says clear, truly clear (simulator), verdict "
               "agrees, mean steps\n";
  for (std::size_t a = 0; a < names.size(); ++a) {
    int said_clear = 0, truly_clear = 0, agree = 0, steps = 0;
    for (std::size_t e = 0; e < episodes[a].size(); ++e) {
      said_clear += episodes[a][e].success();
      truly_clear += truths[a][e].clear;
      agree += episodes[a][e].success() == truths[a][e].clear;
      steps += episodes[a][e].steps;
    }
    const int n = static_cast<int>(episodes[a].size());
    std::cout << names[a] << "  " << said_clear << "/" << n << "  " << truly_clear << "/" << n
              << "  " << agree << "/" << n << "  " << std::fixed << std::setprecision(1)
              << static_cast<double>(steps) / std::max(1, n) << "\n";
    for (std::size_t e = 0; e < episodes[a].size(); ++e) {
      const occlusion_env::EpisodeRecord& record = episodes[a][e];
      std::cout << "  seed " << record.scene_seed << ": bridge says "
                << (record.success() ? "clear" : "occluded") << " after " << record.steps
                << " steps, truth " << truths[a][e].occlusion_px << " px\n";
    }
  }
}

int run(const Arguments& args, const occlusion_env::AgentRegistry& registry) {
  using namespace occlusion_env;
  if (args.agents_markdown) {
    printAgentsMarkdown(registry);
    return 0;
  }
  const std::vector<std::string> names = args.agents.empty() ? registry.competitors() : args.agents;
  std::vector<std::vector<Truth>> truths;
  const std::vector<std::vector<EpisodeRecord>> episodes =
      runEpisodes(args, registry, names, truths);
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
  if (!args.through_bridge.empty()) printBridgeTable(names, episodes, truths);
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
  tools::addOptionFlags(app, environmentOptionTable(), args.options,
                        {"gradient_method", "world", "depth_sensor"});
  // With --through-bridge: the bridge's own options (its parameters' names and ranges).
  tools::addOptionFlags(app, argumentTable(), args, {"through_bridge", "millimetre_depth"});
  tools::addOptionFlags(app, occlusion_env::cameraEnvironmentOptionTable(), args.bridge,
                        {"confirm_views", "occlusion_probability", "clear_bounding_surfaces"});
  tools::addOptionFlags(app, argumentTable(), args, {"agents_markdown"});
  app.footer(agentList(registry));
  return tools::parseAndRun(app, argc, argv, [&] { return run(args, registry); });
}
