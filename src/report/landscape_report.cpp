#include "occlusion_env/report/landscape_report.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "occlusion_env/agents/episode_runner.hpp"
#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/common/text_file.hpp"
#include "occlusion_env/env/scene_set.hpp"
#include "occlusion_env/eval/landscape.hpp"

namespace occlusion_env {
namespace report {

namespace fs = std::filesystem;
using namespace eval;  // NOLINT

std::string runLandscape(const EvalOptions& cl, const std::string& scenes_path) {
  const SceneSet set = loadSceneSet(scenes_path);
  if (set.seeds.empty()) throw InvalidArgumentError(scenes_path + ": no seeds");
  const std::uint64_t seed = set.seeds.front();
  const int max_steps = cl.max_steps.value_or(50);
  Environment env(environmentOptionsFor(set));
  std::vector<EpisodeRecord> paths;
  EpisodeRunOptions run_options;
  run_options.max_steps = max_steps;
  for (const std::string& name :
       cl.agents.empty() ? agentRegistry().runnableByDefault() : cl.agents) {
    const std::unique_ptr<Agent> agent = agentRegistry().make(name, {env, cl.model});
    EpisodeRequest request;
    request.agent = name;
    request.scene_set = set.name;
    request.seed = seed;
    request.reset = resetOptionsFor(set);
    paths.push_back(runEpisode(env, *agent, request, run_options));
    if (!paths.back().completed()) throw std::runtime_error(name + ": " + paths.back().message);
  }
  env.reset(seed, resetOptionsFor(set));
  const LandscapeGrid grid = gridAround(paths, /*margin_rad=*/0.15, /*min_half_width_rad=*/0.6,
                                        /*spacing_rad=*/0.025, env.camera().lowestElevation(),
                                        env.camera().highestElevation());
  const std::string stem = set.name + "_landscape_" + std::to_string(seed);
  const std::string landscape_csv = (fs::path(cl.out) / (stem + ".csv")).string();
  const std::string paths_csv = (fs::path(cl.out) / (stem + "_paths.csv")).string();
  std::cerr << "occlusion_eval: occlusion landscape of scene " << seed << "...\n";
  const int poses = writeOcclusionLandscapeCsv(env, grid, landscape_csv);
  writeEpisodePathsCsv(paths, paths_csv);
  std::cerr << "occlusion_eval: wrote " << landscape_csv << " (" << poses << " views)\n";
  runPlots(cl, {"--landscape", landscape_csv, "--paths", paths_csv});

  std::ostringstream md;
  md << "## One scene from above: occlusion over the camera angles\n\n"
     << "Scene " << seed << " of `" << set.name << "`: the total occlusion L [px] seen from "
     << poses << " camera poses on a " << grid.spacing_rad
     << " rad grid around the start view (dark: none; the cyan line is the border between occluded "
        "and "
        "unoccluded views, L = 0 being the goal), and the path each agent took from the start "
        "(circle) to its last "
        "view (star: unoccluded; cross: still occluded after "
     << max_steps << " steps).";
  for (const EpisodeRecord& path : paths) {
    md << " " << path.agent << ": " << path.steps << " steps, "
       << (path.success() ? "unoccluded." : "failed.");
  }
  md << "\n\n";
  if (cl.plots) md << "![occlusion landscape](" << stem << ".png)\n";
  return md.str();
}

void writeLandscapeReport(const EvalOptions& options) {
  const std::string markdown = runLandscape(options, options.landscape);
  writeTextFile((fs::path(options.out) / "landscape.md").string(), markdown);
}

}  // namespace report
}  // namespace occlusion_env
