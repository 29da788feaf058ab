// occlusion_bridge_calibration: chooses the camera bridge's stopping rule on validation scenes.
// Behind the bridge no simulator says when the view is clear: the bridge ends an episode when the
// network's estimated occlusion falls to ~occlusion_threshold pixels or fewer. This tool runs an
// agent on simulated scenes without the truth's stop, estimates the occlusion of every view as
// the bridge does, and prints for each candidate threshold how often the episode would have
// stopped on a view that is truly clear, stopped too early, or run to the step limit. With
// --second-model, as the bridge's ~second_model: each view's estimate is the union of both maps.
//   occlusion_bridge_calibration --scenes 50 --thresholds 0,16,64,256
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/workers.hpp"
#include "occlusion_env/env/camera_environment.hpp"
#include "occlusion_env/env/environment.hpp"
#include "occlusion_env/env/episode_rule.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/learning/learned_agents.hpp"
#include "occlusion_env/learning/occlusion_estimator.hpp"
#include "occlusion_env/render/depth_encoding.hpp"
#include "occlusion_env/tools/cli_options.hpp"

namespace {

using occlusion_env::OptionSpec;
using occlusion_env::OptionTable;

const occlusion_env::CameraEnvironmentOptions kBridge;  // the camera bridge's defaults

/// The tool's own options; the scenes' come from environmentOptionTable().
struct Arguments {
  occlusion_env::EnvironmentOptions options;
  std::string agent = "predicted_escape";
  std::string model;         // the shipped network for depth cameras unless given
  std::string agent_model;   // "": the estimate's network
  std::string second_model;  // "": no second opinion (the bridge's ~second_model)
  double second_probability = kBridge.second_occlusion_probability;
  int scenes = 50;
  long long first_seed = 900000;
  // The candidates start with the bridge's default rule (CameraEnvironmentOptions).
  std::vector<double> thresholds = {static_cast<double>(kBridge.occlusion_threshold_px), 16, 64};
  std::vector<double> probabilities = {kBridge.occlusion_probability, 0.1, 0.2};
  std::vector<double> confirm_views = {3, 4, static_cast<double>(kBridge.confirm_views)};
  bool millimetre_depth = false;
  bool clear_bounding_surfaces = kBridge.clear_bounding_surfaces;
  int size = 256;
  std::string views_csv;  // "": no file
  int threads = 2;        // workers, one environment, agent and networks each

  Arguments() : model(occlusion_env::learning::bridgeModelPath()) {
    options.catalog.source = "sweethome3d";
    options.scene.categories = {"chair", "table"};
    options.scene.model_split = occlusion_env::ModelSplit::kTrain;
  }
};

const OptionTable<Arguments>& argumentTable() {
  static const auto table =
      OptionTable<Arguments>()
          .add("agent", &Arguments::agent, OptionSpec("the agent that moves"))
          .add("model", &Arguments::model,
               OptionSpec("the network for the estimate, and the agent's model if it needs one "
                          "and --agent-model is not given"))
          .add("agent_model", &Arguments::agent_model,
               OptionSpec("the agent's network, if another than the estimate's (as the camera "
                          "bridge's and the agent node's in bridge_evaluation.launch)"))
          .add("second_model", &Arguments::second_model,
               OptionSpec("a second network whose map joins the estimate's at "
                          "--second-probability, as the bridge's ~second_model: a view counts as "
                          "clear only where both see none (\"\": none)"))
          .add("second_probability", &Arguments::second_probability,
               OptionSpec("with --second-model: its map's ~second_occlusion_probability; the "
                          "candidate probabilities are the first network's")
                   .range(1e-6, 1.0 - 1e-6))
          .add("scenes", &Arguments::scenes, OptionSpec("number of scenes").range(1, 100000))
          .add("first_seed", &Arguments::first_seed,
               OptionSpec("the first seed (validation range 900,000-999,999)").range(0, 999999))
          .add("thresholds", &Arguments::thresholds,
               OptionSpec("candidate ~occlusion_threshold values at the image's resolution")
                   .unit("px")
                   .range(0, 1e9))
          .add("probabilities", &Arguments::probabilities,
               OptionSpec("candidate ~occlusion_probability values").range(1e-6, 1.0 - 1e-6))
          .add("confirm_views", &Arguments::confirm_views,
               OptionSpec("candidate ~confirm_views values: the estimate must be at or below the "
                          "threshold on this many views in a row")
                   .range(1, 1000))
          .add("millimetre_depth", &Arguments::millimetre_depth,
               OptionSpec("round depth to millimetres first, as 16UC1 drivers send it"))
          .add("clear_bounding_surfaces", &Arguments::clear_bounding_surfaces,
               OptionSpec("clear estimated occlusion on a floor or wall (the bridge's "
                          "~clear_bounding_surfaces)"))
          .add("size", &Arguments::size,
               OptionSpec("image width and height").unit("px").range(64, 1024))
          .add("threads", &Arguments::threads,
               OptionSpec("worker threads, one environment, agent and networks each; the "
                          "output is the same as with 1")
                   .range(1, 64))
          .add("views_csv", &Arguments::views_csv,
               OptionSpec("also write every view (seed, step, the true occlusion and the "
                          "estimate at each probability, in px; with --second-model the "
                          "union's) to this CSV file, to study other stopping rules"));
  return table;
}

/// Thresholds are chosen on validation scenes, never on test scenes.
void checkSeeds(const Arguments& args) {
  if (args.first_seed + args.scenes > static_cast<long long>(occlusion_env::kFirstTestSeed)) {
    throw CLI::ValidationError(
        "seeds " + std::to_string(args.first_seed) + ".." +
        std::to_string(args.first_seed + args.scenes - 1) +
        " reach the test range (>= 1,000,000): choose thresholds on validation scenes");
  }
}

/// `value` with one decimal, leaving std::cout's format as it was (a probability such as 0.15
/// printed after it must keep its digits).
std::string oneDecimal(double value) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << value;
  return text.str();
}

// One view of an episode: the truth and the estimate at each probability threshold.
struct View {
  std::int64_t true_pixels = 0;
  std::vector<std::int64_t> estimated_pixels;  // per Arguments::probabilities
};

// Where the bridge's rule (env/episode_rule.hpp, as the bridge sets it) stops on `path`: the
// step whose view is the confirm-th in a row estimated at most `threshold` (the start view never
// counts); path.size() when it never does.
std::size_t stopOf(const std::vector<View>& path, std::size_t probability, double threshold,
                   int confirm) {
  occlusion_env::CameraEnvironmentOptions bridge;
  bridge.occlusion_threshold_px = static_cast<std::int64_t>(std::floor(threshold));
  bridge.confirm_views = confirm;
  bridge.max_steps = std::max<int>(1, static_cast<int>(path.size()) - 1);
  occlusion_env::EpisodeRule rule(bridge.rule());
  occlusion_env::OcclusionStats start;
  start.total_pixels = path.front().estimated_pixels[probability];
  rule.start(start);
  for (std::size_t t = 1; t < path.size(); ++t) {
    if (rule.step(path[t].estimated_pixels[probability]).terminated) return t;
  }
  return path.size();
}

// What the workers share: each scene's path is written to its own slot.
struct Collection {
  explicit Collection(const Arguments& args) : args(args), views(args.scenes) {}
  const Arguments& args;
  std::vector<std::vector<View>> views;  // [scene][t]
  std::mutex mutex;                      // guards done and the progress line
  int done = 0;
};

// One worker: its own environment, agent and networks; the scenes `jobs` gives it.
void collectPaths(Collection& run, occlusion_env::JobSource& jobs) {
  using namespace occlusion_env;
  const Arguments& args = run.args;
  const AgentRegistry registry = learning::learningAgents();
  EnvironmentOptions options = args.options;
  options.width = options.height = args.size;
  Environment environment(options);
  const std::unique_ptr<Agent> agent = registry.make(
      args.agent, {environment, args.agent_model.empty() ? args.model : args.agent_model});
  const auto model = std::make_shared<learning::LoadedModel>(learning::loadModel(args.model));
  std::optional<BoundingSurfaceOptions> surfaces;
  if (args.clear_bounding_surfaces) surfaces.emplace();
  // One pass of the network per view; each probability's count from its map.
  learning::OcclusionEstimator estimator(model, args.probabilities.front(), surfaces);
  // The second opinion's map at its one probability, joined to each of the first's.
  std::optional<learning::OcclusionEstimator> second;
  if (!args.second_model.empty()) {
    second.emplace(std::make_shared<learning::LoadedModel>(learning::loadModel(args.second_model)),
                   args.second_probability, surfaces);
  }
  cv::Mat mask, second_mask, depth_16u, depth_mm;
  while (const std::optional<std::size_t> scene = jobs.next()) {
    std::vector<View>& path = run.views[*scene];
    const std::uint64_t seed = static_cast<std::uint64_t>(args.first_seed) + *scene;
    ResetOptions reset;
    reset.start_azimuth_rad = 0.0;
    StepInfo info = environment.reset(seed, reset).info;
    agent->reset(seed);
    for (int t = 0;; ++t) {
      Observation observation = environment.observation();  // headers, no copy
      if (args.millimetre_depth) {
        // As a 16UC1 camera gives it, read back as metres.
        toMillimetreDepth(observation.depth, depth_16u);
        fromMillimetreDepth(depth_16u, depth_mm);
        observation.depth = depth_mm;
      }
      View view;
      view.true_pixels = info.occlusion.total_pixels;
      const double radius_m = learning::cameraRadius(info.world_from_optical);
      estimator.setCameraRadius(radius_m);
      estimator.estimate(observation.rgb, observation.depth, info.intrinsics, mask);
      if (second) {
        second->setCameraRadius(radius_m);
        second->estimate(observation.rgb, observation.depth, info.intrinsics, second_mask);
      }
      for (const double probability : args.probabilities) {
        view.estimated_pixels.push_back(second
                                            ? estimator.occludedPixelsAt(probability, second_mask)
                                            : estimator.occludedPixelsAt(probability));
      }
      path.push_back(view);
      if (t == options.max_steps) break;
      info = environment.moveOutsideEpisode(agent->act(rigObservationOf(observation, info)));
    }
    const std::lock_guard<std::mutex> lock(run.mutex);
    std::cerr << "\rscene " << ++run.done << "/" << args.scenes << std::flush;
  }
}

/// views[scene][t]: the start view, then one per step, always max_steps + 1 of them. Scenes run
/// on args.threads workers; each path depends only on its scene, so the result does not depend
/// on how many.
std::vector<std::vector<View>> collectViews(const Arguments& args) {
  Collection run(args);
  occlusion_env::learning::setInferenceThreadsForWorkers(args.threads);
  occlusion_env::runWorkers(args.threads, static_cast<std::size_t>(args.scenes),
                            [&run](occlusion_env::JobSource& jobs) { collectPaths(run, jobs); });
  std::cerr << "\n";
  return std::move(run.views);
}

/// What was run, and how far the agent's paths get without a stop.
void printHeader(const Arguments& args, const std::vector<std::vector<View>>& views) {
  using namespace occlusion_env;
  const int max_steps = args.options.max_steps;
  int reached = 0;              // scenes whose path passes a truly clear view
  double steps_to_clear = 0.0;  // to the first truly clear view; the limit where there is none
  for (const auto& path : views) {
    const auto clear = std::find_if(path.begin() + 1, path.end(),
                                    [](const View& v) { return v.true_pixels == 0; });
    reached += clear != path.end();
    steps_to_clear += clear != path.end() ? clear - path.begin() : max_steps;
  }
  std::cout << args.agent << " on " << args.scenes << " scenes (seeds " << args.first_seed << ".."
            << args.first_seed + args.scenes - 1 << ", " << args.options.catalog.source
            << ", split " << toString(args.options.scene.model_split) << ", " << args.size
            << " px, " << args.options.world.world << ", depth " << args.options.sensor.depth_sensor
            << (args.millimetre_depth ? ", depth in millimetres" : "") << "), " << max_steps
            << " steps at most\n"
            << "estimate: " << args.model << "\n";
  if (!args.second_model.empty()) {
    std::cout << "joined by: " << args.second_model << " at probability " << args.second_probability
              << " (a view's estimate: the pixels either network calls occluded)\n";
  }
  std::cout << "agent's network: " << (args.agent_model.empty() ? args.model : args.agent_model)
            << "\n"
            << "its path passes a truly clear view in " << reached << " of " << args.scenes
            << " scenes, after " << oneDecimal(steps_to_clear / args.scenes)
            << " steps on average (where the simulator stops)\n\n"
            << "| probability | threshold [px] | confirm views | stops on a clear view | stops "
               "too early (median true L there [px]) | never stops | mean steps to the stop |\n"
            << "|---:|---:|---:|---:|---:|---:|---:|\n";
}

/// One row of the table: the rule (probability p, threshold, confirm) on every path.
void printRule(const Arguments& args, const std::vector<std::vector<View>>& views, std::size_t p,
               double threshold, double confirm) {
  int clear = 0, never = 0;
  std::vector<std::int64_t> early_pixels;
  double steps = 0.0;
  for (const auto& path : views) {
    const std::size_t stop = stopOf(path, p, threshold, static_cast<int>(confirm));
    if (stop == path.size()) {
      ++never;
      steps += args.options.max_steps;
    } else if (path[stop].true_pixels == 0) {
      ++clear;
      steps += static_cast<double>(stop);
    } else {
      early_pixels.push_back(path[stop].true_pixels);
      steps += static_cast<double>(stop);
    }
  }
  std::sort(early_pixels.begin(), early_pixels.end());
  std::cout << "| " << args.probabilities[p] << " | " << static_cast<std::int64_t>(threshold)
            << " | " << confirm << " | " << clear << " | " << early_pixels.size();
  if (!early_pixels.empty()) std::cout << " (" << early_pixels[early_pixels.size() / 2] << ")";
  std::cout << " | " << never << " | " << oneDecimal(steps / args.scenes) << " |\n";
}

/// Every view of every path, one row each, for rules this tool does not print.
void writeViewsCsv(const Arguments& args, const std::vector<std::vector<View>>& views) {
  std::ofstream file(args.views_csv);
  if (!file) throw occlusion_env::InvalidArgumentError("cannot write " + args.views_csv);
  file << "seed,step,true_px";
  for (const double probability : args.probabilities) file << ",estimated_px_at_" << probability;
  file << "\n";
  for (std::size_t scene = 0; scene < views.size(); ++scene) {
    for (std::size_t t = 0; t < views[scene].size(); ++t) {
      file << args.first_seed + static_cast<long long>(scene) << "," << t << ","
           << views[scene][t].true_pixels;
      for (const std::int64_t pixels : views[scene][t].estimated_pixels) file << "," << pixels;
      file << "\n";
    }
  }
  if (!file) throw occlusion_env::InvalidArgumentError("cannot write " + args.views_csv);
}

int run(const Arguments& args) {
  const std::vector<std::vector<View>> views = collectViews(args);
  if (!args.views_csv.empty()) writeViewsCsv(args, views);
  printHeader(args, views);
  for (std::size_t p = 0; p < args.probabilities.size(); ++p) {
    for (const double threshold : args.thresholds) {
      for (const double confirm : args.confirm_views) printRule(args, views, p, threshold, confirm);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace occlusion_env;
  Arguments args;
  CLI::App app(
      "Runs an agent on validation scenes as it would run behind the camera bridge (the episode "
      "does not\nstop when the view is truly clear), estimates every view's occlusion with the "
      "network, and prints,\nfor each rule, what the bridge would do: stop when the estimate "
      "(pixels above the probability)\nhas been at most the threshold on the last confirm-views "
      "views. Seeds must lie below 1,000,000:\nthresholds are chosen on validation scenes, never "
      "on test scenes.",
      "occlusion_bridge_calibration");
  tools::addOptionFlags(app, argumentTable(), args,
                        {"agent", "model", "agent_model", "second_model", "second_probability",
                         "scenes", "first_seed"});
  tools::addOptionFlags(app, environmentOptionTable(), args.options, {"max_steps"});
  tools::addOptionFlags(app, argumentTable(), args,
                        {"thresholds", "probabilities", "confirm_views", "millimetre_depth",
                         "clear_bounding_surfaces", "views_csv"});
  tools::addOptionFlags(app, environmentOptionTable(), args.options,
                        {"catalog_source", "categories", "model_split", "world", "depth_sensor"});
  tools::addOptionFlags(app, argumentTable(), args, {"size", "threads"});
  app.callback([&app, &args] {
    checkSeeds(args);
    if (args.second_model.empty() && app.count("--second-probability") > 0) {
      throw CLI::ValidationError("--second-probability is the second model's: give --second-model");
    }
  });
  return tools::parseAndRun(app, argc, argv, [&args] { return run(args); });
}
