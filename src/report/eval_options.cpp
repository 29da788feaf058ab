// The one translation unit of the report library that sees libtorch (the learned agents).
#include "occlusion_env/report/eval_options.hpp"

#include "occlusion_env/env/scene_setup.hpp"

#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/package_paths.hpp"
#include "occlusion_env/eval/subprocess.hpp"
#include "occlusion_env/eval/sweep.hpp"
#include "occlusion_env/learning/learned_agents.hpp"

namespace occlusion_env {
namespace report {

namespace {

// `help` with the allowed range and unit of the camera bridge's option `bridge_key`, so that a
// --bridge-* flag accepts what the bridge does.
OptionSpec bridgeSpec(const std::string& bridge_key, const std::string& help) {
  const auto* field = cameraEnvironmentOptionTable().find(bridge_key);
  if (field == nullptr) throw std::logic_error("the bridge has no option " + bridge_key);
  const OptionSpec& bridge = field->spec;
  OptionSpec spec(help);
  if (!bridge.unit().empty()) spec.unit(bridge.unit());
  if (bridge.minimum()) {
    bridge.openMinimum() ? spec.above(*bridge.minimum()) : spec.atLeast(*bridge.minimum());
  }
  if (bridge.maximum()) {
    bridge.openMaximum() ? spec.below(*bridge.maximum()) : spec.atMost(*bridge.maximum());
  }
  return spec;
}

void addModes(OptionTable<EvalOptions>& table) {
  using O = EvalOptions;
  table
      .add("scenes", &O::scenes,
           OptionSpec("mode: run the agents on the scene set of this file (config/scenes/*.yaml)"))
      .add("sweep", &O::sweep,
           OptionSpec("mode: start-azimuth sweep of this preset, two_chairs or two_tables "
                      "(Figure 5)"))
      .add("summarize", &O::summarize,
           OptionSpec("mode: summary and plots from this episode CSV of an earlier run"))
      .add("landscape", &O::landscape,
           OptionSpec("mode: occlusion L over the camera angles of this set's first scene, with "
                      "each agent's path on it (CSV and plot)"))
      .add("strip", &O::strip,
           OptionSpec("mode: frames of one episode of each agent (default gradient, "
                      "predicted_escape) on a scene of this set, side by side (PNG): the first "
                      "scene where the first agent fails and the last succeeds, else the first"))
      .add("networks", &O::networks,
           OptionSpec("mode: print the Table 3 layout (doc/training/*.json and models/*.json "
                      "beside the paper's rows) and exit"))
      .add("all", &O::all,
           OptionSpec("mode: the held-out scene sets (config/scenes/test_*.yaml) and both sweeps, "
                      "on the embedded scene and on Sweet Home 3D models, and the report"));
}

void addRunOptions(OptionTable<EvalOptions>& table) {
  using O = EvalOptions;
  table
      .add("agents", &O::agents,
           OptionSpec("agents by name (empty: every agent of the registry that runs without a "
                      "model path, the oracle included)"))
      .add("max_steps", &O::max_steps,
           OptionSpec("step limit per episode (unset: 50; 2000 for --sweep)").range(1, 1000000))
      .add("limit", &O::limit, OptionSpec("only the first N scenes of the set").range(1, 1000000))
      .add("threads", &O::threads,
           OptionSpec("episodes run at once, each worker with its own simulator (GL context), "
                      "networks and agent; the results and their order are the same as with 1")
               .range(1, 64))
      .add("sweep_source", &O::sweep_source,
           OptionSpec("object source of the sweep's preset scenes")
               .choices({"embedded", "sweethome3d", "folder"}))
      .add("sweep_models", &O::sweep_models,
           OptionSpec("models (one scene seed each) per sweep (unset: 1 for embedded, 6 for "
                      "other sources)")
               .range(1, eval::kSweepSeedSearch))
      .add("model", &O::model,
           OptionSpec("the model of the agents that need one (\"\": each one's shipped model)"))
      .add("through_bridge", &O::through_bridge,
           OptionSpec("with --scenes: \"\" runs on the simulator; else through the camera "
                      "bridge's logic in front of it (doc/CAMERA_BRIDGE.md), this network model "
                      "estimating the occlusion, the simulator's truth scoring where each episode "
                      "ended (OUT/<set>_bridge_*)"))
      .add(
          "bridge_clear_surfaces", [](O& o) -> bool& { return o.bridge.clear_bounding_surfaces; },
          bridgeSpec("clear_bounding_surfaces",
                     "with --through-bridge: the bridge clears estimated occlusion on a floor "
                     "or wall (its ~clear_bounding_surfaces)"))
      .add(
          "bridge_probability", [](O& o) -> double& { return o.bridge.occlusion_probability; },
          bridgeSpec("occlusion_probability",
                     "with --through-bridge: a pixel counts as occluded above this probability "
                     "(the bridge's ~occlusion_probability, chosen for its own network; 0.1 "
                     "was the camera model's)"))
      .add("bridge_second_model", &O::bridge_second_model,
           OptionSpec("with --through-bridge: \"\" none; else a second network whose estimate "
                      "joins the first's, a view clear only where both see no occlusion (the "
                      "bridge's ~second_model)"))
      .add(
          "bridge_second_probability",
          [](O& o) -> double& { return o.bridge.second_occlusion_probability; },
          bridgeSpec("second_occlusion_probability",
                     "with --bridge-second-model: a pixel of its map counts as occluded above "
                     "this probability (the bridge's ~second_occlusion_probability)"))
      .add(
          "bridge_threshold", [](O& o) -> std::int64_t& { return o.bridge.occlusion_threshold_px; },
          bridgeSpec("occlusion_threshold",
                     "with --through-bridge: a view counts as clear at or below this many "
                     "estimated pixels (the bridge's ~occlusion_threshold)"))
      .add(
          "bridge_confirm_views", [](O& o) -> int& { return o.bridge.confirm_views; },
          bridgeSpec("confirm_views",
                     "with --through-bridge: this many clear step views in a row end an episode "
                     "(the bridge's ~confirm_views)"));
  addSceneRandomizationOptions(table, &O::world, &O::depth_sensor, &O::randomize,
                               "with --scenes: ");
  addCameraRandomizationRanges(
      table, [](O& o) -> CameraRandomization& { return o.camera_ranges; }, "with --randomize: ");
}

void addOutputOptions(OptionTable<EvalOptions>& table) {
  using O = EvalOptions;
  table.add("out", &O::out, OptionSpec("output folder"))
      .add(
          "best_seed", [](O& o) -> std::uint64_t& { return o.best.seed; },
          OptionSpec("seed of the BEST chains"))
      .add(
          "best_samples", [](O& o) -> int& { return o.best.samples_per_chain; },
          OptionSpec("kept MCMC samples per chain (3 chains)").range(1, 100000000))
      .add("plots", &O::plots, OptionSpec("the PNG plots").negatedFlag("--no-plots"))
      .add("plot_script", &O::plot_script,
           OptionSpec("the plot script (\"\": scripts/plot_evaluation.py of --source-dir)"))
      .add("source_dir", &O::source_dir,
           OptionSpec("where config/scenes, models and scripts are (\"\": the package's share "
                      "directory, the source tree in a devel space; doc/INSTALL.md)"))
      .add("report", &O::report,
           OptionSpec("with --all: the evaluation report's file, its links pointing into --out "
                      "(\"\": EVALUATION.md in --out)"));
}

OptionTable<EvalOptions> makeEvalTable() {
  OptionTable<EvalOptions> table;
  addModes(table);
  addRunOptions(table);
  addOutputOptions(table);
  return table;
}

}  // namespace

const OptionTable<EvalOptions>& evalOptionTable() {
  static const OptionTable<EvalOptions> table = makeEvalTable();
  return table;
}

void EvalOptions::resolve() {
  evalOptionTable().check(*this);
  const int modes = !scenes.empty() + !sweep.empty() + !summarize.empty() + !landscape.empty() +
                    !strip.empty() + networks + all;
  if (modes != 1) {
    throw InvalidArgumentError(
        "give exactly one of --scenes, --sweep, --summarize, --landscape, --strip, --networks, "
        "--all");
  }
  if (!report.empty() && !all) throw InvalidArgumentError("--report needs --all");
  if ((world || depth_sensor || randomize) && scenes.empty()) {
    throw InvalidArgumentError("--world, --depth-sensor and --randomize need --scenes");
  }
  requireCameraRangesDrawn(camera_ranges, randomize);
  if (!through_bridge.empty() && scenes.empty()) {
    throw InvalidArgumentError("--through-bridge needs --scenes");
  }
  if (!bridge_second_model.empty() && through_bridge.empty()) {
    throw InvalidArgumentError("--bridge-second-model needs --through-bridge");
  }
  if (source_dir.empty()) source_dir = packageShareDirectory();
  if (plot_script.empty()) plot_script = source_dir + "/scripts/plot_evaluation.py";
}

void EvalOptions::applySceneRandomization(EnvironmentOptions& environment) const {
  occlusion_env::applySceneRandomization(environment, world, depth_sensor, randomize);
  if (randomize) {  // the camera's ranges as asked, drawn
    environment.camera_randomization = camera_ranges;
    environment.camera_randomization.enabled = true;
  }
}

const AgentRegistry& agentRegistry() {
  static const AgentRegistry agents = learning::learningAgents();
  return agents;
}

void runPlots(const EvalOptions& cl, std::vector<std::string> plot_args) {
  if (!cl.plots) return;
  std::vector<std::string> argv = {"/usr/bin/python3", cl.plot_script, "--out", cl.out};
  argv.insert(argv.end(), plot_args.begin(), plot_args.end());
  const int status = eval::runProgram(argv, "", "");
  if (status != 0) {
    std::cerr << "occlusion_eval: plotting failed (status " << status
              << "); is python3-matplotlib installed? (scripts/install_deps.sh)\n";
  }
}

}  // namespace report
}  // namespace occlusion_env
